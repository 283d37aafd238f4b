#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace terramesh::planning {

/// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection, 5.1.5).
inline Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Smallest signed difference b - a between two angles, in (-pi, pi].
inline double angleDifference(double a, double b) {
  double d = std::remainder(b - a, 2.0 * M_PI);
  if (d <= -M_PI) d += 2.0 * M_PI;
  return d;
}

}  // namespace terramesh::planning

namespace terramesh::planning {

/// Heading of a direction about `up` (unit), radians in (-pi, pi]: 0 along the map x axis
/// projected into the horizontal plane (the y axis if x is vertical), counter-clockwise seen from
/// above.
inline double headingAbout(const Eigen::Vector3d& direction, const Eigen::Vector3d& up) {
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX() - up.x() * up;
  if (e1.norm() < 0.3) e1 = Eigen::Vector3d::UnitY() - up.y() * up;
  e1.normalize();
  const Eigen::Vector3d e2 = up.cross(e1);
  return std::atan2(direction.dot(e2), direction.dot(e1));
}

}  // namespace terramesh::planning
