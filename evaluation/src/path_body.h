#pragma once

// The robot's body along a path, for the truth check: the heading a rectangle drives at, and an
// exact test of a triangle against the upright box over its footprint.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace terramesh::evaluation::internal {

/// An upright box: a footprint rectangle centred on `base`, turned to `ahead`, from `bottom` to
/// `top` above it along `up`. Lengths in the units of `base`.
struct BodyBox {
  Eigen::Vector3d base = Eigen::Vector3d::Zero();
  Eigen::Vector3d ahead = Eigen::Vector3d::UnitX();  ///< unit, perpendicular to `up`
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();     ///< unit
  double half_length = 0;                            ///< along `ahead`
  double half_width = 0;                             ///< across it
  double bottom = 0, top = 0;

  /// The centre of the box and the radius of the ball around it.
  Eigen::Vector3d centre() const;
  double circumradius() const;
  /// `point` as (ahead, beside, up) from `base`; beside is to the left (up x ahead).
  Eigen::Vector3d local(const Eigen::Vector3d& point) const;
};

/// A point of triangle (a, b, c) strictly inside `box` (the centroid of the corners of the
/// triangle clipped to the box), or nothing when the triangle only touches the box's boundary or
/// misses it.
std::optional<Eigen::Vector3d> triangleInBox(const BodyBox& box, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                             const Eigen::Vector3d& c);

/// The heading of travel at each point of a densely sampled path: the horizontal direction (unit,
/// perpendicular to `up`) of the chord from the path point `half_reach` behind to the one
/// `half_reach` ahead along the path (clamped to its ends), the heading of a body whose two ends
/// follow the path. Where a chord has no horizontal length the neighbouring heading holds. Empty
/// when no chord has one (every point on one vertical line). `half_reach` in the path's units.
std::vector<Eigen::Vector3d> travelHeadings(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& up,
                                            double half_reach);

/// `heading` turned about `up` by `angle_rad` (counter-clockwise seen from above).
Eigen::Vector3d turned(const Eigen::Vector3d& heading, const Eigen::Vector3d& up, double angle_rad);

/// The signed angle about `up` from heading `from` to heading `to`, in (-pi, pi].
double turnAngle(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const Eigen::Vector3d& up);

}  // namespace terramesh::evaluation::internal
