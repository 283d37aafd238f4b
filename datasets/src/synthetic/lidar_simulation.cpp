#include "datasets/lidar_simulation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "problem_list.h"
#include "rng.h"

namespace terramesh::datasets {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
/// How far below the camera the ground under the platform is searched for.
constexpr double kGroundProbeM = 20.0;
/// Separates the noise generators of the LiDAR's scans from the other consumers of the seed.
constexpr std::uint64_t kLidarNoiseStream = 0x4C69444152000000ULL;

/// Sensor axes in the camera frame (x right, y down, z forward): x_S = z_C (forward),
/// y_S = -x_C (left), z_S = -y_C (up). Columns are the sensor axes, so p_C = R_C_S p_S.
Eigen::Matrix3d cameraFromSensorRotation() {
  Eigen::Matrix3d R_C_S;
  R_C_S << 0, -1, 0,  //
      0, 0, -1,       //
      1, 0, 0;
  return R_C_S;
}

/// Cumulative arc length of the camera positions: s[i] = distance travelled to frame i.
std::vector<double> arcLengths(const PoseList& frames_T_W_C) {
  std::vector<double> s(frames_T_W_C.size(), 0.0);
  for (std::size_t i = 1; i < frames_T_W_C.size(); ++i) {
    s[i] = s[i - 1] + (frames_T_W_C[i].translation() - frames_T_W_C[i - 1].translation()).norm();
  }
  return s;
}

/// The camera pose at arc length `s_m` (clamped to the trajectory): positions interpolated
/// linearly, rotations by slerp, between the two frames around it.
Eigen::Isometry3d cameraPoseAt(const PoseList& frames_T_W_C, const std::vector<double>& s,
                               double s_m) {
  const auto after = std::upper_bound(s.begin(), s.end(), s_m);
  if (after == s.begin()) return frames_T_W_C.front();
  if (after == s.end()) return frames_T_W_C.back();
  const auto i = static_cast<std::size_t>(after - s.begin());
  const double t = (s_m - s[i - 1]) / (s[i] - s[i - 1]);  // s[i] > s_m >= s[i - 1]
  const Eigen::Quaterniond q0(frames_T_W_C[i - 1].linear());
  const Eigen::Quaterniond q1(frames_T_W_C[i].linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q0.slerp(t, q1).normalized().toRotationMatrix();
  pose.translation() =
      (1.0 - t) * frames_T_W_C[i - 1].translation() + t * frames_T_W_C[i].translation();
  return pose;
}

}  // namespace

void LidarSimulationConfig::validate() const {
  synthetic::ProblemList problems("LidarSimulationConfig");
  problems.require(beam_count >= 1, "beam_count must be >= 1");
  problems.require(upper_elevation_deg < 90 && lower_elevation_deg > -90,
                   "upper_elevation_deg and lower_elevation_deg must be in (-90, 90)");
  problems.require(upper_elevation_deg >= lower_elevation_deg,
                   "upper_elevation_deg must be >= lower_elevation_deg");
  problems.require(columns_per_revolution >= 1, "columns_per_revolution must be >= 1");
  problems.require(min_range_m >= 0 && std::isfinite(min_range_m),
                   "min_range_m must be a finite number >= 0");
  problems.require(max_range_m > min_range_m && std::isfinite(max_range_m),
                   "max_range_m must be finite and > min_range_m");
  problems.require(range_noise_std_m >= 0 && std::isfinite(range_noise_std_m),
                   "range_noise_std_m must be a finite number >= 0");
  problems.require(rate_hz > 0 && std::isfinite(rate_hz), "rate_hz must be a finite number > 0");
  problems.require(mount_height_m > 0 && mount_height_m < kGroundProbeM,
                   "mount_height_m must be in (0, 20)");
  problems.require(speed_m_per_s > 0 && std::isfinite(speed_m_per_s),
                   "speed_m_per_s must be a finite number > 0");
  problems.throwIfAny();
}

std::vector<double> lidarBeamElevationsDeg(const LidarSimulationConfig& config) {
  config.validate();
  std::vector<double> elevations(static_cast<std::size_t>(config.beam_count),
                                 config.upper_elevation_deg);
  const double span = config.upper_elevation_deg - config.lower_elevation_deg;
  for (int b = 1; b < config.beam_count; ++b) {
    elevations[static_cast<std::size_t>(b)] =
        config.upper_elevation_deg - span * b / (config.beam_count - 1);
  }
  return elevations;
}

std::vector<Eigen::Vector3d> lidarRayDirections(const LidarSimulationConfig& config) {
  const std::vector<double> elevations = lidarBeamElevationsDeg(config);
  std::vector<Eigen::Vector3d> directions;
  directions.reserve(elevations.size() * static_cast<std::size_t>(config.columns_per_revolution));
  for (int c = 0; c < config.columns_per_revolution; ++c) {
    const double azimuth = 2.0 * M_PI * c / config.columns_per_revolution;
    for (const double elevation_deg : elevations) {
      const double elevation = elevation_deg * kDegToRad;
      directions.emplace_back(std::cos(elevation) * std::cos(azimuth),
                              std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    }
  }
  return directions;
}

LidarSimulator::LidarSimulator(const LabeledMesh& truth, const TriangleBvh& bvh,
                               const LidarSimulationConfig& config)
    : truth_(truth), bvh_(bvh), config_(config), directions_S_(lidarRayDirections(config)) {
  truth.validate();
  if (bvh.faceCount() != truth.mesh.faces.size()) {
    throw std::invalid_argument("LidarSimulator: the ray caster was not built from the truth mesh");
  }
}

LidarScan LidarSimulator::scan(const Eigen::Isometry3d& T_W_S, std::size_t index) const {
  LidarScan scan;
  scan.index = index;
  scan.time_s = static_cast<double>(index) / config_.rate_hz;
  scan.T_W_S = T_W_S;
  scan.returns.reserve(directions_S_.size());
  scan.faces.reserve(directions_S_.size());
  scan.labels.reserve(directions_S_.size());
  synthetic::Rng noise(config_.seed, kLidarNoiseStream + index);
  const Eigen::Vector3d origin_W = T_W_S.translation();
  const Eigen::Matrix3d R_W_S = T_W_S.linear();
  for (const Eigen::Vector3d& direction_S : directions_S_) {
    ++scan.stats.rays;
    const auto hit = bvh_.firstHit(origin_W, R_W_S * direction_S, config_.max_range_m);
    if (!hit) {
      ++scan.stats.misses;
      continue;
    }
    const double range_m = hit->distance + config_.range_noise_std_m * noise.normal();
    if (range_m < config_.min_range_m || range_m > config_.max_range_m) {
      ++scan.stats.out_of_range;
      continue;
    }
    VelodyneReturn measured;
    measured.position_S = (range_m * direction_S).cast<float>();
    scan.returns.push_back(measured);
    scan.faces.push_back(hit->face);
    scan.labels.push_back(truth_.labels[hit->face]);
  }
  scan.stats.returns = scan.returns.size();
  return scan;
}

std::size_t lidarScanCount(const SyntheticScene& scene, const LidarSimulationConfig& config,
                           std::size_t max_scans) {
  config.validate();
  if (scene.frames_T_W_C.empty())
    throw std::invalid_argument("lidarScanCount: the scene has no frames");
  const double spacing_m = config.speed_m_per_s / config.rate_hz;
  const double whole = std::floor(arcLengths(scene.frames_T_W_C).back() / spacing_m) + 1.0;
  const double limit = max_scans > 0 ? static_cast<double>(max_scans) : whole;
  const double count = std::min(whole, limit);
  // Compared as doubles: a tiny spacing can give more scans than a size_t holds.
  return count > static_cast<double>(kMaxLidarScans) ? kMaxLidarScans + 1
                                                     : static_cast<std::size_t>(count);
}

std::vector<Eigen::Isometry3d> lidarScanPoses(const SyntheticScene& scene, const TriangleBvh& bvh,
                                              const LidarSimulationConfig& config,
                                              std::size_t max_scans) {
  const std::size_t count = lidarScanCount(scene, config, max_scans);
  if (count > kMaxLidarScans) {
    throw std::invalid_argument("lidarScanPoses: more than " + std::to_string(kMaxLidarScans) +
                                " scans (raise speed_m_per_s or give max_scans)");
  }
  if (bvh.faceCount() != scene.ground_truth.mesh.faces.size()) {
    throw std::invalid_argument(
        "lidarScanPoses: the ray caster was not built from the scene's mesh");
  }
  const std::vector<double> s = arcLengths(scene.frames_T_W_C);
  const double spacing_m = config.speed_m_per_s / config.rate_hz;
  const Eigen::Vector3d up_W = scene.up_W.normalized();
  const Eigen::Matrix3d R_C_S = cameraFromSensorRotation();
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double s_m = static_cast<double>(i) * spacing_m;
    const Eigen::Isometry3d T_W_C = cameraPoseAt(scene.frames_T_W_C, s, s_m);
    const auto ground = bvh.firstHit(T_W_C.translation(), -up_W, kGroundProbeM);
    if (!ground) {
      throw std::invalid_argument("lidarScanPoses: no ground within 20 m below the trajectory at " +
                                  std::to_string(s_m) + " m (scan " + std::to_string(i) + ")");
    }
    Eigen::Isometry3d T_W_S = Eigen::Isometry3d::Identity();
    T_W_S.linear() = T_W_C.linear() * R_C_S;
    T_W_S.translation() = ground->point + config.mount_height_m * up_W;
    poses.push_back(T_W_S);
  }
  return poses;
}

}  // namespace terramesh::datasets
