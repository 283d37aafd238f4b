#pragma once

// Robot profiles in YAML (robot.yaml, traversability/robots/*.yaml): part of traversability_io,
// so that computing layers needs no YAML library.
#include <filesystem>

#include "traversability/robot_profile.h"

namespace terramesh::traversability {

/// Reads a robot profile from YAML. Every key is optional except `name`; unknown keys are errors.
/// Schema (lengths in metres, angles in degrees; ranges as validate() checks them):
///   name: string
///   footprint: {radius_m: R} (disc) | {length_m: L, width_m: W} (rectangle, L along the heading)
///   max_slope_deg (0, 90), max_step_m [0, 10], max_roughness_m (0, 10], min_clearance_m (0, 50],
///   contact_tolerance_m (0, 10], min_support [0, 1], contact_headings: integer [1, 24],
///   inscribed_radius_m [0, 100], inflation_radius_m [inscribed_radius_m, 100],
///   cost_scaling_factor (0, 1000], weights: {slope, step, roughness, contact, inflation} each
///   [0, 1000] not all 0, min_rays: integer [0, 1e6],
///   gravity: auto | [x, y, z] (pointing down, map frame; auto = estimateUpFromCameras),
///   sensor_height_m (0, 20] (sensor above the ground contact plane; unset = estimate),
///   sensor_pose_in_base: {translation_m: [x, y, z], rotation_xyzw: [x, y, z, w]} (T_B_S; z in
///   (0, 20], a non-zero quaternion; sensor_height_m, if given too, equal to z),
///   evidence: {point_noise_m [0, 10], relief_per_m_observed [0, 10], relief_per_m_unobserved
///   [0, 10], driven_uncertainty_m [0, 10], obstacle_extension [0, 10], max_obstacle_extension_m
///   [0, 100], obstacle_support_m [0, 100], unconfirmed_point_extension_m [0, 100], proud_point_rise_m
///   [0, 10], uncertain_cost [0, 1]}.
/// The shipped profiles (traversability/robots/*.yaml) repeat it in their header comment.
/// @throw terramesh::InputError naming the file, the key (and line), the value and the allowed
///        range or type.
RobotProfile loadRobotProfile(const std::filesystem::path& path);

/// Writes `profile` as YAML that loadRobotProfile reads back to an equal profile. Atomic.
/// @throw std::runtime_error if the file cannot be written.
void writeRobotProfile(const std::filesystem::path& path, const RobotProfile& profile);

}  // namespace terramesh::traversability
