#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "mesher/ids.h"

namespace terramesh::mesher {

/// Where a point comes from.
enum class PointKind : std::uint8_t {
  /// A map point of the SLAM system: inserted once `MesherConfig::min_views` keyframes in range
  /// see it.
  kSlam = 0,
  /// A virtual sample of the ground the robot drove on (its contact patch under a keyframe,
  /// traversability/trajectory_evidence.h). Inserted with a single view (exempt from min_views);
  /// otherwise an ordinary point: its rays carve free space, a re-sent keyframe moves it, and it
  /// goes when no keyframe observes it any more. Its vertex key is an ordinary point key.
  kDrivenGround = 1,
  /// The underside of driven ground: a virtual vertex a fixed depth under a driven-ground sample
  /// (ground a robot drove on is solid at least that deep, a parking deck's slab included).
  /// Inserted with a single view and traces no ray: it carves nothing, and with the driven
  /// samples above it keeps a layer of matter under the drive that cameras on a level beneath
  /// cannot carve away (MapState::isFree). It moves and goes as a driven sample does.
  kDrivenUnderside = 2,
};

/// Whether a point of this kind is a virtual sample of the drive, inserted with a single view.
inline bool isDrivenKind(PointKind kind) { return kind != PointKind::kSlam; }
/// Whether a point of this kind traces visibility rays from the keyframes that observe it.
inline bool tracesRays(PointKind kind) { return kind != PointKind::kDrivenUnderside; }

/// One point seen by a keyframe, with the SLAM system's current estimate of its position.
struct PointObservation {
  PointId point;
  /// Current position of the point in the world frame W, in map units.
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  /// The point's kind; a point keeps the kind it was first observed with (a later observation
  /// with another kind is refused).
  PointKind kind = PointKind::kSlam;
};

/// A box of observed free space in the world frame W (map units): where the robot's body was
/// (traversability/trajectory_evidence.h). A cell that meets it is free space, unless its centroid
/// lies below the driven ground one of its corners stands for (MapState::isFree).
struct FreeBox {
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  /// Rotates box-frame vectors into the world frame.
  Eigen::Quaterniond rotation_W_B = Eigen::Quaterniond::Identity();
  /// Half its extent along each of its axes (positive).
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
};

/// A SLAM keyframe: a camera pose and the points it observes.
///
/// Sending a keyframe whose id was already sent replaces it: a new pose (a corrected keyframe)
/// and a new observation list, which replaces the old one.
struct Keyframe {
  KeyframeId id;
  /// Camera centre in the world frame W, in map units.
  Eigen::Vector3d position_W_C = Eigen::Vector3d::Zero();
  /// Camera orientation: rotates camera-frame vectors into the world frame.
  Eigen::Quaterniond rotation_W_C = Eigen::Quaterniond::Identity();
  std::vector<PointObservation> observations;
  /// Free space this keyframe vouches for beyond its rays (the robot's body volume; empty for a
  /// SLAM keyframe). Re-sending the keyframe replaces them; removing it removes them.
  std::vector<FreeBox> free_boxes;
};

}  // namespace terramesh::mesher
