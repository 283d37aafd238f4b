#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>

#include "mesher/triangle_mesh.h"

namespace terramesh::datasets {

/// A similarity x' = s R x + t: maps a SLAM map (arbitrary scale) into a metric frame.
struct SimilarityTransform {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return scale * (rotation * x) + translation; }
  /// The mesh with every vertex mapped (faces and flags unchanged; a similarity keeps orientation).
  mesher::TriangleMesh apply(const mesher::TriangleMesh& mesh) const;
  /// A camera-to-world rotation mapped into the target frame.
  Eigen::Quaterniond apply(const Eigen::Quaterniond& rotation_W_C) const;
};

/// Reads a similarity as in ../shared/data/kitti00_lidar/piazza_sim3_to_gt*.txt: lines
/// `s SCALE`, `R r00 r01 r02 r10 ... r22` (row-major) and `t tx ty tz`; `#` starts a comment; lines
/// with other keys (e.g. `matched_frames`) are ignored.
/// @throw terramesh::InputError naming the file and line: missing s, R or t, a wrong field count,
///        a non-finite or non-positive scale, R not a rotation (within 1e-3).
SimilarityTransform readSimilarityTransform(const std::filesystem::path& path);

}  // namespace terramesh::datasets
