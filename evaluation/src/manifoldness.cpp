#include "evaluation/manifoldness.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace terramesh::evaluation {

namespace {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = i;
  }
  std::size_t find(std::size_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void join(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace

Manifoldness measureManifoldness(const mesher::TriangleMesh& mesh) {
  const mesher::MeshTopology topology = mesher::analyzeTopology(mesh);
  Manifoldness m;
  m.vertices = topology.vertices;
  m.faces = topology.faces;
  m.non_manifold_edges = topology.non_manifold_edges;
  m.non_manifold_vertices = topology.non_manifold_vertices;
  m.boundary_edges = topology.boundary_edges;
  m.components = topology.components;
  m.orientation_errors = topology.orientation_errors;

  const std::size_t n = mesh.vertices.size();
  UnionFind component(n);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_faces;
  std::vector<std::uint8_t> used(n, 0);
  for (const auto& f : mesh.faces) {
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = f[static_cast<std::size_t>(i)], b = f[static_cast<std::size_t>((i + 1) % 3)];
      edge_faces[{std::min(a, b), std::max(a, b)}] += 1;
      component.join(a, b);
      used[a] = 1;
    }
  }
  // Per component: V - E + F and the boundary loops (pieces of the boundary-edge graph).
  std::unordered_map<std::size_t, long> chi;
  std::unordered_map<std::size_t, long> loops;
  for (std::size_t v = 0; v < n; ++v) {
    if (used[v]) chi[component.find(v)] += 1;
  }
  for (const auto& f : mesh.faces) chi[component.find(f[0])] += 1;
  UnionFind boundary(n);
  std::vector<std::uint8_t> on_boundary(n, 0);
  for (const auto& [edge, count] : edge_faces) {
    chi[component.find(edge.first)] -= 1;
    if (count == 1) {
      boundary.join(edge.first, edge.second);
      on_boundary[edge.first] = on_boundary[edge.second] = 1;
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (on_boundary[v] && boundary.find(v) == v) {
      loops[component.find(v)] += 1;
      m.boundary_loops += 1;
    }
  }
  for (const auto& [root, euler] : chi) {
    const auto found = loops.find(root);
    const long b = found == loops.end() ? 0 : found->second;
    m.genus += (2 - euler - b) / 2;
  }
  return m;
}

}  // namespace terramesh::evaluation
