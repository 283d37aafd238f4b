#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "evaluation/robot_limits.h"

namespace terramesh::evaluation {

/// Why a ground-truth face is or is not traversable for a robot: the first rule it fails (in
/// the order of labelTraversability). The numeric values are written to reports: never renumber.
enum class TruthReason : std::uint8_t {
  kTraversable = 0,
  kNotGround = 1,        ///< label is wall, obstacle or ceiling
  kTooSteep = 2,         ///< true slope above max_slope_deg
  kCurbTooHigh = 3,      ///< a curb face whose height jump within the footprint exceeds max_step_m
  kLowClearance = 4,     ///< the first face straight up is closer than the robot's height
  kStepInFootprint = 5,  ///< surface rises more than max_step_m above the face's plane (below the
                         ///< robot's height) within the footprint
};
inline constexpr std::size_t kTruthReasonCount = 6;

/// Lower-case name of a reason ("traversable", "not_ground", ...).
std::string_view toString(TruthReason reason);

/// Whether a label is ground a robot may drive on: road, sidewalk, ramp, vegetation (grass and
/// terrain) and curb (curbs then also need their height within the robot's step).
bool isGroundLabel(datasets::SurfaceLabel label);

/// How the ground truth is judged.
struct GroundTruthConfig {
  /// Faces are split (longest edge first) until no edge is longer than this, in metres, so that
  /// one answer per face (judged at its centroid) holds over the whole face. 0: no split.
  double max_edge_m = 0.25;
  /// Cell size of the horizontal face index used for the footprint queries, in metres.
  double index_cell_m = 0.5;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Per-face traversability of a ground-truth surface for one robot.
struct GroundTruthTraversability {
  /// The ground truth the answers refer to (candidate faces refined, in a new order), in its
  /// own frame and metres.
  datasets::LabeledMesh mesh;
  /// One per face of `mesh`: 1 traversable, 0 not.
  std::vector<std::uint8_t> traversable;
  /// One per face: why.
  std::vector<TruthReason> reasons;
  /// Unit vector up used for slopes, heights and clearance.
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  /// The robot it was computed for.
  RobotLimits robot;

  /// Area (m^2) of the faces with each reason.
  std::array<double, kTruthReasonCount> areaByReason() const;
};

/// "Up" of a labelled ground truth, from its own labels: the area-weighted mean normal of the
/// faces whose true slope is at most `level_deg` (level ground, whose normal is up).
/// @throw std::invalid_argument if no face is that level (or their normals cancel out).
Eigen::Vector3d estimateUpFromSlopes(const datasets::LabeledMesh& truth, double level_deg = 1.0);

/// Judges every face of `truth` for `robot` (the faces passing rules 1 and 2 are first split to
/// config.max_edge_m; the others are kept whole), from the
/// ground truth alone (its geometry, labels and true slopes). A face is traversable iff
/// 1. its label is a ground label (isGroundLabel);
/// 2. its true slope is at most max_slope_deg;
/// 3. the first surface straight up from the centroid is at least height_m away;
/// 4. the footprint centred on the centroid in the face's plane (the disc, or the rectangle at
///    some heading) has no surface rising more than max_step_m (exclusive) and at most height_m
///    above that plane (heights along the face normal: the robot stands tilted on a slope);
/// 5. curb faces only: the same footprint also has no surface more than max_step_m below the
///    plane (down to height_m): the curb's height jump either way is within the step.
/// Surfaces are the ground truth's faces (walls, cars, rocks, curbs, ceilings, the ground itself).
/// O(F_refined * faces per footprint), single-threaded.
/// @throw std::invalid_argument if the robot, config or truth do not validate or `up_W` is zero.
GroundTruthTraversability labelTraversability(const datasets::LabeledMesh& truth, const RobotLimits& robot,
                                              const Eigen::Vector3d& up_W, const GroundTruthConfig& config);

}  // namespace terramesh::evaluation
