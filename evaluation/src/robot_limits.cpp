#include "evaluation/robot_limits.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "traversability/robot_profile.h"

namespace terramesh::evaluation {

void RobotLimits::validate() const {
  std::ostringstream problems;
  auto require = [&](bool ok, const char* field, double value, const char* expected) {
    if (ok) return;
    problems << (problems.tellp() > 0 ? "; " : "") << field << ": " << value << " (expected " << expected << ")";
  };
  require(std::isfinite(footprint_radius_m) && footprint_radius_m >= 0, "footprint_radius_m", footprint_radius_m,
          ">= 0");
  require(footprint_length_m >= 0 && footprint_width_m >= 0 && (footprint_length_m > 0) == (footprint_width_m > 0),
          "footprint_length_m", footprint_length_m, ">= 0, and > 0 exactly when footprint_width_m is");
  require(!isRectangle() || footprint_radius_m >= 0.5 * std::hypot(footprint_length_m, footprint_width_m) - 1e-12,
          "footprint_radius_m", footprint_radius_m, ">= half the rectangle's diagonal");
  require(headings >= 1 && headings <= 360, "headings", headings, "in [1, 360]");
  require(max_slope_deg >= 0 && max_slope_deg <= 90, "max_slope_deg", max_slope_deg, "in [0, 90]");
  require(std::isfinite(max_step_m) && max_step_m >= 0, "max_step_m", max_step_m, ">= 0");
  require(std::isfinite(height_m) && height_m > max_step_m, "height_m", height_m, "finite and > max_step_m");
  if (problems.tellp() > 0) throw std::invalid_argument("RobotLimits " + name + ": " + problems.str());
}

RobotLimits robotLimitsFrom(const traversability::RobotProfile& profile) {
  RobotLimits limits;
  limits.name = profile.name;
  if (profile.footprint == traversability::FootprintShape::kDisc) {
    limits.footprint_radius_m = profile.footprint_radius_m;
  } else {
    limits.footprint_length_m = profile.footprint_length_m;
    limits.footprint_width_m = profile.footprint_width_m;
    limits.footprint_radius_m = 0.5 * std::hypot(profile.footprint_length_m, profile.footprint_width_m);
  }
  limits.max_slope_deg = profile.max_slope_deg;
  limits.max_step_m = profile.max_step_m;
  limits.height_m = profile.min_clearance_m;
  limits.validate();
  return limits;
}

}  // namespace terramesh::evaluation
