#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "mesher/ids.h"

namespace terramesh::mesher {

/// One point seen by a keyframe, with the SLAM system's current estimate of its position.
struct PointObservation {
  PointId point;
  /// Current position of the point in the world frame W, in map units.
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
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
};

}  // namespace terramesh::mesher
