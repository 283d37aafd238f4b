#pragma once
// Faces projected on the horizontal plane, for the incremental update's reach tests. Internal.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <limits>
#include <tuple>

#include "surface_store.h"

namespace terramesh::traversability::internal {

/// A face's projection on the horizontal plane.
struct Projection {
  std::array<Eigen::Vector2d, 3> p;
  Eigen::Vector2d lo, hi;
};

/// A face added, removed or re-judged by its evidence: its projection, bounds, whether heightAt
/// can sample it and whether it is driven ground.
struct Change {
  Projection projection;
  FaceBounds bounds;
  bool sampleable = false;
  bool driven = false;
  /// Its longest horizontal edge (SampleGeometry::span_m): how far its obstacle parts may extend.
  double span_m = 0;
};

inline Projection projectionOf(const StoredFace& f) {
  return {{f.p_L[0].head<2>(), f.p_L[1].head<2>(), f.p_L[2].head<2>()}, f.box_min, f.box_max};
}

/// Face s of `store` as a change (as it is now). A face with two driven vertices counts as driven
/// ground whatever its evidence says now: whether it is the strip's edge is decided after it is
/// added, and may change with the drive's poses.
inline Change changeOf(const SurfaceStore& store, Slot s) {
  const SampleGeometry& g = store.geometry(s);
  const bool driven = g.driven || store.face(s).driven_vertices >= 2;
  return {projectionOf(store.face(s)), store.bounds(s), g.sampleable, g.sampleable && driven, g.span_m};
}

/// The point of segment ab closest to q.
inline Eigen::Vector2d closestPointOnSegment(const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                                             const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

/// The point of a projected face closest to q (q itself inside it).
inline Eigen::Vector2d closestPoint(const Eigen::Vector2d& q, const Projection& t) {
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double d0 = cross(t.p[1] - t.p[0], q - t.p[0]);
  const double d1 = cross(t.p[2] - t.p[1], q - t.p[1]);
  const double d2 = cross(t.p[0] - t.p[2], q - t.p[2]);
  if ((d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0)) return q;
  Eigen::Vector2d best = closestPointOnSegment(q, t.p[0], t.p[1]);
  for (int i = 1; i < 3; ++i) {
    const Eigen::Vector2d c = closestPointOnSegment(q, t.p[static_cast<std::size_t>(i)], t.p[static_cast<std::size_t>((i + 1) % 3)]);
    if ((c - q).squaredNorm() < (best - q).squaredNorm()) best = c;
  }
  return best;
}

/// Horizontal distance from q to a projected face (0 inside it).
inline double distanceToTriangle(const Eigen::Vector2d& q, const Projection& t) { return (closestPoint(q, t) - q).norm(); }

/// The separating-axis test of convex polygons a (na points) and b (nb points; either may be a
/// segment or a point): the widest gap between them along the normals of their edges (m; <= 0:
/// they overlap or touch along every one, by -gap at least), -infinity when neither has an edge.
inline double separatingGap(const Eigen::Vector2d* a, int na, const Eigen::Vector2d* b, int nb) {
  double gap = -std::numeric_limits<double>::infinity();
  for (const auto& [p, n, q, m] : {std::tuple(a, na, b, nb), std::tuple(b, nb, a, na)}) {
    for (int i = 0; i < n && n >= 2; ++i) {
      const Eigen::Vector2d e = p[(i + 1) % n] - p[i];
      if (!(e.squaredNorm() > 0)) continue;
      const Eigen::Vector2d axis(-e.y(), e.x());
      double lo_p = std::numeric_limits<double>::infinity(), hi_p = -lo_p, lo_q = lo_p, hi_q = -lo_p;
      for (int j = 0; j < n; ++j) lo_p = std::min(lo_p, axis.dot(p[j])), hi_p = std::max(hi_p, axis.dot(p[j]));
      for (int j = 0; j < m; ++j) lo_q = std::min(lo_q, axis.dot(q[j])), hi_q = std::max(hi_q, axis.dot(q[j]));
      gap = std::max(gap, std::max(lo_q - hi_p, lo_p - hi_q) / axis.norm());
    }
  }
  return gap;
}

/// Whether two projected faces overlap by more than `tolerance_m` across every edge direction:
/// faces that only touch, at a shared vertex or edge, do not.
inline bool projectionsOverlap(const Projection& a, const Projection& b, double tolerance_m) {
  const double gap = separatingGap(a.p.data(), 3, b.p.data(), 3);
  return gap > -std::numeric_limits<double>::infinity() && gap < -tolerance_m;
}

}  // namespace terramesh::traversability::internal
