#include "traversability/layered_mesh.h"

#include <cmath>

namespace terramesh::traversability {

std::vector<float> LayeredMesh::vertexCost() const {
  std::vector<float> cost(mesh.vertices.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const FaceLayers& face = layers[f];
    if (face.face_class == FaceClass::kUnknown) continue;
    const float c = face.face_class == FaceClass::kLethal ? 1.0f : face.cost;
    for (std::uint32_t v : mesh.faces[f]) {
      if (std::isnan(cost[v]) || c > cost[v]) cost[v] = c;
    }
  }
  return cost;
}

std::vector<FaceClass> LayeredMesh::vertexClass() const {
  std::vector<FaceClass> result(mesh.vertices.size(), FaceClass::kUnknown);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const FaceClass c = layers[f].face_class;
    // Lethal before uncertain before free before unknown.
    const auto rank = [](FaceClass k) {
      return k == FaceClass::kLethal ? 3 : k == FaceClass::kUncertain ? 2 : k == FaceClass::kFree ? 1 : 0;
    };
    for (std::uint32_t v : mesh.faces[f]) {
      if (rank(c) > rank(result[v])) result[v] = c;
    }
  }
  return result;
}

}  // namespace terramesh::traversability
