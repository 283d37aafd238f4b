#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "mesher/keyframe.h"

namespace terramesh::datasets {

/// How a LiDAR reader (KITTI sequences, ROS bags of untracked returns) thins each scan and merges
/// it into the points of the scans before it. The defaults suit a LiDAR driven through a street
/// (docs/formats.md, "LiDAR scans"); `everyReturn()` keeps every return as its own point.
struct LidarScanOptions {
  /// Keep returns whose distance from the sensor is in [min_range_m, max_range_m] (with voxels:
  /// whose voxel's centre is). 40 m is the mesher's default max_camera_distance_m: a farther
  /// return would make a point with no ray.
  double min_range_m = 0.0;
  double max_range_m = 40.0;
  /// Edge of the world voxels, in metres (0: off, every return is its own point seen once). Each
  /// scan keeps one return per voxel, the one nearest the voxel's centre; a voxel's first kept
  /// return is its point (id and position) for good, and a later scan's return in that voxel is
  /// another view of it.
  double voxel_size_m = 0.15;
  /// A return in a voxel whose point already has this many views adds no view (no ray): free
  /// space is carved by the first rays to each voxel, and the rays kept grow with the area
  /// seen, not with the scans (0: every scan's return is a view). Ignored when voxel_size_m is 0.
  /// 2: a second ray from a later pose to each voxel (docs/benchmarks.md, "LiDAR scans", for 1-3).
  std::uint32_t max_views_per_point = 2;

  /// No range limit, no voxels: the readers' behaviour for callers that want the raw returns.
  static LidarScanOptions everyReturn();
  /// Every problem with these options, one sentence each (empty when valid).
  std::vector<std::string> problems() const;
  /// Whether a return at squared distance `range_sq` (m^2) from the sensor is kept.
  bool inRange(double range_sq) const {
    return range_sq >= min_range_m * min_range_m && range_sq <= max_range_m * max_range_m;
  }
};

/// The Steiner lattice spacing LiDAR readers advise (SlamStream::recommended_steiner_step_m),
/// metres. A scan's rays fill the space within range; with the mesher's 10 m lattice the surface
/// closes what no ray reached (between a scan's rings, behind its far returns) with long faces
/// between returns, which touch no Steiner vertex and so count as measured. With nodes 2 m apart
/// those closures stay near the data and touch lattice nodes (interpolated), and a scan's
/// enclosing set shrinks with the lattice. docs/benchmarks.md, "LiDAR scans", has the spacings
/// measured.
inline constexpr double kLidarSteinerStepM = 2.0;

/// What a LidarScanFilter did, summed over the scans it filtered.
struct LidarScanCounts {
  std::size_t scans = 0;
  std::size_t returns = 0;       ///< observations given
  std::size_t out_of_range = 0;  ///< dropped by the range limits
  /// dropped: another return of the scan was nearer its voxel's centre
  std::size_t same_voxel = 0;
  std::size_t over_view_cap = 0;  ///< dropped: their voxel's point had max_views_per_point views
  std::size_t new_points = 0;     ///< kept as the first view of a voxel
  std::size_t merged_views = 0;   ///< kept as another view of an earlier scan's point
  std::size_t observations() const { return new_points + merged_views; }
};

/// The scans of one LiDAR stream in order: each scan's returns thinned to one per world voxel and
/// merged into the voxel's point (LidarScanOptions). Point ids are the voxels' keys
/// (geometry::packCell3 of the voxel), so the same returns give the same ids whichever reader
/// read them, and filtering a filtered stream again changes nothing. Memory: one record per
/// voxel seen (its key, position and view count), about 60 bytes.
class LidarScanFilter {
 public:
  /// @throw std::invalid_argument if `options` are invalid (see problems()).
  explicit LidarScanFilter(const LidarScanOptions& options);

  /// Replaces `scan.observations` (world positions, metres; the scan's sensor at
  /// scan.position_W_C) by the kept ones, in the order of the returns they come from: with
  /// voxels, one per voxel at its point's position with its point's id; without, the returns in
  /// range as they were. O(returns) expected.
  /// @throw std::out_of_range if a kept return's voxel index does not fit packCell3 (a return
  ///        more than 2^20 voxels from the world origin); its voxels and points are then
  ///        unchanged (the counts may have grown).
  void filter(mesher::Keyframe& scan);

  /// Counts `returns` that a reader dropped by options().inRange before filter() (the KITTI
  /// reader, ahead of its random subset), so that counts() and describe() cover them.
  void countDroppedOutOfRange(std::size_t returns) {
    counts_.returns += returns;
    counts_.out_of_range += returns;
  }

  const LidarScanOptions& options() const { return options_; }
  /// Summed over the scans filtered so far.
  const LidarScanCounts& counts() const { return counts_; }
  /// Voxels holding a point.
  std::size_t voxels() const { return points_.size(); }
  /// One sentence for SlamStream::reader_notes: the options and counts.
  std::string describe() const;

 private:
  struct VoxelPoint {
    Eigen::Vector3d position_W;
    std::uint32_t views = 0;
  };
  /// The return of the current scan nearest its voxel's centre so far.
  struct Candidate {
    std::uint64_t key = 0;
    std::size_t index = 0;
    double centre_distance_sq = 0;
  };
  std::vector<Candidate> nearestInVoxels(const mesher::Keyframe& scan);

  LidarScanOptions options_;
  LidarScanCounts counts_;
  std::unordered_map<std::uint64_t, VoxelPoint> points_;
  std::unordered_map<std::uint64_t, std::size_t> scratch_;  ///< voxel key -> candidate, this scan
};

}  // namespace terramesh::datasets
