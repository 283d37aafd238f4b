#include "traversability/layered_mesh.h"

#include <cmath>

namespace terramesh::traversability {

std::vector<float> LayeredMesh::vertexWorst(const std::function<float(const FaceLayers&)>& value, Worst worst) const {
  std::vector<float> result(mesh.vertices.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const float x = value(layers[f]);
    if (std::isnan(x)) continue;
    for (std::uint32_t v : mesh.faces[f]) {
      if (std::isnan(result[v])) {
        result[v] = x;
      } else if (worst == Worst::kBitwiseOr) {
        result[v] = static_cast<float>(static_cast<std::uint32_t>(result[v]) | static_cast<std::uint32_t>(x));
      } else if (worst == Worst::kBitwiseAnd) {
        result[v] = static_cast<float>(static_cast<std::uint32_t>(result[v]) & static_cast<std::uint32_t>(x));
      } else if (worst == Worst::kHighest ? x > result[v] : x < result[v]) {
        result[v] = x;
      }
    }
  }
  return result;
}

std::vector<float> LayeredMesh::vertexCost() const {
  return vertexWorst([](const FaceLayers& face) {
    if (face.face_class == FaceClass::kUnknown) return std::numeric_limits<float>::quiet_NaN();
    return face.face_class == FaceClass::kLethal ? 1.0f : face.cost;
  });
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
