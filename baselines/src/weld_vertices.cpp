#include "baselines/weld_vertices.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace terramesh::baselines {

mesher::TriangleMesh weldVertices(const mesher::TriangleMesh& mesh, double tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) {
    throw std::invalid_argument("weldVertices: tolerance " + std::to_string(tolerance) + " (expected >= 0)");
  }
  struct KeyHash {
    std::size_t operator()(const std::array<double, 3>& k) const noexcept {
      std::size_t h = 0;
      for (const double c : k) h = h * 1000003u ^ std::hash<double>{}(c);
      return h;
    }
  };
  const bool flags = mesh.is_steiner.size() == mesh.vertices.size();
  std::unordered_map<std::array<double, 3>, std::uint32_t, KeyHash> index;
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  mesher::TriangleMesh welded;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Eigen::Vector3d& p = mesh.vertices[v];
    const std::array<double, 3> key =
        tolerance > 0 ? std::array<double, 3>{std::round(p.x() / tolerance), std::round(p.y() / tolerance),
                                              std::round(p.z() / tolerance)}
                      : std::array<double, 3>{p.x(), p.y(), p.z()};
    const auto [it, inserted] = index.emplace(key, static_cast<std::uint32_t>(welded.vertices.size()));
    if (inserted) {
      welded.vertices.push_back(p);
      if (flags) welded.is_steiner.push_back(mesh.is_steiner[v]);
    } else if (flags && mesh.is_steiner[v]) {
      welded.is_steiner[it->second] = 1;
    }
    remap[v] = it->second;
  }
  for (const auto& f : mesh.faces) {
    const std::array<std::uint32_t, 3> g = {remap[f[0]], remap[f[1]], remap[f[2]]};
    if (g[0] == g[1] || g[1] == g[2] || g[0] == g[2]) continue;
    welded.faces.push_back(g);
  }
  return welded;
}

}  // namespace terramesh::baselines
