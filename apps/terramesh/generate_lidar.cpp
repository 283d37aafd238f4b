#include "generate_lidar.h"

#include <algorithm>
#include <chrono>
#include <sstream>

#include "datasets/kitti_sequence_writer.h"
#include "progress_bar.h"

namespace terramesh::cli {

namespace {

/// A whole number > 0 (CLI11's own message for "2.5" says only that it could not convert).
CLI::Validator positiveInteger() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.size() <= 18 &&
                            text.find_first_not_of("0123456789") == std::string::npos;
        return digits && std::stoull(text) > 0 ? std::string()
                                               : "expects a whole number > 0, got \"" + text + "\"";
      },
      "POSITIVE_INTEGER");
}

}  // namespace

void addLidarOptions(CLI::App& app, LidarOptions& options) {
  const datasets::LidarSimulationConfig defaults;
  std::ostringstream speed_help;
  speed_help << "--lidar: platform speed along the trajectory; scans are V / " << defaults.rate_hz
             << " Hz apart (default " << defaults.speed_m_per_s << ")";
  std::ostringstream noise_help;
  noise_help << "--lidar: standard deviation of the range error (default "
             << defaults.range_noise_std_m << ")";
  app.add_flag(
      "--lidar", options.enabled,
      "also write DIR/lidar/, a 64-beam 10 Hz LiDAR along the trajectory as a KITTI odometry "
      "sequence (velodyne/*.bin, poses.txt, times.txt, calib.txt) that `terramesh mesh DIR/lidar` "
      "reads");
  app.add_option("--lidar-scans", options.scans,
                 "--lidar: at most N scans (default: as many as the trajectory holds)")
      ->option_text("N")
      ->check(positiveInteger());
  app.add_option("--lidar-speed-m-per-s", options.speed_m_per_s, speed_help.str())
      ->option_text("V")
      ->check(positiveNumber());
  app.add_option("--lidar-range-noise-m", options.range_noise_m, noise_help.str())
      ->option_text("S")
      ->check(nonNegativeNumber());
}

std::optional<datasets::LidarSimulationConfig> lidarConfigFrom(const LidarOptions& options,
                                                               std::uint64_t seed) {
  if (!options.enabled) {
    const char* given = options.scans           ? "--lidar-scans"
                        : options.speed_m_per_s ? "--lidar-speed-m-per-s"
                        : options.range_noise_m ? "--lidar-range-noise-m"
                                                : nullptr;
    if (given != nullptr) throw UsageError(std::string("generate: ") + given + " needs --lidar");
    return std::nullopt;
  }
  datasets::LidarSimulationConfig config;
  config.seed = seed;
  if (options.speed_m_per_s) config.speed_m_per_s = *options.speed_m_per_s;
  if (options.range_noise_m) config.range_noise_std_m = *options.range_noise_m;
  config.validate();
  return config;
}

std::vector<Eigen::Isometry3d> lidarPosesFor(const LidarOptions& options,
                                             const datasets::SyntheticScene& scene,
                                             const datasets::TriangleBvh& bvh,
                                             const datasets::LidarSimulationConfig& config) {
  const std::size_t limit = options.scans ? static_cast<std::size_t>(*options.scans) : 0;
  if (datasets::lidarScanCount(scene, config, limit) > datasets::kMaxLidarScans) {
    std::ostringstream message;
    message << "generate: --lidar-speed-m-per-s " << config.speed_m_per_s << " gives more than "
            << datasets::kMaxLidarScans
            << " scans along this trajectory: give a higher speed or --lidar-scans N";
    throw UsageError(message.str());
  }
  return datasets::lidarScanPoses(scene, bvh, config, limit);
}

LidarRunSummary writeLidarSequence(const std::filesystem::path& directory,
                                   const datasets::SyntheticScene& scene,
                                   const datasets::TriangleBvh& bvh,
                                   const datasets::LidarSimulationConfig& config,
                                   const std::vector<Eigen::Isometry3d>& poses_T_W_S, bool quiet) {
  const auto started = std::chrono::steady_clock::now();
  const datasets::LidarSimulator simulator(scene.ground_truth, bvh, config);
  datasets::KittiSequenceWriter writer(directory);
  LidarRunSummary summary;
  std::vector<std::size_t> returns_per_scan;
  std::optional<ProgressBar> progress;
  if (!quiet) progress.emplace("lidar", poses_T_W_S.size());
  for (std::size_t i = 0; i < poses_T_W_S.size(); ++i) {
    const datasets::LidarScan scan = simulator.scan(poses_T_W_S[i], i);
    writer.addScan(scan.returns, scan.T_W_S, scan.time_s);
    summary.totals.rays += scan.stats.rays;
    summary.totals.returns += scan.stats.returns;
    summary.totals.misses += scan.stats.misses;
    summary.totals.out_of_range += scan.stats.out_of_range;
    returns_per_scan.push_back(scan.stats.returns);
    if (progress) progress->update(i + 1);
  }
  writer.finish();
  summary.scans = returns_per_scan.size();
  if (!returns_per_scan.empty()) {
    const auto middle =
        returns_per_scan.begin() + static_cast<std::ptrdiff_t>(returns_per_scan.size() / 2);
    std::nth_element(returns_per_scan.begin(), middle, returns_per_scan.end());
    summary.median_returns_per_scan = *middle;
  }
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return summary;
}

std::string describeLidar(const datasets::LidarSimulationConfig& config,
                          const LidarRunSummary& summary) {
  std::ostringstream out;
  out.precision(10);
  out << "lidar_directory lidar\nlidar_beams " << config.beam_count << "\nlidar_elevation_deg "
      << config.upper_elevation_deg << ' ' << config.lower_elevation_deg
      << "\nlidar_columns_per_revolution " << config.columns_per_revolution << "\nlidar_range_m "
      << config.min_range_m << ' ' << config.max_range_m << "\nlidar_range_noise_std_m "
      << config.range_noise_std_m << "\nlidar_rate_hz " << config.rate_hz
      << "\nlidar_mount_height_m " << config.mount_height_m << "\nlidar_speed_m_per_s "
      << config.speed_m_per_s << "\nlidar_scans " << summary.scans << "\nlidar_rays "
      << summary.totals.rays << "\nlidar_returns " << summary.totals.returns << "\nlidar_misses "
      << summary.totals.misses << "\nlidar_out_of_range " << summary.totals.out_of_range
      << "\nlidar_median_returns_per_scan " << summary.median_returns_per_scan << '\n';
  return out.str();
}

}  // namespace terramesh::cli
