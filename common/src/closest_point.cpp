#include "common/closest_point.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace terramesh::geometry {

Eigen::Vector3d closestPointOnSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 == 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
  return a + t * ab;
}

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c, DegenerateTriangles degenerate) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  if (degenerate == DegenerateTriangles::kAsEdges) {
    const double scale = std::max(ab.squaredNorm(), ac.squaredNorm());
    if (ab.cross(ac).squaredNorm() <= 1e-24 * scale * scale) {
      const Eigen::Vector3d candidates[3] = {closestPointOnSegment(p, a, b), closestPointOnSegment(p, b, c),
                                             closestPointOnSegment(p, c, a)};
      const Eigen::Vector3d* best = &candidates[0];
      for (const Eigen::Vector3d& q : candidates) {
        if ((q - p).squaredNorm() < (*best - p).squaredNorm()) best = &q;
      }
      return *best;
    }
  }
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

}  // namespace terramesh::geometry
