#pragma once

// Orthonormal frames built from an up vector: the plan (horizontal) frame of maps, grids and
// headings, and the two axes across any direction.
#include <Eigen/Core>

namespace terramesh::geometry {

/// How `planFrame` builds its first axis e1 from the helper map axis.
enum class FirstAxis {
  kProjectedHelper,  ///< the helper projected into the plane orthogonal to up, normalised
  kUpCrossHelper,    ///< up x helper, normalised: a quarter turn about up from kProjectedHelper
};

/// How `planFrame` picks its helper axis (the map x axis, or the map y axis where x is too close
/// to up) and turns it into e1. The defaults give the plan frame of the maps and their exports.
/// Dimensionless thresholds; each variant is kept exactly because its users' outputs depend on it.
struct PlanFrameRule {
  FirstAxis first_axis = FirstAxis::kProjectedHelper;
  /// The helper is the map x axis while |up.x| < this, else the map y axis. In (0, 1].
  double x_helper_below_abs_up_x = 0.9;
  /// If > 0, replaces the test above: the helper is the map x axis while its projection into the
  /// plane, x - (x . up) up, is at least this long, else the map y axis. In [0, 1).
  double x_helper_min_projected_norm = 0.0;

  /// @throw std::invalid_argument naming every threshold out of its range.
  void validate() const;
};

/// The map x axis projected unless it lies within 30 degrees of up (|up.x| > cos 30 degrees; then
/// y): the frame of the 2-D map exports (traversability::MapPlane) and of compare's top view.
PlanFrameRule exportFrameRule();

/// The map x axis projected unless that projection is shorter than 0.3 (then y): the frame that
/// planning measures headings in.
PlanFrameRule headingFrameRule();

/// The horizontal unit direction at heading `yaw_rad` about `up` (unit) in the frame planning
/// measures headings in (headingFrameRule): cos(yaw) e1 + sin(yaw) e2, counter-clockwise seen
/// from above. The yaw of terramesh plan's path.csv. O(1), thread-safe.
Eigen::Vector3d headingDirection(double yaw_rad, const Eigen::Vector3d& up);

/// e1 = up x helper with the default helper test: two axes across any unit direction (a column's
/// axis, a face normal).
PlanFrameRule acrossFrameRule();

/// A right-handed orthonormal frame with a given third axis: e1 x e2 = up.
struct PlanFrame {
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();

  /// Coordinates of p along e1 and e2 (its position in the plan, in p's units).
  Eigen::Vector2d project(const Eigen::Vector3d& p) const { return {p.dot(e1), p.dot(e2)}; }
};

/// The frame (e1, e2, up) for `up` under `rule`: e1 from the helper axis (see PlanFrameRule),
/// e2 = up x e1. Deterministic: the same up gives the same bits. O(1), thread-safe.
/// @pre up is a unit vector (it is used as given, not normalised).
/// @throw std::invalid_argument if `rule` is invalid.
PlanFrame planFrame(const Eigen::Vector3d& up, const PlanFrameRule& rule = {});

/// The rotation that turns `up` onto +z by the smallest turn (Eigen's Quaternion::FromTwoVectors):
/// the gravity-aligned frame of the voxel baselines, whose x and y follow the map's as closely as
/// a rotation can. Rows are the frame's axes in map coordinates. O(1), thread-safe.
/// @pre up is finite and non-zero (normalised here).
Eigen::Matrix3d rotationUpToZ(const Eigen::Vector3d& up);

}  // namespace terramesh::geometry
