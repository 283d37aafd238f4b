#pragma once

#include <string>

namespace terramesh::traversability {
struct RobotProfile;
}

namespace terramesh::evaluation {

/// The few numbers of a robot that decide ground-truth traversability, as plain values, so that
/// the ground-truth labeller depends on nothing of the traversability library's layer code.
/// Lengths in metres, angles in degrees.
struct RobotLimits {
  std::string name = "robot";
  /// Radius of the disc the robot occupies on the ground; for a rectangle, the radius of the
  /// smallest disc around it (half its diagonal).
  double footprint_radius_m = 0.3;
  /// Rectangle footprint (length along the heading, width across); both 0 for a disc. A
  /// rectangle fits where it fits at one of `headings` headings evenly spread over 180 degrees.
  double footprint_length_m = 0;
  double footprint_width_m = 0;
  int headings = 16;
  /// Steepest slope the robot climbs.
  double max_slope_deg = 20.0;
  /// Highest step it crosses (curbs, a rock edge).
  double max_step_m = 0.2;
  /// Robot height: it needs at least this much free height above the ground.
  double height_m = 1.0;

  bool isRectangle() const { return footprint_length_m > 0 && footprint_width_m > 0; }

  /// @throw std::invalid_argument listing every out-of-range field as "field: value (expected)".
  void validate() const;
};

/// The limits of a profile: its footprint (disc, or rectangle with its circumradius), max slope,
/// max step and min clearance (the robot's height).
/// @throw std::invalid_argument if the resulting limits do not validate.
RobotLimits robotLimitsFrom(const traversability::RobotProfile& profile);

}  // namespace terramesh::evaluation
