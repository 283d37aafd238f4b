// The surface walk: a straight line in each face's plane, continued across shared edges.
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

#include "planning/face_graph.h"

namespace terramesh::planning {
namespace {

constexpr double kTiny = 1e-12;
constexpr std::size_t kMaxSteps = 50000;
/// Crossings that make no progress (round a vertex, back and forth over a ridge) before giving up.
constexpr int kMaxIdleSteps = 16;
/// A target on a face next to the current one counts as reached from here when it lies this close
/// (metres) to the current face's plane: mesh noise can put it "behind" the shared edge.
constexpr double kNeighbourPlaneToleranceM = 0.05;

bool shareVertex(const std::array<std::uint32_t, 3>& a, const std::array<std::uint32_t, 3>& b) {
  for (std::uint32_t u : a) {
    for (std::uint32_t v : b) {
      if (u == v) return true;
    }
  }
  return false;
}

int edgeIndex(const std::array<std::uint32_t, 3>& t, std::uint32_t a, std::uint32_t b) {
  for (int e = 0; e < 3; ++e) {
    const std::uint32_t u = t[static_cast<std::size_t>(e)], v = t[static_cast<std::size_t>((e + 1) % 3)];
    if ((u == a && v == b) || (u == b && v == a)) return e;
  }
  return -1;
}

}  // namespace

Eigen::Vector3d FaceGraph::sharedCrossing(const std::array<std::uint32_t, 3>& a, const std::array<std::uint32_t, 3>& b,
                                          const Eigen::Vector3d& from, const Eigen::Vector3d& to) const {
  std::vector<std::uint32_t> shared;
  for (std::uint32_t u : a) {
    for (std::uint32_t v : b) {
      if (u == v) shared.push_back(u);
    }
  }
  if (shared.size() < 2) return vertices_[shared.front()];
  const Eigen::Vector3d& p = vertices_[shared[0]];
  const Eigen::Vector3d& q = vertices_[shared[1]];
  auto length = [&](double s) {
    const Eigen::Vector3d x = p + s * (q - p);
    return (x - from).norm() + (to - x).norm();
  };
  double lo = 0, hi = 1;
  for (int it = 0; it < 60 && hi - lo > 1e-10; ++it) {  // golden-section search: convex in s
    const double m1 = hi - 0.6180339887 * (hi - lo), m2 = lo + 0.6180339887 * (hi - lo);
    if (length(m1) <= length(m2)) hi = m2;
    else lo = m1;
  }
  return p + 0.5 * (lo + hi) * (q - p);
}

SurfaceWalk FaceGraph::walk(const SurfaceLocation& from, const SurfaceLocation& to, bool require_walkable,
                            double max_detour, const std::optional<BodyTurn>& body) const {
  SurfaceWalk out;
  out.points.push_back(from);
  const double straight = (to.point_W - from.point_W).norm();
  const double max_length = max_detour * straight + 1.0 / metres_per_unit_;
  double length = 0, cost = 0;
  SurfaceLocation current = from;
  int entry_edge = -1;
  int idle_steps = 0;
  // The heading of travel, straight at the target; or the body's own, turning over the walk.
  const Eigen::Vector3d travel = to.point_W - from.point_W;
  const auto passable = [&](std::uint32_t f) {
    return walkable_[f] && (body ? turnFits(f, body->from_W, body->turn_rad) : headingFits(f, travel));
  };
  auto finish = [&](WalkStop stop) {
    out.stop = stop;
    out.length_m = length * metres_per_unit_;
    out.cost = cost * metres_per_unit_;
    return out;
  };
  auto step = [&](const SurfaceLocation& next, std::uint32_t on_face) {
    const double piece = (next.point_W - current.point_W).norm();
    length += piece;
    cost += piece * multipliers_[on_face];
    out.points.push_back(next);
    current = next;
  };
  for (std::size_t steps = 0; steps < kMaxSteps; ++steps) {
    const std::uint32_t f = current.face;
    if (f >= faces_.size()) return finish(WalkStop::kBoundary);
    if (require_walkable && !passable(f)) return finish(WalkStop::kBlocked);
    if (f == to.face) {
      step(to, f);
      return finish(WalkStop::kReached);
    }
    const auto& t = faces_[f];
    const Eigen::Vector3d& n = normals_[f];
    Eigen::Vector3d d = to.point_W - current.point_W;
    d -= d.dot(n) * n;
    const double dl = d.norm();
    double t_exit = std::numeric_limits<double>::infinity();
    int exit_edge = -1;
    if (dl > kTiny) {
      const Eigen::Vector3d dir = d / dl;
      for (int e = 0; e < 3; ++e) {
        if (e == entry_edge) continue;
        const Eigen::Vector3d& a = vertices_[t[static_cast<std::size_t>(e)]];
        const Eigen::Vector3d& b = vertices_[t[static_cast<std::size_t>((e + 1) % 3)]];
        const Eigen::Vector3d inward = n.cross(b - a);  // faces are counter-clockwise about n
        const double rate = dir.dot(inward);
        if (rate >= 0) continue;
        const double te = std::max(0.0, (current.point_W - a).dot(inward) / -rate);
        if (te < t_exit) {
          t_exit = te;
          exit_edge = e;
        }
      }
    }
    if (dl <= kTiny || dl <= t_exit) {
      // The projected target lies inside this face.
      if (to.face == kNoFace) {
        step(SurfaceLocation{f, current.point_W + d}, f);
        return finish(WalkStop::kReached);
      }
      const double off_plane = std::abs((to.point_W - current.point_W).dot(n)) * metres_per_unit_;
      if (to.face < faces_.size() && shareVertex(t, faces_[to.face]) && off_plane <= kNeighbourPlaneToleranceM &&
          (!require_walkable || passable(to.face))) {
        // Over the shared edge (or vertex) at its cheapest point, so both pieces stay on their faces.
        step(SurfaceLocation{to.face, sharedCrossing(t, faces_[to.face], current.point_W, to.point_W)}, f);
        step(to, to.face);
        return finish(WalkStop::kReached);
      }
      return finish(WalkStop::kStuck);
    }
    if (exit_edge < 0) return finish(WalkStop::kStuck);
    const std::uint32_t ia = t[static_cast<std::size_t>(exit_edge)];
    const std::uint32_t ib = t[static_cast<std::size_t>((exit_edge + 1) % 3)];
    const Eigen::Vector3d& a = vertices_[ia];
    const Eigen::Vector3d& b = vertices_[ib];
    // Put the crossing exactly on the shared edge, off its end points (the next face owns it too).
    const Eigen::Vector3d crossing = current.point_W + t_exit * (d / dl);
    const double edge2 = (b - a).squaredNorm();
    const double u = std::clamp(edge2 > 0 ? (crossing - a).dot(b - a) / edge2 : 0.5, 1e-7, 1.0 - 1e-7);
    const Eigen::Vector3d q = a + u * (b - a);
    const std::uint32_t g = neighbours_[f][static_cast<std::size_t>(exit_edge)];
    const double before = length;
    step(SurfaceLocation{g == kNoFace ? f : g, q}, f);
    if (g == kNoFace) return finish(WalkStop::kBoundary);
    idle_steps = length - before < 1e-9 * (1.0 + straight) ? idle_steps + 1 : 0;
    if (idle_steps > kMaxIdleSteps) return finish(WalkStop::kStuck);
    if (length > max_length) return finish(WalkStop::kTooLong);
    entry_edge = edgeIndex(faces_[g], ia, ib);
  }
  return finish(WalkStop::kTooLong);
}

}  // namespace terramesh::planning
