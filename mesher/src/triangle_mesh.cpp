#include <algorithm>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include "mesher/triangle_mesh.h"

namespace terramesh::mesher {
namespace {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

/// True when the faces around `vertex` (given as the opposite edges) form one connected fan.
bool isSingleFan(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& opposite_edges) {
  if (opposite_edges.size() <= 1) return true;
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> adjacency;
  for (const auto& [a, b] : opposite_edges) {
    adjacency[a].push_back(b);
    adjacency[b].push_back(a);
  }
  std::vector<std::uint32_t> stack{opposite_edges.front().first};
  std::unordered_map<std::uint32_t, bool> seen;
  while (!stack.empty()) {
    const std::uint32_t u = stack.back();
    stack.pop_back();
    if (seen[u]) continue;
    seen[u] = true;
    for (std::uint32_t w : adjacency[u]) {
      if (!seen[w]) stack.push_back(w);
    }
  }
  return seen.size() == adjacency.size();
}

}  // namespace

MeshTopology analyzeTopology(const TriangleMesh& mesh) {
  MeshTopology topology;
  topology.faces = mesh.faces.size();
  const std::size_t n = mesh.vertices.size();
  std::unordered_map<std::uint64_t, std::uint32_t> directed;
  std::unordered_map<std::uint64_t, std::uint32_t> undirected;
  directed.reserve(mesh.faces.size() * 3);
  undirected.reserve(mesh.faces.size() * 3 / 2);
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> fans(n);
  DisjointSets components(n);
  std::vector<bool> referenced(n, false);
  for (const auto& face : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      if (face[static_cast<std::size_t>(k)] >= n) {
        throw std::invalid_argument("analyzeTopology: face index out of range");
      }
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = face[static_cast<std::size_t>(k)];
      const std::uint32_t b = face[static_cast<std::size_t>((k + 1) % 3)];
      const std::uint32_t c = face[static_cast<std::size_t>((k + 2) % 3)];
      if (++directed[edgeKey(a, b)] == 2) ++topology.orientation_errors;
      ++undirected[edgeKey(std::min(a, b), std::max(a, b))];
      fans[a].emplace_back(b, c);
      referenced[a] = true;
      components.unite(a, b);
    }
  }
  topology.edges = undirected.size();
  for (const auto& [key, count] : undirected) {
    if (count == 1) ++topology.boundary_edges;
    if (count > 2) ++topology.non_manifold_edges;
  }
  std::map<std::size_t, long> chi_per_component;
  std::map<std::size_t, bool> open_component;
  for (std::size_t v = 0; v < n; ++v) {
    if (!referenced[v]) continue;
    ++topology.vertices;
    ++chi_per_component[components.find(v)];
    if (!isSingleFan(fans[v])) ++topology.non_manifold_vertices;
  }
  for (const auto& [key, count] : undirected) {
    const std::size_t root = components.find(static_cast<std::uint32_t>(key >> 32));
    --chi_per_component[root];
    if (count == 1) open_component[root] = true;
  }
  for (const auto& face : mesh.faces) ++chi_per_component[components.find(face[0])];
  topology.components = chi_per_component.size();
  topology.euler_characteristic = static_cast<long>(topology.vertices) -
                                  static_cast<long>(topology.edges) +
                                  static_cast<long>(topology.faces);
  for (const auto& [root, chi] : chi_per_component) {
    if (!open_component[root]) topology.total_genus += (2 - chi) / 2;
  }
  return topology;
}

TriangleMesh selectFaces(const TriangleMesh& mesh, const std::vector<std::uint8_t>& keep) {
  if (keep.size() != mesh.faces.size()) {
    throw std::invalid_argument("selectFaces: " + std::to_string(keep.size()) + " flags for " +
                                std::to_string(mesh.faces.size()) + " faces");
  }
  const bool steiner = mesh.is_steiner.size() == mesh.vertices.size();
  const bool keyed = mesh.vertex_keys.size() == mesh.vertices.size();
  const bool driven = mesh.driven_kind.size() == mesh.vertices.size();
  const bool observed = mesh.face_rays.size() == mesh.faces.size() && mesh.face_front_crossings.size() == mesh.faces.size();
  const bool sided = mesh.face_view_sides.size() == mesh.faces.size();
  const bool behind = mesh.face_back_crossings.size() == mesh.faces.size() && mesh.face_back_depth.size() == mesh.faces.size();
  TriangleMesh result;
  std::vector<std::uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!keep[f]) continue;
    const auto& face = mesh.faces[f];
    std::array<std::uint32_t, 3> mapped{};
    for (std::size_t k = 0; k < 3; ++k) {
      std::uint32_t& index = remap[face[k]];
      if (index == UINT32_MAX) {
        index = static_cast<std::uint32_t>(result.vertices.size());
        result.vertices.push_back(mesh.vertices[face[k]]);
        if (steiner) result.is_steiner.push_back(mesh.is_steiner[face[k]]);
        if (keyed) result.vertex_keys.push_back(mesh.vertex_keys[face[k]]);
        if (driven) result.driven_kind.push_back(mesh.driven_kind[face[k]]);
      }
      mapped[k] = index;
    }
    result.faces.push_back(mapped);
    if (observed) {
      result.face_rays.push_back(mesh.face_rays[f]);
      result.face_front_crossings.push_back(mesh.face_front_crossings[f]);
    }
    if (sided) result.face_view_sides.push_back(mesh.face_view_sides[f]);
    if (behind) {
      result.face_back_crossings.push_back(mesh.face_back_crossings[f]);
      result.face_back_depth.push_back(mesh.face_back_depth[f]);
    }
  }
  return result;
}

TriangleMesh dropSteinerFaces(const TriangleMesh& mesh) {
  if (mesh.is_steiner.size() != mesh.vertices.size()) {
    throw std::invalid_argument("dropSteinerFaces: is_steiner must have one flag per vertex");
  }
  std::vector<std::uint8_t> keep(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    keep[f] = !(mesh.is_steiner[face[0]] || mesh.is_steiner[face[1]] || mesh.is_steiner[face[2]]);
  }
  return selectFaces(mesh, keep);
}

}  // namespace terramesh::mesher
