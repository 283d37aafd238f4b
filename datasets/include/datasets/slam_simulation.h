#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/slam_stream.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::datasets {

/// How the simulated sparse SLAM system behaves. Lengths in metres (the scene's units).
///
/// Model: keyframes are chosen along the scene's frames. At each keyframe, new features appear
/// where rays through random pixels of a pinhole camera first meet the surface within range
/// (on ground, only with probability `ground_feature_probability`; at depth d, with probability
/// (d / max_range_m)^feature_depth_exponent).
/// A feature is tracked at later keyframes while it is geometrically matchable there (inside the
/// image, within range, not occluded, distance within `max_scale_change` of the distance it was
/// created at, viewing direction within `max_view_angle_deg` of the creating one), each time with
/// probability `match_probability`; it is dropped after `max_missed_keyframes` keyframes in a row
/// without a match. Every observation has Gaussian error: `noise_std_m + depth_noise_per_m *
/// depth^2` along the viewing ray and `pixel_noise_px * depth / focal` across it. The SLAM
/// estimate of a point is the information-weighted fusion of its observations so far, so it
/// moves at each re-observation and its error shrinks; only a `moving_point_fraction` of points
/// are refined that way, the others keep their first estimate (as most map points of a real SLAM
/// system are never touched again). Outliers keep an estimate displaced along the first ray by a
/// factor 0.5-0.8 or 1.25-2 of the true depth. Each keyframe message carries the current
/// estimate of every point observed there.
struct SlamSimulationConfig {
  std::uint64_t seed = 1;
  /// Distance travelled between keyframes; used when keyframe_every_frames is 0.
  double keyframe_spacing_m = 2.0;
  /// A keyframe every this many frames instead (0: use the spacing).
  int keyframe_every_frames = 0;
  /// Pinhole camera; defaults are KITTI's grey camera (principal point at the image centre).
  int image_width_px = 1241;
  int image_height_px = 376;
  double focal_length_px = 718.856;
  double min_range_m = 0.5;
  double max_range_m = 40.0;
  /// Features created per keyframe (the feature density).
  int new_points_per_keyframe = 130;
  /// Rays cast per wanted feature before giving up (sky, grazing surfaces).
  int max_rays_per_new_point = 8;
  /// Surfaces seen more obliquely than this give no features.
  double max_incidence_deg = 80.0;
  /// Chance that a ray hitting ground (a face sloped under 30 degrees) yields a feature: asphalt
  /// and paving seen at grazing angles have little texture, so real feature detectors find fewer
  /// corners there than on facades, cars and trees.
  double ground_feature_probability = 1.0;
  /// A hit at depth d yields a feature with probability (d / max_range_m)^exponent: 0 spreads
  /// features uniformly over the image (a detector's grid), 2 uniformly over the surface area
  /// seen (a fixed density of texture per m^2), which favours the far, long-tracked points.
  double feature_depth_exponent = 0.0;
  double match_probability = 0.9;
  int max_missed_keyframes = 2;
  double max_scale_change = 3.0;
  double max_view_angle_deg = 60.0;
  double noise_std_m = 0.03;
  double depth_noise_per_m = 3e-4;
  double pixel_noise_px = 1.0;
  double moving_point_fraction = 1.0;
  double outlier_fraction = 0.01;
  /// Loop closure: the keyframe poses of the middle third of the trajectory drift, growing
  /// linearly to this many metres of camera position error plus 0.5 * drift / (window length)
  /// radians of yaw about the camera (the points sent with a drifted keyframe drift with it); at
  /// the end of the window those keyframes are re-sent with their true poses and corrected
  /// estimates. 0: no drift.
  double loop_closure_drift_m = 0.0;
  /// Surfaces within this distance of an end of a camera-point segment do not occlude it.
  double occlusion_tolerance_m = 0.005;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// The issue-3 benchmark stream: along KITTI 00 a keyframe every 4 frames; the mesher inserts
/// ~130 points (those seen twice) and traces ~500 rays per keyframe, and ~10 % of the points move
/// after their insertion. The simulated SLAM creates ~270 features per keyframe for that, as
/// many are seen once only.
SlamSimulationConfig kittiLikeSlamConfig();
/// The dense stress variant: nine times the features, ~4,500 rays per keyframe.
SlamSimulationConfig kittiDenseSlamConfig();

/// The hazards scene's default: sparse SLAM as the hazards it holds are missed in practice, about
/// 1-3 points per m^2 of the ground the camera sees (measured with measureGroundDensity, see
/// docs/synthetic_data.md), 3 cm noise along and across the ray at every depth (no growth with
/// depth), a keyframe every 2 m; features on surfaces seen up to 85 degrees from their normal,
/// as a ground robot's low camera sees the ground at grazing angles.
SlamSimulationConfig hazardsSlamConfig();

/// Ground truth of one simulated map point; its id is its index in SimulatedSlam::points.
struct SimulatedPoint {
  /// True position on the ground-truth surface (also for outliers: where the feature really is).
  Eigen::Vector3d true_position_W = Eigen::Vector3d::Zero();
  /// Ground-truth face the point lies on.
  std::uint32_t face = 0;
  bool outlier = false;
  /// Whether its estimate is refined at re-observations.
  bool moving = false;
  /// Index (in SimulatedSlam::keyframes) of the keyframe that created it.
  std::size_t first_keyframe = 0;
  int observations = 0;
  /// Estimate sent with the last observation.
  Eigen::Vector3d final_estimate_W = Eigen::Vector3d::Zero();
};

/// Ground truth of one keyframe; its id is its index in SimulatedSlam::keyframes.
struct SimulatedKeyframe {
  /// Index of the scene frame it was taken at.
  std::size_t frame = 0;
  Eigen::Isometry3d true_T_W_C = Eigen::Isometry3d::Identity();
  /// Whether it was sent with a drifted pose first and re-sent corrected (loop closure).
  bool corrected_by_loop_closure = false;
};

/// Counts over a simulated stream.
struct SimulationStats {
  std::size_t keyframes = 0;
  /// Keyframe messages, re-sent ones included.
  std::size_t keyframe_events = 0;
  std::size_t points = 0;
  std::size_t outliers = 0;
  std::size_t moving_points = 0;
  /// Observations in first-sent keyframe messages (re-sends not counted).
  std::size_t observations = 0;
  std::size_t rays_cast = 0;
  /// Points whose sent estimate changed after they had two views (when a mesher inserts them).
  std::size_t points_moved_after_second_view = 0;
  /// Points with at least two observations.
  std::size_t points_seen_twice = 0;
};

/// A simulated SLAM stream with its ground truth.
struct SimulatedSlam {
  SlamStream stream;
  std::vector<SimulatedPoint> points;
  std::vector<SimulatedKeyframe> keyframes;
  SimulationStats stats;
};

/// Indices of the frames that become keyframes: the first, then every keyframe_every_frames-th,
/// or each frame at least keyframe_spacing_m (travelled) after the previous keyframe.
std::vector<std::size_t> selectKeyframeFrames(const PoseList& frames_T_W_C, const SlamSimulationConfig& config);

/// Runs the simulated SLAM along the scene's frames. `bvh` must be built from
/// scene.ground_truth.mesh. Deterministic for a given scene and config (seed included).
/// Single-threaded; O(keyframes * (tracked points + rays) * log faces).
/// @throw std::invalid_argument for a bad config, a bvh of another mesh or a scene without frames.
SimulatedSlam simulateSlam(const SyntheticScene& scene, const TriangleBvh& bvh,
                           const SlamSimulationConfig& config);

}  // namespace terramesh::datasets
