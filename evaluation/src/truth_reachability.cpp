#include "evaluation/truth_reachability.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "evaluation/cell_key.h"
#include "evaluation/mesh_refinement.h"

namespace terramesh::evaluation {
namespace {

/// One edge of a traversable face.
struct Edge {
  Eigen::Vector3d a, b;
  std::uint32_t face;
};

/// Disjoint sets of faces, with path halving.
class UnionFind {
 public:
  explicit UnionFind(std::size_t size) : parent_(size) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void join(std::uint32_t x, std::uint32_t y) {
    x = find(x);
    y = find(y);
    if (x != y) parent_[std::max(x, y)] = std::min(x, y);
  }

 private:
  std::vector<std::uint32_t> parent_;
};

/// Whether edges p and q lie on one line (within `tolerance`) and overlap by more than it.
bool shareSegment(const Edge& p, const Edge& q, double tolerance) {
  const Eigen::Vector3d axis = p.b - p.a;
  const double length = axis.norm();
  if (!(length > tolerance)) return false;
  const Eigen::Vector3d d = axis / length;
  auto along = [&](const Eigen::Vector3d& x) { return (x - p.a).dot(d); };
  auto offLine = [&](const Eigen::Vector3d& x) { return ((x - p.a) - along(x) * d).norm(); };
  if (offLine(q.a) > tolerance || offLine(q.b) > tolerance) return false;
  const double t0 = along(q.a), t1 = along(q.b);
  const double overlap = std::min(length, std::max(t0, t1)) - std::max(0.0, std::min(t0, t1));
  return overlap > tolerance;
}


/// Joins every two traversable faces with a shared edge segment. Two overlapping edges have
/// midpoints at most (l1 + l2) / 2 <= the longest edge apart, so cells of that size and their 26
/// neighbours hold every candidate.
void joinAcrossEdges(const mesher::TriangleMesh& mesh, const std::vector<std::uint8_t>& traversable, double tolerance,
                     UnionFind& sets) {
  std::vector<Edge> edges;
  double longest = tolerance;
  for (std::uint32_t f = 0; f < mesh.faces.size(); ++f) {
    if (!traversable[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const Edge edge{mesh.vertices[mesh.faces[f][k]], mesh.vertices[mesh.faces[f][(k + 1) % 3]], f};
      longest = std::max(longest, (edge.b - edge.a).norm());
      edges.push_back(edge);
    }
  }
  const double cell = longest;
  auto keyOf = [cell](const Edge& e) { return geometry::cellOf(Eigen::Vector3d(0.5 * (e.a + e.b)), cell); };
  std::unordered_map<CellKey, std::vector<std::uint32_t>, CellKeyHash> cells;
  for (std::uint32_t e = 0; e < edges.size(); ++e) cells[keyOf(edges[e])].push_back(e);
  for (std::uint32_t e = 0; e < edges.size(); ++e) {
    const Edge& p = edges[e];
    const CellKey k = keyOf(p);
    const Eigen::Vector3d mid = 0.5 * (p.a + p.b);
    const double half = 0.5 * (p.b - p.a).norm();
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find({k.i + dx, k.j + dy, k.k + dz});
          if (it == cells.end()) continue;
          for (const std::uint32_t o : it->second) {
            const Edge& q = edges[o];
            if (o <= e || q.face == p.face || sets.find(q.face) == sets.find(p.face)) continue;
            if ((0.5 * (q.a + q.b) - mid).norm() > half + 0.5 * (q.b - q.a).norm() + tolerance) continue;
            if (shareSegment(p, q, tolerance)) sets.join(p.face, q.face);
          }
        }
      }
    }
  }
}

}  // namespace

void ReachabilityConfig::validate() const {
  std::ostringstream problems;
  if (!(edge_tolerance_m > 0) || !std::isfinite(edge_tolerance_m)) {
    problems << "edge_tolerance_m: " << edge_tolerance_m << " (expected > 0)";
  }
  if (!(snap_height_m > 0) || !std::isfinite(snap_height_m)) {
    problems << (problems.tellp() > 0 ? "; " : "") << "snap_height_m: " << snap_height_m << " (expected > 0)";
  }
  if (problems.tellp() > 0) throw std::invalid_argument("ReachabilityConfig: " + problems.str());
}

std::string_view toString(ReachStatus status) {
  switch (status) {
    case ReachStatus::kReachable: return "reachable";
    case ReachStatus::kNoSurfaceUnderStart: return "no_surface_under_start";
    case ReachStatus::kNoSurfaceUnderGoal: return "no_surface_under_goal";
    case ReachStatus::kStartNotTraversable: return "start_not_traversable";
    case ReachStatus::kGoalNotTraversable: return "goal_not_traversable";
    case ReachStatus::kDifferentComponents: return "different_components";
  }
  return "?";
}

TruthReachability::TruthReachability(const GroundTruthTraversability& truth, const ReachabilityConfig& config)
    : config_(config), up_W_(truth.up_W.normalized()), bvh_(truth.mesh.mesh) {
  config.validate();
  const mesher::TriangleMesh& mesh = truth.mesh.mesh;
  if (truth.traversable.size() != mesh.faces.size()) {
    throw std::invalid_argument("TruthReachability: the truth has " + std::to_string(truth.traversable.size()) +
                                " answers for " + std::to_string(mesh.faces.size()) + " faces");
  }
  UnionFind sets(mesh.faces.size());
  joinAcrossEdges(mesh, truth.traversable, config.edge_tolerance_m, sets);
  // Components numbered in the order of their lowest face (deterministic).
  component_.assign(mesh.faces.size(), kNoComponent);
  std::unordered_map<std::uint32_t, std::uint32_t> number;
  for (std::uint32_t f = 0; f < mesh.faces.size(); ++f) {
    if (!truth.traversable[f]) continue;
    const auto [it, inserted] = number.emplace(sets.find(f), static_cast<std::uint32_t>(component_area_m2_.size()));
    if (inserted) component_area_m2_.push_back(0.0);
    component_[f] = it->second;
    component_area_m2_[it->second] += faceArea(mesh, f);
  }
}

std::optional<std::uint32_t> TruthReachability::faceUnder(const Eigen::Vector3d& point_W) const {
  if (!point_W.allFinite()) throw std::invalid_argument("TruthReachability: a start or goal is not finite");
  if (bvh_.faceCount() == 0) return std::nullopt;
  const auto hit = bvh_.firstHit(point_W + config_.snap_height_m * up_W_, -up_W_, 2 * config_.snap_height_m);
  if (!hit) return std::nullopt;
  return hit->face;
}

ReachAnswer TruthReachability::connects(const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W) const {
  ReachAnswer answer;
  answer.start_face = faceUnder(start_W);
  answer.goal_face = faceUnder(goal_W);
  if (!answer.start_face) answer.status = ReachStatus::kNoSurfaceUnderStart;
  else if (!answer.goal_face) answer.status = ReachStatus::kNoSurfaceUnderGoal;
  else if (component_[*answer.start_face] == kNoComponent) answer.status = ReachStatus::kStartNotTraversable;
  else if (component_[*answer.goal_face] == kNoComponent) answer.status = ReachStatus::kGoalNotTraversable;
  else if (component_[*answer.start_face] != component_[*answer.goal_face]) {
    answer.status = ReachStatus::kDifferentComponents;
  }
  return answer;
}

}  // namespace terramesh::evaluation
