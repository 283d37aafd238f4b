#pragma once
// Faces projected on the horizontal plane, for the incremental update's reach tests. Internal.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <utility>

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
};

inline Projection projectionOf(const StoredFace& f) {
  return {{f.p_L[0].head<2>(), f.p_L[1].head<2>(), f.p_L[2].head<2>()}, f.box_min, f.box_max};
}

/// Face s of `store` as a change (as it is now).
inline Change changeOf(const SurfaceStore& store, Slot s) {
  const SampleGeometry& g = store.geometry(s);
  return {projectionOf(store.face(s)), store.bounds(s), g.sampleable, g.sampleable && g.driven};
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

/// Whether two projected faces overlap by more than `tolerance_m` across every edge direction
/// (separating axes): faces that only touch, at a shared vertex or edge, do not.
inline bool projectionsOverlap(const Projection& a, const Projection& b, double tolerance_m) {
  for (const auto& [edges, other] : {std::pair(&a, &b), std::pair(&b, &a)}) {
    for (std::size_t i = 0; i < 3; ++i) {
      const Eigen::Vector2d e = edges->p[(i + 1) % 3] - edges->p[i];
      const double length = e.norm();
      if (!(length > 0)) continue;
      const Eigen::Vector2d axis = Eigen::Vector2d(-e.y(), e.x()) / length;
      double lo_a = axis.dot(edges->p[0]), hi_a = lo_a, lo_b = axis.dot(other->p[0]), hi_b = lo_b;
      for (std::size_t j = 1; j < 3; ++j) {
        lo_a = std::min(lo_a, axis.dot(edges->p[j]));
        hi_a = std::max(hi_a, axis.dot(edges->p[j]));
        lo_b = std::min(lo_b, axis.dot(other->p[j]));
        hi_b = std::max(hi_b, axis.dot(other->p[j]));
      }
      if (hi_a <= lo_b + tolerance_m || hi_b <= lo_a + tolerance_m) return false;
    }
  }
  return true;
}

}  // namespace terramesh::traversability::internal
