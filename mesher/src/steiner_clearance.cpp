#include "steiner_clearance.h"

#include <algorithm>
#include <tuple>

#include "mesher/surface_delta.h"

namespace terramesh::mesher::internal {

double SteinerClearance::clearance() const {
  return state_.config.steiner_clearance_steps * state_.grid.step();
}

bool SteinerClearance::enabled() const { return state_.config.steiner_clearance_steps > 0; }

bool SteinerClearance::nearNode(const Eigen::Vector3d& p, GridKey& node) const {
  if (state_.grid.empty()) return false;
  node = state_.grid.nodeOf(p);
  const GridKey lo = state_.grid.lowerNode();
  const GridKey hi = state_.grid.upperNode();
  // Nodes on the box's faces bound the triangulation; they are never within reach of the data
  // (the grid keeps a margin of cells beyond it), but never remove them.
  if (node.i <= lo.i || node.j <= lo.j || node.k <= lo.k || node.i >= hi.i || node.j >= hi.j || node.k >= hi.k) {
    return false;
  }
  return (state_.grid.nodePosition(node) - p).norm() < clearance();
}

bool SteinerClearance::clearAround(const Eigen::Vector3d& p, std::vector<RayId>& retrace) {
  GridKey node;
  if (!enabled() || !nearNode(p, node)) return false;
  const auto it = state_.steiner_nodes.find(VertexKey::steinerNode(node.i, node.j, node.k).value);
  if (it == state_.steiner_nodes.end()) return false;
  const VertexHandle v = it->second;
  if (editor_.starTouchesOutside(v)) return false;
  editor_.remove(v, retrace);
  state_.steiner_nodes.erase(it);
  --state_.steiner_vertices;
  return true;
}

std::size_t SteinerClearance::restoreAround(const std::vector<Eigen::Vector3d>& old_positions,
                                            std::vector<RayId>& retrace) {
  if (!enabled()) return 0;
  std::vector<GridKey> nodes;
  for (const Eigen::Vector3d& p : old_positions) {
    GridKey node;
    if (nearNode(p, node)) nodes.push_back(node);
  }
  // One order whatever the order of the points.
  std::sort(nodes.begin(), nodes.end(), [](const GridKey& a, const GridKey& b) {
    return std::tie(a.i, a.j, a.k) < std::tie(b.i, b.j, b.k);
  });
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  std::size_t restored = 0;
  for (const GridKey& node : nodes) {
    const std::uint64_t key = VertexKey::steinerNode(node.i, node.j, node.k).value;
    if (state_.steiner_nodes.count(key)) continue;
    const Eigen::Vector3d position = state_.grid.nodePosition(node);
    // Other lattice nodes are a step away, so a vertex nearer than the clearance is a point.
    const VertexHandle nearest = state_.tri.nearest_vertex(toPoint(position));
    if (nearest != VertexHandle() && !state_.tri.is_infinite(nearest) &&
        (toEigen(nearest->point()) - position).norm() < clearance()) {
      continue;
    }
    VertexHandle vertex;
    if (editor_.insert(position, kNone, retrace, vertex) != TriangulationEditor::InsertResult::kInserted) continue;
    state_.steiner_nodes.emplace(key, vertex);
    ++state_.steiner_vertices;
    ++restored;
  }
  return restored;
}

}  // namespace terramesh::mesher::internal
