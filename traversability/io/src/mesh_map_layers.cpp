// The per-vertex layers of traversability.h5, under the names mesh_navigation's mesh_map layer
// plugins read, and terramesh's own beside them (docs/mesh_navigation.md).
#include <cmath>
#include <limits>
#include <unordered_map>

#include "export_writers.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability::internal {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kDegToRad = static_cast<float>(M_PI / 180.0);
using Worst = LayeredMesh::Worst;

/// mesh_map's layers take +inf where a value is missing (their defaultValue()): never NaN, so
/// that no comparison with a threshold or cost limit can pass a vertex without data.
std::vector<float> noDataWorst(std::vector<float> values) {
  for (float& x : values) {
    if (std::isnan(x)) x = kInf;
  }
  return values;
}

/// Free height above each vertex for mesh_map's ClearanceLayer: the lowest of its faces, where a
/// face whose clearance is unknown (NaN: the first face above is closing geometry) counts 0, as
/// does a vertex without faces; +inf = nothing above.
std::vector<float> clearanceLayer(const LayeredMesh& map) {
  std::vector<float> clearance = map.vertexWorst(
      [](const FaceLayers& face) { return std::isnan(face.clearance_m) ? 0.0f : face.clearance_m; }, Worst::kLowest);
  for (float& x : clearance) {
    if (std::isnan(x)) x = 0.0f;
  }
  return clearance;
}

std::vector<float> flag(const std::vector<FaceClass>& classes, FaceClass which) {
  std::vector<float> result(classes.size());
  for (std::size_t v = 0; v < classes.size(); ++v) result[v] = classes[v] == which ? 1.0f : 0.0f;
  return result;
}

/// 1 on the border of what is known: vertices of unknown faces, of open boundary edges (one face)
/// and vertices without faces; 0 elsewhere.
std::vector<float> borderLayer(const LayeredMesh& map) {
  std::vector<float> border = map.vertexWorst([](const FaceLayers& face) {
    return face.face_class == FaceClass::kUnknown ? 1.0f : 0.0f;
  });
  std::unordered_map<std::uint64_t, std::uint32_t> edge_faces;
  edge_faces.reserve(map.mesh.faces.size() * 2);
  const auto key = [](std::uint32_t a, std::uint32_t b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (const auto& face : map.mesh.faces) {
    for (int k = 0; k < 3; ++k) ++edge_faces[key(face[k], face[(k + 1) % 3])];
  }
  for (const auto& [edge, faces] : edge_faces) {
    if (faces != 1) continue;
    border[edge >> 32] = 1.0f;
    border[edge & 0xffffffffu] = 1.0f;
  }
  for (float& x : border) {
    if (std::isnan(x)) x = 1.0f;
  }
  return border;
}

}  // namespace

std::vector<VertexLayer> meshMapVertexLayers(const LayeredMesh& map, const RobotProfile& profile) {
  const std::vector<FaceClass> classes = map.vertexClass();
  const std::vector<float> vertex_cost = map.vertexCost();
  const std::size_t n = classes.size();
  std::vector<float> cost(n), cost_allow_uncertain(n), inflation(n);
  const std::vector<float> lethal_distance =
      map.vertexWorst([](const FaceLayers& face) { return face.lethal_distance_m; }, Worst::kLowest);
  for (std::size_t v = 0; v < n; ++v) {
    const bool drivable = classes[v] == FaceClass::kFree || classes[v] == FaceClass::kUncertain;
    cost_allow_uncertain[v] = drivable ? vertex_cost[v] : kInf;
    cost[v] = classes[v] == FaceClass::kFree ? vertex_cost[v] : kInf;
    inflation[v] = classes[v] == FaceClass::kLethal ? kInf : static_cast<float>(profile.inflationTerm(lethal_distance[v]));
  }
  std::vector<VertexLayer> layers;
  layers.push_back({"height_diff", noDataWorst(map.vertexWorst([](const FaceLayers& f) { return f.step_m; }))});
  layers.push_back({"roughness", noDataWorst(map.vertexWorst([](const FaceLayers& f) { return f.roughness_m; }))});
  layers.push_back({"steepness", noDataWorst(map.vertexWorst([](const FaceLayers& f) { return f.slope_deg * kDegToRad; }))});
  layers.push_back({"border", borderLayer(map)});
  layers.push_back({"clearance", clearanceLayer(map)});
  layers.push_back({"inflation", std::move(inflation)});
  layers.push_back({"cost", std::move(cost)});
  layers.push_back({"cost_allow_uncertain", std::move(cost_allow_uncertain)});
  layers.push_back({"lethal", flag(classes, FaceClass::kLethal)});
  layers.push_back({"uncertain", flag(classes, FaceClass::kUncertain)});
  layers.push_back({"unknown", flag(classes, FaceClass::kUnknown)});
  // terramesh's own per-vertex layers: the registry's, each by its per-vertex rule.
  for (const LayerInfo& layer : faceLayerRegistry()) {
    if (!layer.in_mesh_map) continue;
    layers.push_back(
        {layer.name,
         map.vertexWorst([&layer](const FaceLayers& f) { return static_cast<float>(layer.get(f)); }, layer.worst)});
  }
  return layers;
}

}  // namespace terramesh::traversability::internal
