#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>

namespace terramesh::traversability {

/// Shape of the robot's footprint on the ground.
enum class FootprintShape { kDisc, kRectangle };

/// How the body's heading relates to its motion (Nav2 MPPI's motion models, without Ackermann's
/// turning radius). Only a rectangle's heading matters: a disc is the same at every heading.
enum class MotionModel {
  /// The body faces its direction of travel (a differential-drive or car-like base).
  kDiffDrive,
  /// Holonomic: the body keeps any heading while it moves in any direction, and turns on the spot
  /// (a legged robot or a mecanum base walking sideways).
  kOmni,
};

/// "diff_drive" or "omni", as the profile's `motion_model` key spells it.
const char* toString(MotionModel model);

/// Weights of the normalised layers in the combined cost (each layer is first mapped to [0, 1]
/// by its limit in the profile, see docs/traversability.md). Any non-negative values; they are
/// normalised by their sum.
struct LayerWeights {
  double slope = 1.0;
  double step = 1.0;
  double roughness = 1.0;
  double contact = 1.0;
  double inflation = 1.0;
};

/// How the layers weigh the evidence behind each face (docs/traversability.md, "Evidence"). A face's
/// height uncertainty bound is `point_noise_m` plus its longest horizontal edge times the relief
/// per metre (observed: rays crossed the free space in front of it; unobserved: none did);
/// driven faces have `driven_uncertainty_m`. Lengths in metres.
struct EvidenceModel {
  /// Height noise (1 sigma) of the SLAM points.
  double point_noise_m = 0.03;
  /// Relief a span can hide between its vertices, per metre of span, with rays over it / without.
  double relief_per_m_observed = 0.01;
  double relief_per_m_unobserved = 0.05;
  /// Height uncertainty of driven ground (the sensor mounting's).
  double driven_uncertainty_m = 0.05;
  /// A measured obstacle may extend beyond its faces by this fraction of their longest edge (a
  /// wall's free end, a rock seen from one side), up to `max_obstacle_extension_m`.
  double obstacle_extension = 0.5;
  double max_obstacle_extension_m = 0.5;
  /// Over driven ground, a measured face supports an obstacle within this distance of its
  /// vertices along its edges; the rest of a longer span, across the volume the robot's body
  /// swept, is interpolated and contradicted by the drive.
  double obstacle_support_m = 0.5;
  /// A SLAM point the mesher did not insert (fewer than its `min_views` keyframes saw it:
  /// mesher::Mesher::unconfirmedPoints) inside a face's body is a possible obstacle this far
  /// around it (a rock seen by one keyframe: its size unknown).
  double unconfirmed_point_extension_m = 0.5;
  /// A SLAM point this high over the ground plane under a footprint belongs to an object whose
  /// top nobody measured: a sparse point lies anywhere on it, rarely at its top. An unconfirmed
  /// point higher than this (or than max_step_m, if lower) is a possible obstacle.
  double proud_point_rise_m = 0.1;
  /// Cost of an uncertain face, for planners allowed to enter one, in [0, 1].
  double uncertain_cost = 0.9;
};

/// What a robot can drive on. Lengths in metres, angles in degrees. Loaded from YAML
/// (loadRobotProfile) or built in code; validate() before use.
struct RobotProfile {
  std::string name = "robot";
  FootprintShape footprint = FootprintShape::kDisc;
  /// Disc footprint radius.
  double footprint_radius_m = 0.3;
  /// Rectangle footprint, length along the heading and width across it.
  double footprint_length_m = 0.6;
  double footprint_width_m = 0.5;

  /// Steepest slope the robot climbs; steeper faces are lethal.
  double max_slope_deg = 20.0;
  /// Highest step (height jump within the footprint) it crosses; higher is lethal.
  double max_step_m = 0.2;
  /// Largest roughness (RMS deviation from the plane fitted over the footprint); more is lethal.
  double max_roughness_m = 0.08;
  /// Robot height: faces with less measured free height above them are lethal.
  double min_clearance_m = 1.0;
  /// A footprint sample point is supported if the surface is within this distance of the
  /// footprint plane there.
  double contact_tolerance_m = 0.05;
  /// Smallest supported fraction of the footprint the robot needs at a heading; a face where no
  /// heading has it is lethal.
  double min_support = 0.7;
  /// Headings at which a rectangular footprint is judged (evenly spaced over 180 degrees: a
  /// rectangle turned by 180 degrees is the same); a disc has one.
  int contact_headings = 8;
  /// Whether a rectangle's body faces its direction of travel (planners keep that heading to the
  /// ones its footprint fits at) or keeps a heading of its own (docs/planning.md, "Headings").
  MotionModel motion_model = MotionModel::kDiffDrive;

  /// Costmap-style inflation (Nav2 inflation layer): within `inscribed_radius_m` of a lethal face
  /// the cost is the inscribed cost; beyond it decays as exp(-cost_scaling_factor * (d - r_i))
  /// up to `inflation_radius_m`, where it stops. Distances are geodesic over the surface.
  double inscribed_radius_m = 0.3;
  double inflation_radius_m = 1.0;
  double cost_scaling_factor = 3.0;  ///< 1/m

  LayerWeights weights;

  /// Faces touching a Steiner vertex, or seen by fewer rays, are unknown.
  int min_rays = 3;
  /// The evidence model behind the uncertain class (YAML section `evidence`).
  EvidenceModel evidence;

  /// Gravity direction (pointing down) in the map frame; nullopt = estimate from the camera poses.
  std::optional<Eigen::Vector3d> gravity_W;

  // Sensor mounting (trajectory evidence, trajectory_evidence.h). A property of the sensor rig,
  // not of the robot type: unset unless the rig is known, and then estimated from the data.
  /// Height of the sensor (the keyframes' camera centre) above the ground contact plane, metres.
  std::optional<double> sensor_height_m;
  /// Full sensor-to-base transform: the sensor's pose in the base frame B (origin on the ground
  /// contact plane at the footprint's centre, x forward, y left, z up; ROS base_footprint), as a
  /// ROS base_link -> camera transform gives it; translation in metres. Its translation's z is
  /// the sensor height (`sensor_height_m`, if also given, must equal it). Without it the contact
  /// patch is centred under the sensor, heading along the sensor's forward axis.
  std::optional<Eigen::Isometry3d> T_B_S;
  /// The mounting's sensor height: `sensor_height_m`, else T_B_S's z, else nullopt.
  std::optional<double> mountedSensorHeightM() const;

  /// Radius of the smallest disc around the footprint's centre that contains it.
  double footprintCircumradiusM() const;
  /// Inflation term in [0, 1] of a geodesic distance (metres) to the nearest lethal face: 1
  /// within `inscribed_radius_m`, exp(-cost_scaling_factor * (d - inscribed_radius_m)) up to
  /// `inflation_radius_m`, 0 beyond (and for NaN).
  double inflationTerm(double distance_m) const;

  /// @throw std::invalid_argument listing every out-of-range field, each as
  ///        "key: value (expected range)".
  void validate() const;
};

}  // namespace terramesh::traversability
