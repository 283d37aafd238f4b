#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <filesystem>
#include <vector>

namespace terramesh::datasets {

/// Camera poses T_W_C, one per frame: each maps camera-frame points into the world frame W.
/// (KITTI pose files are read by readKittiPoses in datasets/kitti_odometry_reader.h.)
using PoseList = std::vector<Eigen::Isometry3d>;

/// Writes poses as a KITTI odometry pose file: one line per pose, the 12 numbers of the
/// row-major 3x4 matrix [R | t] of T_W_C, full double precision. Written atomically.
/// @throw std::runtime_error if writing fails.
void writeKittiPoses(const std::filesystem::path& path, const PoseList& poses_T_W_C);

/// Frames [first, last) of `poses`; `last` is clamped to the size.
/// @throw std::invalid_argument if the clamped range is empty.
PoseList selectFrames(const PoseList& poses, std::size_t first, std::size_t last);

}  // namespace terramesh::datasets
