// A* over the face graph for a body that keeps a heading of its own (MotionModel::kOmni): each
// node of shortestPath's graph once per judged heading.
#include <algorithm>
#include <cmath>
#include <vector>

#include "common/graph_search.h"
#include "planning/face_graph.h"

namespace terramesh::planning {
namespace {

/// Each point's judged heading or its reverse (the same rectangle): the one nearer the previous
/// point's, and at the start the one nearer the way the path first moves.
std::vector<Eigen::Vector3d> continuousHeadings(const std::vector<Eigen::Vector3d>& points,
                                                const std::vector<Eigen::Vector3d>& judged) {
  std::vector<Eigen::Vector3d> out;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  const auto moved =
      std::find_if(points.begin(), points.end(), [&](const Eigen::Vector3d& p) { return p != points[0]; });
  if (moved != points.end()) previous = *moved - points[0];
  for (Eigen::Vector3d heading : judged) {
    if (heading.dot(previous) < 0) heading = -heading;
    out.push_back(heading);
    previous = heading;
  }
  return out;
}

}  // namespace

GraphPath FaceGraph::omniShortestPath(const SurfaceLocation& start, const SurfaceLocation& goal,
                                      std::uint32_t k) const {
  GraphPath result;
  const auto n = static_cast<std::uint32_t>(config_.heading_count);
  const std::size_t edge_nodes = edge_vertices_.size() * k;
  const auto start_node = static_cast<std::uint32_t>(edge_nodes);
  const auto goal_node = start_node + 1;
  // State (node, heading h) is node * n + h; a source before every start heading and a target
  // after every goal heading close the graph.
  const auto source = static_cast<std::uint32_t>((edge_nodes + 2) * n);
  const std::uint32_t target = source + 1;
  const auto position = [&](std::uint32_t node) { return nodePosition(node, k, start.point_W, goal.point_W); };
  const double turn_cost = config_.turn_cost_m_per_rad * M_PI / n / metres_per_unit_;

  const auto expand = [&](std::uint32_t u, const graph::Relax& relax) {
    if (u == target) return;
    if (u == source) {
      for (std::uint32_t h = 0; h < n; ++h) {
        if (judgedHeadingFits(start.face, static_cast<int>(h))) relax(start_node * n + h, 0.0, start.face);
      }
      return;
    }
    const std::uint32_t node = u / n, h = u % n;
    if (node == goal_node) relax(target, 0.0, goal.face);
    const Eigen::Vector3d pu = position(node);
    const auto relax_face = [&](std::uint32_t f) {
      if (f == kNoFace || !walkable_[f] || !judgedHeadingFits(f, static_cast<int>(h))) return;
      // Across f at the body's heading h.
      for (std::uint32_t edge : face_edges_[f]) {
        for (std::uint32_t j = 0; j < k; ++j) {
          const std::uint32_t v = edge * k + j;
          relax(v * n + h, (position(v) - pu).norm() * multipliers_[f], f);
        }
      }
      if (f == goal.face) relax(goal_node * n + h, (goal.point_W - pu).norm() * multipliers_[f], f);
      // Turning on the spot by one judged heading, on f.
      for (const std::uint32_t turned : {(h + 1) % n, (h + n - 1) % n}) {
        if (judgedHeadingFits(f, static_cast<int>(turned))) relax(node * n + turned, turn_cost, f);
      }
    };
    if (node == start_node) {
      relax_face(start.face);
    } else if (node != goal_node) {
      for (std::uint32_t f : edge_faces_[node / k]) relax_face(f);
    }
  };
  const auto heuristic = [&](std::uint32_t v) {
    if (v == target) return 0.0;
    return (goal.point_W - position(v == source ? start_node : v / n)).norm();
  };
  const graph::SearchResult search =
      graph::bestFirstSearch((edge_nodes + 2) * n + 2, source, target, expand, heuristic);
  result.expanded = search.expanded;
  if (!search.reached) return result;

  std::vector<std::array<Eigen::Vector3d, 2>> ends;
  std::vector<int> headings;
  for (std::uint32_t state = search.parent[target]; state != source; state = search.parent[state]) {
    const std::uint32_t node = state / n;
    result.points_W.push_back(position(node));
    headings.push_back(static_cast<int>(state % n));
    if (search.parent[state] != source) result.faces.push_back(search.parent_label[state]);
    ends.push_back(nodeEdge(node, k, start.point_W, goal.point_W));
  }
  std::reverse(result.points_W.begin(), result.points_W.end());
  std::reverse(result.faces.begin(), result.faces.end());
  std::reverse(ends.begin(), ends.end());
  std::reverse(headings.begin(), headings.end());
  std::vector<Eigen::Vector3d> judged;
  for (const int h : headings) judged.push_back(judgedHeading(h));
  result.body_headings_W = continuousHeadings(result.points_W, judged);
  finishPath(result, ends);
  return result;
}

}  // namespace terramesh::planning
