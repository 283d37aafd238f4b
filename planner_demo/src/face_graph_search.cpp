// A* over points on the edges of the walkable faces: the discrete baseline.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include "common/graph_search.h"
#include "planning/face_graph.h"

namespace terramesh::planning {
namespace {

/// Moves every crossing along its edge to the cheapest place given its neighbours, sweep after
/// sweep (coordinate descent on a convex function: the cost is a sum of weighted norms of affine
/// functions of the edge parameters), so the polyline becomes the cheapest one through the same
/// sequence of edges. `ends[i]` are the edge end points of point i (unused for the first and last).
/// A move is taken only where `allowed(i, p)` holds for point i at p (the headings of travel).
void straighten(std::vector<Eigen::Vector3d>& points, const std::vector<std::array<Eigen::Vector3d, 2>>& ends,
                const std::vector<double>& weights,
                const std::function<bool(std::size_t, const Eigen::Vector3d&)>& allowed) {
  auto piece_cost = [&](std::size_t i, const Eigen::Vector3d& p) {
    return (p - points[i - 1]).norm() * weights[i - 1] + (points[i + 1] - p).norm() * weights[i];
  };
  for (int sweep = 0; sweep < 500; ++sweep) {
    double moved = 0;
    for (std::size_t i = 1; i + 1 < points.size(); ++i) {
      const Eigen::Vector3d& a = ends[i][0];
      const Eigen::Vector3d& b = ends[i][1];
      double lo = 0, hi = 1;
      for (int it = 0; it < 60 && hi - lo > 1e-10; ++it) {  // golden-section search
        const double m1 = hi - 0.6180339887 * (hi - lo), m2 = lo + 0.6180339887 * (hi - lo);
        if (piece_cost(i, a + m1 * (b - a)) <= piece_cost(i, a + m2 * (b - a))) hi = m2;
        else lo = m1;
      }
      const Eigen::Vector3d candidate = a + 0.5 * (lo + hi) * (b - a);
      if (piece_cost(i, candidate) < piece_cost(i, points[i]) && allowed(i, candidate)) {
        moved = std::max(moved, (candidate - points[i]).norm());
        points[i] = candidate;
      }
    }
    if (moved < 1e-9) break;
  }
}

}  // namespace

Eigen::Vector3d FaceGraph::nodePosition(std::uint32_t node, std::uint32_t k, const Eigen::Vector3d& start_W,
                                        const Eigen::Vector3d& goal_W) const {
  const std::size_t edge_nodes = edge_vertices_.size() * k;
  if (node == edge_nodes) return start_W;
  if (node == edge_nodes + 1) return goal_W;
  const auto& ends = edge_vertices_[node / k];
  const double s = static_cast<double>(node % k + 1) / static_cast<double>(k + 1);
  return vertices_[ends[0]] + s * (vertices_[ends[1]] - vertices_[ends[0]]);
}

std::array<Eigen::Vector3d, 2> FaceGraph::nodeEdge(std::uint32_t node, std::uint32_t k, const Eigen::Vector3d& start_W,
                                                   const Eigen::Vector3d& goal_W) const {
  if (node < edge_vertices_.size() * k) {
    const auto& ends = edge_vertices_[node / k];
    return {vertices_[ends[0]], vertices_[ends[1]]};
  }
  const Eigen::Vector3d p = nodePosition(node, k, start_W, goal_W);  // the start or goal: fixed
  return {p, p};
}

void FaceGraph::finishPath(GraphPath& path, const std::vector<std::array<Eigen::Vector3d, 2>>& ends) const {
  std::vector<double> weights;
  for (std::uint32_t f : path.faces) weights.push_back(multipliers_[f]);
  // Point i joins piece i - 1 (on faces[i - 1]) and piece i (on faces[i]). A body that keeps its own
  // heading fits its faces wherever the crossings lie; one facing its travel turns with them.
  const auto allowed = [&](std::size_t i, const Eigen::Vector3d& p) {
    if (!path.body_headings_W.empty()) return true;
    return headingFits(path.faces[i - 1], p - path.points_W[i - 1]) &&
           headingFits(path.faces[i], path.points_W[i + 1] - p);
  };
  straighten(path.points_W, ends, weights, allowed);
  double length = 0, cost = 0;
  for (std::size_t i = 1; i < path.points_W.size(); ++i) {
    const double piece = (path.points_W[i] - path.points_W[i - 1]).norm();
    length += piece;
    cost += piece * weights[i - 1];
    if (path.body_headings_W.empty()) continue;
    // The body's turn (a rectangle turned by 180 deg is the same), as the search charged it.
    const double cosine = std::abs(path.body_headings_W[i].dot(path.body_headings_W[i - 1]));
    cost += config_.turn_cost_m_per_rad * std::acos(std::min(cosine, 1.0)) / metres_per_unit_;
  }
  path.found = true;
  path.length_m = length * metres_per_unit_;
  path.cost = cost * metres_per_unit_;
}

GraphPath FaceGraph::shortestPath(const SurfaceLocation& start, const SurfaceLocation& goal, int points_per_edge) const {
  if (points_per_edge < 1) throw std::invalid_argument("FaceGraph::shortestPath: points_per_edge must be >= 1");
  GraphPath result;
  if (start.face >= faces_.size() || goal.face >= faces_.size()) return result;
  if (!walkable_[start.face] || !walkable_[goal.face]) return result;
  if (components_[start.face] != components_[goal.face]) return result;
  const auto k = static_cast<std::uint32_t>(points_per_edge);
  if (keepsOwnHeading()) return omniShortestPath(start, goal, k);

  const std::size_t edge_nodes = edge_vertices_.size() * k;
  const auto start_node = static_cast<std::uint32_t>(edge_nodes);
  const auto goal_node = start_node + 1;
  const auto position = [&](std::uint32_t node) { return nodePosition(node, k, start.point_W, goal.point_W); };

  // A* over the edge nodes (plus start and goal); an edge's label is the face it crosses.
  const auto expand = [&](std::uint32_t u, const graph::Relax& relax) {
    const Eigen::Vector3d pu = position(u);
    auto relax_face = [&](std::uint32_t f) {
      if (f == kNoFace || !walkable_[f]) return;
      // The piece across f from u to v, at the heading of travel it drives.
      const auto relax_piece = [&](std::uint32_t v, const Eigen::Vector3d& pv) {
        if (headingFits(f, pv - pu)) relax(v, (pv - pu).norm() * multipliers_[f], f);
      };
      for (std::uint32_t edge : face_edges_[f]) {
        for (std::uint32_t j = 0; j < k; ++j) relax_piece(edge * k + j, position(edge * k + j));
      }
      if (f == goal.face) relax_piece(goal_node, goal.point_W);
    };
    if (u == start_node) {
      relax_face(start.face);
    } else {
      for (std::uint32_t f : edge_faces_[u / k]) relax_face(f);
    }
  };
  const graph::SearchResult search = graph::bestFirstSearch(
      edge_nodes + 2, start_node, goal_node, expand, [&](std::uint32_t v) { return (goal.point_W - position(v)).norm(); });
  result.expanded = search.expanded;
  if (!search.reached) return result;
  std::vector<std::array<Eigen::Vector3d, 2>> ends;
  for (std::uint32_t node = goal_node; node != graph::SearchResult::kNone; node = search.parent[node]) {
    result.points_W.push_back(position(node));
    if (search.parent[node] != graph::SearchResult::kNone) result.faces.push_back(search.parent_label[node]);
    ends.push_back(nodeEdge(node, k, start.point_W, goal.point_W));
  }
  std::reverse(result.points_W.begin(), result.points_W.end());
  std::reverse(result.faces.begin(), result.faces.end());
  std::reverse(ends.begin(), ends.end());
  finishPath(result, ends);
  return result;
}

}  // namespace terramesh::planning
