#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "datasets/lidar_scan_filter.h"
#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// How a poses file is written.
enum class PoseFileFormat {
  kAuto,   ///< by the field count of the first pose line: 12 KITTI, 8 TUM
  kKitti,  ///< KITTI odometry: line i = frame i, 12 numbers, the 3x4 cam0-to-world matrix by rows
  kTum,    ///< TUM: `timestamp tx ty tz qx qy qz qw`, matched to frames through times.txt (or
           ///< by order without it: see readKittiOdometry)
};

/// What readKittiOdometry reads from a sequence, and how it thins the returns.
struct KittiOdometryOptions {
  /// Poses of cam0 in the world (KITTI or TUM); empty: findKittiPoses(sequence directory).
  std::filesystem::path poses_path;
  PoseFileFormat poses_format = PoseFileFormat::kAuto;
  /// Frames first_frame, first_frame + frame_step, ... up to last_frame (inclusive) that have a
  /// scan in velodyne/.
  std::size_t first_frame = 0;
  std::size_t last_frame = std::numeric_limits<std::size_t>::max();
  std::size_t frame_step = 1;
  /// Keep at most this many returns of each scan, a uniform random subset (0: keep all).
  std::size_t max_returns_per_scan = 0;
  /// Seed of that subset; scan F uses a generator seeded from (seed, F), so a frame's subset
  /// does not depend on the other frames read.
  std::uint64_t seed = 1;
  /// Range limits, voxels and merging across scans (LidarScanFilter). The reader's default keeps
  /// every return; `LidarScanOptions()` holds the LiDAR defaults that `terramesh` uses.
  LidarScanOptions lidar = LidarScanOptions::everyReturn();
  /// TUM poses: largest gap between a scan's time (times.txt) and the nearest pose.
  double pose_time_tolerance_s = 0.01;

  /// Every problem with these options (empty when valid).
  std::vector<std::string> problems() const;
};

/// Whether `directory` looks like a KITTI odometry sequence: a `velodyne/` folder and `calib.txt`.
bool isKittiSequenceDirectory(const std::filesystem::path& directory);

/// The poses of a KITTI sequence directory: `poses.txt` in it, else `../../poses/NAME.txt` (the
/// official layout `dataset/sequences/NAME/` beside `dataset/poses/NAME.txt`); nullopt if none.
std::optional<std::filesystem::path> findKittiPoses(
    const std::filesystem::path& sequence_directory);

/// The format of a poses file, from the field count of its first non-comment line.
/// @throw terramesh::InputError if the file cannot be read or the count is neither 12 nor 8.
PoseFileFormat detectPoseFileFormat(const std::filesystem::path& path);

/// Reads a KITTI odometry poses file: line i is frame i's cam0-to-world pose (3x4, by rows).
/// @throw terramesh::InputError naming the file and line (field count, non-finite number,
///        non-rotation).
std::vector<Eigen::Isometry3d> readKittiPoses(const std::filesystem::path& path);

/// Reads `Tr` (Velodyne to cam0, 3x4 by rows) from a KITTI odometry `calib.txt`.
/// @throw terramesh::InputError naming the file (and line) if Tr is missing or malformed.
Eigen::Isometry3d readKittiVelodyneToCam0(const std::filesystem::path& calib_path);

/// Reads a KITTI `times.txt`: line i is frame i's time in seconds.
/// @throw terramesh::InputError naming the file and line.
std::vector<double> readKittiTimes(const std::filesystem::path& path);

/// One Velodyne return in the sensor frame (x forward, y left, z up), metres, and reflectance.
struct VelodyneReturn {
  Eigen::Vector3f position_S = Eigen::Vector3f::Zero();
  float reflectance = 0.0f;
};

/// Reads a KITTI Velodyne scan: float32 little-endian `x y z reflectance` records.
/// @throw terramesh::InputError naming the file and its size if that is not a multiple of 16,
///        or the byte offset of a non-finite coordinate.
std::vector<VelodyneReturn> readVelodyneScan(const std::filesystem::path& path);

/// Reads a KITTI odometry sequence as a LiDAR stream, one keyframe event per selected scan
/// (`velodyne/NNNNNN.bin`, frame = NNNNNN), in frame order. The scan's pose is
/// T_W_S = T_W_cam0(frame) * Tr: the keyframe centre is the sensor origin in the world, its
/// rotation the Velodyne-to-world rotation, and every kept return is an observation at
/// T_W_S * x_S with a unique point id (frame << 32 | index of the return in its file), so that
/// each return is a ray from the sensor. `options.lidar` then limits the range (before the
/// random subset of max_returns_per_scan) and, with voxels, keeps one return per voxel and scan
/// and merges the scans' returns into the voxels' points (ids: the voxel keys, LidarScanFilter);
/// `SlamStream::reader_notes` says what it kept. World = cam0 of the poses' first frame (metres): the
/// stream says metres_per_unit = 1 and recommended_min_views = 1. keyframe_names are the scan
/// files' names. TUM poses are matched to scans through `times.txt` in the directory; without it
/// (KITTI's Velodyne download has none), by order when there is one pose per scan in velodyne/.
/// KITTI poses need no times.txt.
/// @throw std::invalid_argument if `options` are invalid (see problems()).
/// @throw terramesh::InputError naming the file: no scan selected, a frame without a pose, a
///        corrupt scan, bad calib, poses or times.
SlamStream readKittiOdometry(const std::filesystem::path& sequence_directory,
                             const KittiOdometryOptions& options = {});

}  // namespace terramesh::datasets
