#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <filesystem>
#include <vector>

#include "datasets/kitti_odometry_reader.h"

namespace terramesh::datasets {

/// The Velodyne-to-cam0 transform (T_cam0_S) that KittiSequenceWriter writes by default: KITTI's
/// axes (Velodyne x forward, y left, z up; cam0 x right, y down, z forward) exactly, and KITTI
/// 00's offset rounded to centimetres: cam0 0.29 m ahead of the sensor, 0.05 m below it and
/// 0.01 m to its right.
Eigen::Isometry3d kittiLikeVelodyneToCam0();

/// Writes KITTI Velodyne scan records: float32 little-endian `x y z reflectance`, 16 bytes a
/// return, in the order given. Written atomically.
/// @throw std::runtime_error naming the file if writing fails.
void writeVelodyneScan(const std::filesystem::path& path,
                       const std::vector<VelodyneReturn>& returns_S);

/// Writes a LiDAR sequence as a KITTI odometry sequence directory that readKittiOdometry reads:
/// `velodyne/NNNNNN.bin` (frame i = the i-th scan added), `poses.txt` (cam0-to-world, KITTI
/// format, line i = frame i: T_W_S * inverse(T_cam0_S)), `times.txt` (line i = frame i's time in
/// seconds) and `calib.txt` (one line, `Tr:` T_cam0_S by rows). Scans go to disk as they are
/// added, so a long sequence never sits in memory. Every file is written atomically; calib.txt
/// last, so that a directory whose writing was interrupted is not taken for a sequence
/// (isKittiSequenceDirectory needs it).
///
/// Not thread-safe: one writer per directory.
class KittiSequenceWriter {
 public:
  /// Creates `directory` and `directory/velodyne` if missing, and removes `calib.txt` from an
  /// earlier sequence there (finish() writes the new one).
  /// @throw std::filesystem::filesystem_error if they cannot be created or calib.txt removed.
  explicit KittiSequenceWriter(std::filesystem::path directory,
                               const Eigen::Isometry3d& T_cam0_S = kittiLikeVelodyneToCam0());

  /// Writes the next frame's scan (returns in the sensor frame) and records its pose and time.
  /// @throw std::runtime_error if writing fails; std::logic_error after finish().
  void addScan(const std::vector<VelodyneReturn>& returns_S, const Eigen::Isometry3d& T_W_S,
               double time_s);

  /// Removes `velodyne/NNNNNN.bin` files of frames past the last one added (left by an earlier,
  /// longer run: the reader would take them), then writes poses.txt, times.txt and calib.txt.
  /// @throw std::runtime_error if writing fails; std::logic_error if no scan was added or
  ///        finish() was called before.
  void finish();

  /// Number of scans added so far.
  std::size_t scanCount() const { return poses_T_W_cam0_.size(); }

  /// `velodyne/NNNNNN.bin` of frame `frame` (six digits, as KITTI names them).
  static std::filesystem::path scanFileName(std::size_t frame);

 private:
  void removeStaleScans() const;

  std::filesystem::path directory_;
  Eigen::Isometry3d T_cam0_S_;
  std::vector<Eigen::Isometry3d> poses_T_W_cam0_;
  std::vector<double> times_s_;
  bool finished_ = false;
};

}  // namespace terramesh::datasets
