#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/kitti_trajectory.h"
#include "datasets/labeled_mesh.h"

namespace terramesh::datasets {

/// Frames of every synthetic trajectory are this far apart in time (KITTI's camera rate).
inline constexpr double kSyntheticFrameRateHz = 10.0;

/// What a hazard of the hazards scene is.
enum class HazardKind : std::uint8_t {
  kSlab = 0,       ///< a raised platform with vertical edges, no way up
  kPlateau = 1,    ///< a raised plateau with vertical edges and one ramp up onto it
  kPit = 2,        ///< a lowered area with vertical edges (a negative obstacle)
  kThinWall = 3,   ///< a thin upright wall with two free ends
  kRock = 4,       ///< a small rock sitting on the ground
};

/// Lower-case name of a kind ("slab", "plateau", "pit", "thin_wall", "rock").
std::string_view toString(HazardKind kind);

/// One hazard of a generated scene, with a start and a goal placed to test it (z-up W, metres).
/// Whether a robot can get from start to goal is for the per-robot truth to decide.
struct SceneHazard {
  /// Unique in its scene: "slab_1", "plateau", "pit", "wall_1", "rock_3".
  std::string name;
  HazardKind kind = HazardKind::kSlab;
  /// Centre of its footprint at ground level (z = 0).
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  /// Footprint along x and y (axis-aligned; a rock: its diameter at ground level, both).
  Eigen::Vector2d size_m = Eigen::Vector2d::Zero();
  /// Height of its top above the ground; negative for a pit (minus its depth).
  double height_m = 0.0;
  /// Plateau only: the ramp's slope, its footprint along x (the ramp rises along +x up to the
  /// plateau's -x edge) and its width along y.
  double ramp_slope_deg = 0.0;
  double ramp_length_m = 0.0;
  double ramp_width_m = 0.0;
  /// Where a robot stands to cross it (on the ground, on its top or on the pit's floor).
  Eigen::Vector3d start_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d goal_W = Eigen::Vector3d::Zero();
};

/// A synthetic world: the labelled ground-truth surface and the camera's true trajectory.
///
/// Cameras follow the KITTI/OpenCV convention: x right, y down, z forward. Units are metres.
struct SyntheticScene {
  std::string name;
  LabeledMesh ground_truth;
  /// True camera poses T_W_C, one per frame at kSyntheticFrameRateHz.
  PoseList frames_T_W_C;
  /// Unit vector of W pointing up (against gravity): (0, 0, 1) in the procedural scenes, whose W
  /// is z-up; (0, -1, 0) when the street follows KITTI poses, whose W is y-down.
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  /// One line saying what W is.
  std::string frame_description;
  /// The hazards placed on purpose (hazards scene; empty for the others).
  std::vector<SceneHazard> hazards;
};

/// A street: a road with camber and grades, 0.15 m curbs, sidewalks, a grass verge, building
/// facades with gaps, parked cars, trees and loading ramps, along a procedural gently curving
/// road or along a given camera trajectory (KITTI poses).
struct StreetSceneConfig {
  /// Procedural road length; with a given trajectory, the trajectory is cut after this distance
  /// travelled (0: keep it all).
  double length_m = 300.0;
  std::uint64_t seed = 1;
  /// Scales the number of cars, trees and buildings (1: a typical city street; 0: none).
  double object_density = 1.0;
  double road_width_m = 7.0;
  /// Cross slope of the road from its crown down to each curb, in percent.
  double camber_percent = 2.0;
  /// Largest longitudinal grade of the procedural road, in percent (unused with a trajectory).
  double max_grade_percent = 4.0;
  /// Smallest turn radius of the procedural road.
  double min_turn_radius_m = 80.0;
  double curb_height_m = 0.15;
  double sidewalk_width_m = 2.5;
  /// Grass between the sidewalk and the buildings' line and beyond.
  double verge_width_m = 4.0;
  /// Height of the camera above the road crown (KITTI: 1.65 m).
  double camera_height_m = 1.65;
  /// Procedural camera speed; frames are speed / kSyntheticFrameRateHz apart.
  double speed_m_per_s = 8.0;
  /// Inclination of the loading ramps' top surface.
  double ramp_slope_deg = 8.0;
  /// One ramp every this distance along the road (at least one per scene).
  double ramp_spacing_m = 150.0;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Builds a street. Without `trajectory_T_W_C` the road is procedural, in a z-up W, and the
/// camera drives on its centre line; with it (KITTI poses: y-down W), the road's crown runs
/// `camera_height_m` below the (smoothed) camera path, repeated passes over the same road share
/// one road surface, and sidewalks are cut where another pass crosses (junctions).
/// @throw std::invalid_argument for a bad config or a trajectory of fewer than 2 distinct poses.
SyntheticScene buildStreetScene(const StreetSceneConfig& config, const PoseList& trajectory_T_W_C = {});

/// Rolling terrain along a dirt track, with a steep bank, a ditch and rocks (z-up W).
struct OffroadSceneConfig {
  double length_m = 200.0;
  std::uint64_t seed = 1;
  /// Scales the number of rocks (1: one per 4 m of track).
  double object_density = 1.0;
  /// Terrain extends this far to each side of the track.
  double half_width_m = 30.0;
  double track_width_m = 3.0;
  /// Steepest slope of the rolling hills.
  double hill_slope_deg = 10.0;
  /// Steepest slope of the bank (before the hills add theirs) and its height.
  double bank_slope_deg = 34.0;
  double bank_height_m = 4.0;
  /// Depth and steepest side slope of the ditch beside the track.
  double ditch_depth_m = 1.0;
  double ditch_slope_deg = 30.0;
  double camera_height_m = 1.6;
  double speed_m_per_s = 4.0;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Builds the off-road scene. @throw std::invalid_argument for a bad config.
SyntheticScene buildOffroadScene(const OffroadSceneConfig& config);

/// A two-level parking garage (z-up W, origin at a ground-floor corner): floors, ceilings,
/// perimeter walls, a grid of pillars on both levels, a straight ramp between the levels through
/// an opening in the upper floor, and parked cars. The camera loops around pillars on both
/// levels, so free space has genus > 0.
struct GarageSceneConfig {
  /// Extent of the garage along x (the ramp runs along x); at least 40 m.
  double length_m = 48.0;
  std::uint64_t seed = 1;
  /// Probability scale of a parking bay being taken by a car (1: half the bays).
  double object_density = 1.0;
  /// Floor to ceiling on each level; the slab between levels is `slab_thickness_m` thick.
  double clear_height_m = 2.8;
  double slab_thickness_m = 0.3;
  double pillar_size_m = 1.0;
  double camera_height_m = 1.5;
  double speed_m_per_s = 2.5;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Width (along y) of every garage; pillars stand every 8 m.
inline constexpr double kGarageWidthM = 32.0;
/// Length of the garage ramp along x; its slope is atan((clear height + slab) / this).
inline constexpr double kGarageRampLengthM = 20.0;

/// Builds the garage. @throw std::invalid_argument for a bad config.
SyntheticScene buildGarageScene(const GarageSceneConfig& config);

/// The cases sparse SLAM maps get wrong, on a flat ground plane (z = 0; z-up W, origin at a
/// corner of the ground): two raised slabs (edges 0.3-0.5 m), a plateau with a ramp just under
/// 20 degrees up onto it, a pit 0.3-0.6 m deep, two thin walls with free ends and small rocks
/// (0.3-0.9 m). The camera drives a rounded rectangular loop past all of them. The seed jitters
/// every hazard's position and size within those ranges; SyntheticScene::hazards lists them.
struct HazardsSceneConfig {
  std::uint64_t seed = 1;
  /// Scales the number of rocks (1: kHazardsRockCount of them; 0: none; at most 2).
  double object_density = 1.0;
  /// Camera height above the ground (a ground robot's camera mast).
  double camera_height_m = 1.4;
  double speed_m_per_s = 2.0;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Extent of the hazards scene's ground along x and y.
inline constexpr double kHazardsLengthM = 72.0;
inline constexpr double kHazardsWidthM = 36.0;
/// Rocks at object_density 1.
inline constexpr int kHazardsRockCount = 6;

/// Builds the hazards scene. @throw std::invalid_argument for a bad config.
SyntheticScene buildHazardsScene(const HazardsSceneConfig& config);

}  // namespace terramesh::datasets
