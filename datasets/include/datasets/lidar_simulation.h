#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "datasets/kitti_odometry_reader.h"
#include "datasets/labeled_mesh.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::datasets {

/// A spinning multi-beam LiDAR (HDL-64E-like by default) carried along a synthetic scene's
/// trajectory. Lengths in metres (the scene's units), angles in degrees.
///
/// Model: `beam_count` beams evenly spaced in elevation from `upper_elevation_deg` (beam 0) down
/// to `lower_elevation_deg` (the real HDL-64E spaces its two laser blocks unevenly), each fired
/// at `columns_per_revolution` azimuths evenly spaced over one turn. A scan is one turn taken at
/// a single pose: the motion during the turn (0.1 s at 10 Hz) is ignored. Each ray is cast into
/// the truth mesh (TriangleBvh::firstHit); a ray that meets no surface within `max_range_m` (sky,
/// far away) gives no return. The measured range is the true range plus a Gaussian error of
/// `range_noise_std_m`, drawn from a generator seeded by (seed, scan index); a return whose
/// measured range falls outside [min_range_m, max_range_m] is dropped. No beam divergence, no
/// multiple echoes, no reflectance (written as 0), no dropouts on dark or specular surfaces.
///
/// Poses: scans are `speed_m_per_s / rate_hz` apart along the arc length of the scene's camera
/// trajectory (poses interpolated between frames). The sensor stands `mount_height_m` above the
/// ground under the camera (the first surface straight down along -up_W), with the camera's
/// orientation: sensor x forward (the camera's z), y left (-x), z up (-y).
struct LidarSimulationConfig {
  /// Seed of the range noise.
  std::uint64_t seed = 1;
  int beam_count = 64;
  /// Elevation of the top beam and of the bottom beam above the sensor's xy plane.
  double upper_elevation_deg = 2.0;
  double lower_elevation_deg = -24.8;
  /// Azimuth steps per turn: 2048 gives 0.176 degrees, 131,072 rays per scan.
  int columns_per_revolution = 2048;
  double min_range_m = 0.9;
  double max_range_m = 120.0;
  double range_noise_std_m = 0.02;
  /// Scans (turns) per second; scan i is taken at time i / rate_hz.
  double rate_hz = 10.0;
  /// Height of the sensor's origin above the ground contact under the platform (KITTI's
  /// Velodyne: 1.73 m).
  double mount_height_m = 1.73;
  /// Speed of the platform along the trajectory (the street scene's camera speed).
  double speed_m_per_s = 8.0;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Elevations of the beams in degrees, beam 0 (top) first, evenly spaced from
/// upper_elevation_deg to lower_elevation_deg.
/// @throw std::invalid_argument for an invalid config.
std::vector<double> lidarBeamElevationsDeg(const LidarSimulationConfig& config);

/// Unit directions of every ray of a scan in the sensor frame (x forward, y left, z up), in
/// firing order: column by column (azimuth 0, counter-clockwise seen from above, starting
/// forward), each column top beam first.
/// @throw std::invalid_argument for an invalid config.
std::vector<Eigen::Vector3d> lidarRayDirections(const LidarSimulationConfig& config);

/// What one scan cast, and what became of its rays.
struct LidarScanStats {
  std::size_t rays = 0;
  std::size_t returns = 0;
  /// Rays that met no surface within max_range_m.
  std::size_t misses = 0;
  /// Rays that met a surface but whose measured range fell outside [min_range_m, max_range_m].
  std::size_t out_of_range = 0;
};

/// One turn of the sensor: its pose and its returns, with the truth of each.
struct LidarScan {
  /// Index of the scan in the sequence (seeds its noise), and its time (index / rate_hz).
  std::size_t index = 0;
  double time_s = 0.0;
  /// Sensor-to-world pose.
  Eigen::Isometry3d T_W_S = Eigen::Isometry3d::Identity();
  /// Returns in the sensor frame, in firing order; reflectance 0.
  std::vector<VelodyneReturn> returns;
  /// Per return: the truth face it hit (index into the truth mesh) and that face's label.
  std::vector<std::uint32_t> faces;
  std::vector<SurfaceLabel> labels;
  LidarScanStats stats;
};

/// Casts LiDAR scans into a labelled truth mesh. Holds references to `truth` and `bvh`, which
/// must outlive it. Const members are thread-safe (the ray caster's queries are).
class LidarSimulator {
 public:
  /// @throw std::invalid_argument for an invalid config, a truth that does not validate or a
  ///        `bvh` not built from `truth.mesh` (face counts differ).
  LidarSimulator(const LabeledMesh& truth, const TriangleBvh& bvh,
                 const LidarSimulationConfig& config);

  const LidarSimulationConfig& config() const { return config_; }

  /// The scan taken at sensor pose `T_W_S` as scan number `index` of a sequence (its noise comes
  /// from (seed, index), so the same index and pose give the same scan). O(rays * log faces).
  LidarScan scan(const Eigen::Isometry3d& T_W_S, std::size_t index) const;

 private:
  const LabeledMesh& truth_;
  const TriangleBvh& bvh_;
  LidarSimulationConfig config_;
  std::vector<Eigen::Vector3d> directions_S_;
};

/// Most scans one sequence may hold (a million scans of the default sensor fill about 2 TB).
inline constexpr std::size_t kMaxLidarScans = 1000000;

/// How many scans lidarScanPoses gives: one every speed_m_per_s / rate_hz of the trajectory's
/// arc length, the first at its start (floor(length / spacing) + 1), at most `max_scans` (0: no
/// limit); kMaxLidarScans + 1 for any count above kMaxLidarScans. O(frames).
/// @throw std::invalid_argument for an invalid config or a scene without frames.
std::size_t lidarScanCount(const SyntheticScene& scene, const LidarSimulationConfig& config,
                           std::size_t max_scans = 0);

/// Sensor poses T_W_S of the scans along the scene's trajectory (see LidarSimulationConfig):
/// the first at the trajectory's start, then every speed_m_per_s / rate_hz of arc length, as
/// many as fit on the trajectory, at most `max_scans` (0: no limit). `bvh` must be built from
/// scene.ground_truth.mesh.
/// @throw std::invalid_argument for an invalid config, a scene without frames, more than
///        kMaxLidarScans scans, or a pose with no ground within 20 m below the camera (the
///        message gives the arc length).
std::vector<Eigen::Isometry3d> lidarScanPoses(const SyntheticScene& scene, const TriangleBvh& bvh,
                                              const LidarSimulationConfig& config,
                                              std::size_t max_scans = 0);

}  // namespace terramesh::datasets
