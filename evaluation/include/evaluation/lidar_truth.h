#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "evaluation/mesh_evaluation.h"

namespace terramesh::evaluation {

/// Which LiDAR returns of a KITTI odometry sequence serve as depth ground truth.
struct LidarTruthOptions {
  /// KITTI poses (cam0-to-world, 12 numbers per line); frame i on line i.
  std::filesystem::path poses_path;
  /// Frames first_frame..last_frame (inclusive) that have a scan in velodyne/.
  std::size_t first_frame = 0;
  std::size_t last_frame = 0;
  /// Keep only returns that cam0 of the same frame sees (inside its image, in front): the part of
  /// the scene a camera-based map can have reconstructed.
  bool camera_view_only = true;
  /// Vertical field of the scanner (KITTI's HDL-64E: +2.0 to -24.9 degrees), for covers().
  double max_elevation_deg = 2.0;
  double min_elevation_deg = -24.9;
};

/// LiDAR ground truth in the world of the poses (cam0 of frame 0, metres).
struct LidarTruth {
  std::vector<DepthRay> rays;                    ///< sensor origin -> return, one per kept return
  std::vector<Eigen::Vector3d> returns_W;        ///< every return within max depth, seen by cam0 or not
  std::vector<Eigen::Isometry3d> world_from_sensor;  ///< one per frame read
  std::vector<Eigen::Isometry3d> world_from_camera;  ///< cam0, one per frame read
  std::size_t returns_read = 0;  ///< before the camera-view and depth filters
  double max_elevation_deg = 2.0;
  double min_elevation_deg = -24.9;

  /// Whether some frame's scanner could have measured `p_W`: within `max_depth_m` of the sensor,
  /// inside its vertical field, and (when `camera` is given) seen by that frame's cam0. Where this
  /// is false the LiDAR says nothing about a reconstructed surface.
  bool covers(const Eigen::Vector3d& p_W, double max_depth_m, const PinholeCamera* camera) const;
};

/// Reads the scans `velodyne/NNNNNN.bin` of `sequence_directory` (with its `calib.txt`) for the
/// selected frames: each return becomes a ray from the sensor origin, T_W_cam0(frame) * Tr, to the
/// return, kept when within config.max_depth_m (and seen by cam0 when asked).
/// @throw terramesh::InputError naming the file for a missing or corrupt scan, calib or poses
///        file, or when no scan is selected.
LidarTruth readLidarTruth(const std::filesystem::path& sequence_directory, const LidarTruthOptions& options,
                          const PinholeCamera& camera, const DepthComparisonConfig& config);

}  // namespace terramesh::evaluation
