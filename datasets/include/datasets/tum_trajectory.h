#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <vector>

namespace terramesh::datasets {

/// A sensor pose at a time.
struct StampedPose {
  double time_s = 0.0;
  /// Sensor to world: x_W = pose_W_C * x_C.
  Eigen::Isometry3d pose_W_C = Eigen::Isometry3d::Identity();
};

/// Reads a TUM RGB-D trajectory file: one pose a line, `timestamp tx ty tz qx qy qz qw` (the
/// sensor's position and orientation in the world, i.e. sensor to world), '#' comments and blank
/// lines ignored. Times must not decrease; quaternions must have unit norm within 1e-2.
/// @throw terramesh::InputError naming the file and the line (wrong field count, a non-number or
///        non-finite number, a non-unit quaternion, a time going back, or no pose at all).
std::vector<StampedPose> readTumTrajectory(const std::filesystem::path& path);

/// The pose whose time is nearest `time_s`, if one is within `tolerance_s`; `poses` sorted by
/// time. O(log n).
const StampedPose* nearestPose(const std::vector<StampedPose>& poses, double time_s,
                               double tolerance_s);

}  // namespace terramesh::datasets
