#pragma once

#include <Eigen/Core>
#include <cmath>

#include "common/plan_frame.h"

namespace terramesh::planning {

/// Smallest signed difference b - a between two angles, in (-pi, pi].
inline double angleDifference(double a, double b) {
  double d = std::remainder(b - a, 2.0 * M_PI);
  if (d <= -M_PI) d += 2.0 * M_PI;
  return d;
}

/// Heading of a direction about `up` (unit), radians in (-pi, pi]: 0 along the map x axis
/// projected into the horizontal plane (the y axis where that projection is shorter than 0.3, x
/// nearly vertical), counter-clockwise seen from above.
inline double headingAbout(const Eigen::Vector3d& direction, const Eigen::Vector3d& up) {
  const geometry::PlanFrame frame = geometry::planFrame(up, geometry::headingFrameRule());
  return std::atan2(direction.dot(frame.e2), direction.dot(frame.e1));
}

}  // namespace terramesh::planning
