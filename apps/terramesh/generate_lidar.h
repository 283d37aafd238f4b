#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cli_args.h"
#include "datasets/lidar_simulation.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::cli {

/// `generate --lidar`: the parsed options; unset optionals keep LidarSimulationConfig's defaults.
struct LidarOptions {
  bool enabled = false;
  std::optional<long> scans;
  std::optional<double> speed_m_per_s;
  std::optional<double> range_noise_m;
};

/// Adds --lidar and the --lidar-* options to `app`.
void addLidarOptions(CLI::App& app, LidarOptions& options);

/// The sensor's config (noise seeded by `seed`), or nothing without --lidar.
/// @throw UsageError naming the option: a --lidar-* option without --lidar, or a bad value.
std::optional<datasets::LidarSimulationConfig> lidarConfigFrom(const LidarOptions& options,
                                                               std::uint64_t seed);

/// The sensor poses of the scans along the scene's trajectory (datasets::lidarScanPoses), at most
/// --lidar-scans of them.
/// @throw UsageError naming --lidar-speed-m-per-s and --lidar-scans if that is more than
///        datasets::kMaxLidarScans; std::invalid_argument if there is no ground under the path.
std::vector<Eigen::Isometry3d> lidarPosesFor(const LidarOptions& options,
                                             const datasets::SyntheticScene& scene,
                                             const datasets::TriangleBvh& bvh,
                                             const datasets::LidarSimulationConfig& config);

/// What writing the sequence gave.
struct LidarRunSummary {
  std::size_t scans = 0;
  datasets::LidarScanStats totals;
  /// The upper median for an even count: element scans / 2 of the sorted counts.
  std::size_t median_returns_per_scan = 0;
  double seconds = 0.0;
};

/// Casts a scan at each pose and writes the sequence to `directory` as a KITTI odometry sequence
/// (datasets::KittiSequenceWriter), one scan at a time; a progress bar on a terminal unless
/// `quiet`.
LidarRunSummary writeLidarSequence(const std::filesystem::path& directory,
                                   const datasets::SyntheticScene& scene,
                                   const datasets::TriangleBvh& bvh,
                                   const datasets::LidarSimulationConfig& config,
                                   const std::vector<Eigen::Isometry3d>& poses_T_W_S, bool quiet);

/// The `lidar_*` lines of generation.txt: the sensor's parameters and the sequence's counts.
std::string describeLidar(const datasets::LidarSimulationConfig& config,
                          const LidarRunSummary& summary);

}  // namespace terramesh::cli
