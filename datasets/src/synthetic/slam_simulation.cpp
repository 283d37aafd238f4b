#include "datasets/slam_simulation.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "problem_list.h"
#include "rng.h"

namespace terramesh::datasets {
namespace {

using synthetic::Rng;

constexpr double kDegToRad = M_PI / 180.0;
/// Faces sloped less than this count as ground for ground_feature_probability.
constexpr double kGroundSlopeDeg = 30.0;

/// Independent random streams of one seed, so that e.g. a different match probability does not
/// change where features appear.
enum Stream : std::uint64_t { kPixels = 1, kMatches, kNoise, kFlags, kDrift };

/// What the simulated SLAM system knows about a point (its truth is in SimulatedPoint).
struct PointState {
  /// Sum of the observations' information matrices and of information-weighted errors.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d weighted_error = Eigen::Vector3d::Zero();
  Eigen::Vector3d estimate_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d estimate_at_second_view_W = Eigen::Vector3d::Zero();
  double creation_distance_m = 0.0;
  Eigen::Vector3d creation_direction_W = Eigen::Vector3d::UnitZ();
  int missed = 0;
};

/// A rigid drift of the map frame: x -> centre + R (x - centre) + offset.
struct Drift {
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d offset_W = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return centre_W + rotation * (x - centre_W) + offset_W; }
  Eigen::Isometry3d apply(const Eigen::Isometry3d& T_W_C) const {
    Eigen::Isometry3d result = T_W_C;
    result.linear() = rotation * T_W_C.linear();
    result.translation() = apply(T_W_C.translation());
    return result;
  }
};

class SlamSimulator {
 public:
  SlamSimulator(const SyntheticScene& scene, const TriangleBvh& bvh, const SlamSimulationConfig& config)
      : scene_(scene), bvh_(bvh), config_(config),
        pixel_rng_(config.seed, kPixels), match_rng_(config.seed, kMatches),
        noise_rng_(config.seed, kNoise), flag_rng_(config.seed, kFlags) {
    const mesher::TriangleMesh& mesh = scene.ground_truth.mesh;
    face_normals_.reserve(mesh.faces.size());
    for (const auto& face : mesh.faces) {
      const Eigen::Vector3d& a = mesh.vertices[face[0]];
      face_normals_.push_back((mesh.vertices[face[1]] - a).cross(mesh.vertices[face[2]] - a).normalized());
    }
    cos_view_angle_ = std::cos(config.max_view_angle_deg * kDegToRad);
    cos_incidence_ = std::cos(config.max_incidence_deg * kDegToRad);
  }

  SimulatedSlam run() {
    const std::vector<std::size_t> keyframe_frames = selectKeyframeFrames(scene_.frames_T_W_C, config_);
    planLoopClosure(keyframe_frames);
    result_.stream.metres_per_unit = 1.0;
    result_.stream.scale_known = true;
    result_.stream.description = "terramesh synthetic " + scene_.name + " stream (seed " +
                                 std::to_string(config_.seed) + "): " + scene_.frame_description;
    for (std::size_t k = 0; k < keyframe_frames.size(); ++k) {
      if (drift_window_end_ > 0 && k == drift_window_end_) resendCorrectedWindow();
      processKeyframe(k, keyframe_frames[k]);
    }
    finishStats();
    return std::move(result_);
  }

 private:
  const Eigen::Isometry3d& truePose(std::size_t k) const { return result_.keyframes[k].true_T_W_C; }

  void processKeyframe(std::size_t k, std::size_t frame) {
    SimulatedKeyframe keyframe;
    keyframe.frame = frame;
    keyframe.true_T_W_C = scene_.frames_T_W_C[frame];
    keyframe.corrected_by_loop_closure = inDriftWindow(k);
    result_.keyframes.push_back(keyframe);

    std::vector<std::size_t> observed;
    trackActivePoints(k, observed);
    createPoints(k, observed);
    if (inDriftWindow(k)) window_observations_.push_back(observed);
    sendKeyframe(k, observed, inDriftWindow(k) ? &drifts_[k - drift_window_start_] : nullptr);
    result_.stats.observations += observed.size();
  }

  /// Re-observes the points still tracked; drops those missed too often.
  void trackActivePoints(std::size_t k, std::vector<std::size_t>& observed) {
    const Eigen::Isometry3d& T_W_C = truePose(k);
    std::size_t kept = 0;
    for (const std::size_t index : active_) {
      PointState& state = states_[index];
      if (matchable(index, T_W_C) && match_rng_.chance(config_.match_probability)) {
        observe(index, T_W_C.translation());
        observed.push_back(index);
        state.missed = 0;
      } else if (++state.missed > config_.max_missed_keyframes) {
        continue;
      }
      active_[kept++] = index;
    }
    active_.resize(kept);
  }

  /// Whether the true point is inside the image, in range, matchable from this viewpoint and
  /// unoccluded.
  bool matchable(std::size_t index, const Eigen::Isometry3d& T_W_C) const {
    const Eigen::Vector3d& X = result_.points[index].true_position_W;
    const PointState& state = states_[index];
    const Eigen::Vector3d ray = X - T_W_C.translation();
    const double distance = ray.norm();
    if (distance < config_.min_range_m || distance > config_.max_range_m) return false;
    if (!inImage(T_W_C.linear().transpose() * ray)) return false;
    const double scale = distance / state.creation_distance_m;
    if (scale > config_.max_scale_change || scale * config_.max_scale_change < 1.0) return false;
    if (ray.dot(state.creation_direction_W) < cos_view_angle_ * distance) return false;
    return !bvh_.segmentOccluded(T_W_C.translation(), X, config_.occlusion_tolerance_m);
  }

  bool inImage(const Eigen::Vector3d& p_C) const {
    if (p_C.z() <= 0) return false;
    const double u = config_.focal_length_px * p_C.x() / p_C.z() + config_.image_width_px / 2.0;
    const double v = config_.focal_length_px * p_C.y() / p_C.z() + config_.image_height_px / 2.0;
    return u >= 0 && u < config_.image_width_px && v >= 0 && v < config_.image_height_px;
  }

  /// Casts rays through random pixels until enough new features are found or the budget is spent.
  void createPoints(std::size_t k, std::vector<std::size_t>& observed) {
    const Eigen::Isometry3d& T_W_C = truePose(k);
    const Eigen::Vector3d centre = T_W_C.translation();
    const int wanted = config_.new_points_per_keyframe;
    const long budget = static_cast<long>(wanted) * config_.max_rays_per_new_point;
    int created = 0;
    for (long ray = 0; ray < budget && created < wanted; ++ray) {
      const double u = pixel_rng_.uniform(0.0, config_.image_width_px);
      const double v = pixel_rng_.uniform(0.0, config_.image_height_px);
      const Eigen::Vector3d direction_C((u - config_.image_width_px / 2.0) / config_.focal_length_px,
                                        (v - config_.image_height_px / 2.0) / config_.focal_length_px, 1.0);
      const Eigen::Vector3d direction_W = (T_W_C.linear() * direction_C).normalized();
      ++result_.stats.rays_cast;
      const std::optional<RayHit> hit = bvh_.firstHit(centre, direction_W, config_.max_range_m);
      if (!hit || hit->distance < config_.min_range_m) continue;
      if (std::abs(face_normals_[hit->face].dot(direction_W)) < cos_incidence_) continue;
      if (scene_.ground_truth.slope_deg[hit->face] < kGroundSlopeDeg &&
          !pixel_rng_.chance(config_.ground_feature_probability)) {
        continue;
      }
      if (config_.feature_depth_exponent > 0 &&
          !pixel_rng_.chance(std::pow(hit->distance / config_.max_range_m, config_.feature_depth_exponent))) {
        continue;
      }
      SimulatedPoint point;
      point.true_position_W = hit->point;
      point.face = hit->face;
      point.outlier = flag_rng_.chance(config_.outlier_fraction);
      point.moving = !point.outlier && flag_rng_.chance(config_.moving_point_fraction);
      point.first_keyframe = k;
      const std::size_t index = result_.points.size();
      result_.points.push_back(point);
      PointState state;
      state.creation_distance_m = hit->distance;
      state.creation_direction_W = direction_W;
      states_.push_back(state);
      observe(index, centre);
      if (point.outlier) {
        const double factor = flag_rng_.chance(0.5) ? flag_rng_.uniform(0.5, 0.8) : flag_rng_.uniform(1.25, 2.0);
        states_[index].estimate_W = centre + factor * (hit->point - centre);
        result_.points[index].final_estimate_W = states_[index].estimate_W;
      }
      active_.push_back(index);
      observed.push_back(index);
      ++created;
    }
  }

  /// Adds one noisy observation from `camera_W` and updates the estimate.
  void observe(std::size_t index, const Eigen::Vector3d& camera_W) {
    SimulatedPoint& point = result_.points[index];
    PointState& state = states_[index];
    const Eigen::Vector3d ray = point.true_position_W - camera_W;
    const double depth = ray.norm();
    const Eigen::Vector3d r = ray / depth;
    const double sigma_along = config_.noise_std_m + config_.depth_noise_per_m * depth * depth;
    const double sigma_across = config_.pixel_noise_px * depth / config_.focal_length_px;
    const Eigen::Vector3d e1 = r.unitOrthogonal();
    const Eigen::Vector3d e2 = r.cross(e1);
    const double n1 = noise_rng_.normal(), n2 = noise_rng_.normal(), n3 = noise_rng_.normal();
    const Eigen::Vector3d error = sigma_along * n1 * r + sigma_across * (n2 * e1 + n3 * e2);
    const Eigen::Matrix3d information =
        r * r.transpose() * (1.0 / (sigma_along * sigma_along) - 1.0 / (sigma_across * sigma_across)) +
        Eigen::Matrix3d::Identity() / (sigma_across * sigma_across);
    state.information += information;
    state.weighted_error += information * error;
    ++point.observations;
    if (point.observations == 1) {
      state.estimate_W = point.true_position_W + error;
    } else if (point.moving) {
      state.estimate_W = point.true_position_W + state.information.ldlt().solve(state.weighted_error);
    }
    if (point.observations == 2) state.estimate_at_second_view_W = state.estimate_W;
    point.final_estimate_W = state.estimate_W;
  }

  void sendKeyframe(std::size_t k, const std::vector<std::size_t>& observed, const Drift* drift) {
    mesher::Keyframe message;
    message.id = {k};
    const Eigen::Isometry3d pose = drift ? drift->apply(truePose(k)) : truePose(k);
    message.position_W_C = pose.translation();
    message.rotation_W_C = Eigen::Quaterniond(pose.linear()).normalized();
    message.observations.reserve(observed.size());
    for (const std::size_t index : observed) {
      const Eigen::Vector3d& estimate = states_[index].estimate_W;
      message.observations.push_back({{index}, drift ? drift->apply(estimate) : estimate});
    }
    result_.stream.events.emplace_back(std::move(message));
    ++result_.stats.keyframe_events;
  }

  bool inDriftWindow(std::size_t k) const {
    return drift_window_end_ > 0 && k >= drift_window_start_ && k < drift_window_end_;
  }

  /// The middle third of the keyframes drifts, growing linearly to the configured drift.
  void planLoopClosure(const std::vector<std::size_t>& keyframe_frames) {
    const std::size_t n = keyframe_frames.size();
    if (config_.loop_closure_drift_m <= 0 || n < 6) return;
    drift_window_start_ = n / 3;
    drift_window_end_ = 2 * n / 3;
    Rng rng(config_.seed, kDrift);
    const Eigen::Vector3d up = scene_.up_W.normalized();
    const Eigen::Vector3d any(rng.normal(), rng.normal(), rng.normal());
    const Eigen::Vector3d direction = (any - any.dot(up) * up).normalized();
    double window_length = 0.0;
    for (std::size_t k = drift_window_start_ + 1; k < drift_window_end_; ++k) {
      window_length += (scene_.frames_T_W_C[keyframe_frames[k]].translation() -
                        scene_.frames_T_W_C[keyframe_frames[k - 1]].translation()).norm();
    }
    const double max_yaw = 0.5 * config_.loop_closure_drift_m / std::max(window_length, 1.0);
    const double count = static_cast<double>(drift_window_end_ - drift_window_start_);
    for (std::size_t k = drift_window_start_; k < drift_window_end_; ++k) {
      const double fraction = static_cast<double>(k - drift_window_start_ + 1) / count;
      // The heading error turns the map about the camera, so the camera itself is off by exactly
      // the translation drift.
      Drift drift;
      drift.centre_W = scene_.frames_T_W_C[keyframe_frames[k]].translation();
      drift.rotation = Eigen::AngleAxisd(fraction * max_yaw, up).toRotationMatrix();
      drift.offset_W = fraction * config_.loop_closure_drift_m * direction;
      drifts_.push_back(drift);
    }
  }

  /// Loop closure: re-sends the drifted keyframes with true poses and current estimates.
  void resendCorrectedWindow() {
    for (std::size_t k = drift_window_start_; k < drift_window_end_; ++k) {
      sendKeyframe(k, window_observations_[k - drift_window_start_], nullptr);
    }
  }

  void finishStats() {
    SimulationStats& stats = result_.stats;
    stats.keyframes = result_.keyframes.size();
    stats.points = result_.points.size();
    for (std::size_t i = 0; i < result_.points.size(); ++i) {
      const SimulatedPoint& point = result_.points[i];
      stats.outliers += point.outlier;
      stats.moving_points += point.moving;
      if (point.observations >= 2) {
        ++stats.points_seen_twice;
        stats.points_moved_after_second_view += point.final_estimate_W != states_[i].estimate_at_second_view_W;
      }
    }
  }

  const SyntheticScene& scene_;
  const TriangleBvh& bvh_;
  const SlamSimulationConfig& config_;
  Rng pixel_rng_, match_rng_, noise_rng_, flag_rng_;
  std::vector<Eigen::Vector3d> face_normals_;
  double cos_view_angle_ = 0.0;
  double cos_incidence_ = 0.0;
  SimulatedSlam result_;
  std::vector<PointState> states_;
  /// Points still tracked, in id order.
  std::vector<std::size_t> active_;
  std::size_t drift_window_start_ = 0, drift_window_end_ = 0;
  std::vector<Drift> drifts_;
  std::vector<std::vector<std::size_t>> window_observations_;
};

}  // namespace

void SlamSimulationConfig::validate() const {
  synthetic::ProblemList problems("SlamSimulationConfig");
  problems.require(keyframe_every_frames >= 0, "keyframe_every_frames must be >= 0");
  problems.require(keyframe_every_frames > 0 || keyframe_spacing_m > 0,
                   "keyframe_spacing_m must be > 0 when keyframe_every_frames is 0");
  problems.require(image_width_px >= 16 && image_height_px >= 16, "image must be at least 16 x 16 px");
  problems.require(focal_length_px > 0, "focal_length_px must be > 0");
  problems.require(min_range_m >= 0 && max_range_m > min_range_m, "need 0 <= min_range_m < max_range_m");
  problems.require(new_points_per_keyframe >= 0, "new_points_per_keyframe must be >= 0");
  problems.require(max_rays_per_new_point >= 1, "max_rays_per_new_point must be >= 1");
  problems.require(max_incidence_deg > 0 && max_incidence_deg <= 90, "max_incidence_deg must be in (0, 90]");
  problems.require(ground_feature_probability >= 0 && ground_feature_probability <= 1,
                   "ground_feature_probability must be in [0, 1]");
  problems.require(feature_depth_exponent >= 0 && feature_depth_exponent <= 4,
                   "feature_depth_exponent must be in [0, 4]");
  problems.require(match_probability >= 0 && match_probability <= 1, "match_probability must be in [0, 1]");
  problems.require(max_missed_keyframes >= 0, "max_missed_keyframes must be >= 0");
  problems.require(max_scale_change >= 1, "max_scale_change must be >= 1");
  problems.require(max_view_angle_deg > 0 && max_view_angle_deg <= 180, "max_view_angle_deg must be in (0, 180]");
  problems.require(noise_std_m > 0, "noise_std_m must be > 0");
  problems.require(depth_noise_per_m >= 0, "depth_noise_per_m must be >= 0");
  problems.require(pixel_noise_px > 0, "pixel_noise_px must be > 0");
  problems.require(moving_point_fraction >= 0 && moving_point_fraction <= 1, "moving_point_fraction must be in [0, 1]");
  problems.require(outlier_fraction >= 0 && outlier_fraction <= 1, "outlier_fraction must be in [0, 1]");
  problems.require(loop_closure_drift_m >= 0, "loop_closure_drift_m must be >= 0");
  problems.require(occlusion_tolerance_m >= 0, "occlusion_tolerance_m must be >= 0");
  problems.throwIfAny();
}

SlamSimulationConfig kittiLikeSlamConfig() {
  // Tuned on KITTI 00 so that `terramesh mesh` sees the paper's Table IV statistics: ~130 points
  // inserted (seen twice) and ~500 rays traced per keyframe, ~10 % of the points moving after
  // their insertion (docs/synthetic_data.md has the measured values).
  SlamSimulationConfig config;
  config.keyframe_every_frames = 4;
  config.new_points_per_keyframe = 270;
  config.max_rays_per_new_point = 20;
  config.ground_feature_probability = 0.3;
  config.feature_depth_exponent = 1.0;
  config.match_probability = 0.8;
  config.max_missed_keyframes = 0;
  config.moving_point_fraction = 0.18;
  return config;
}

SlamSimulationConfig kittiDenseSlamConfig() {
  SlamSimulationConfig config = kittiLikeSlamConfig();
  config.new_points_per_keyframe = 9 * 270;
  return config;
}

SlamSimulationConfig hazardsSlamConfig() {
  SlamSimulationConfig config;
  config.keyframe_spacing_m = 2.0;
  config.new_points_per_keyframe = 60;
  config.max_range_m = 30.0;
  config.max_incidence_deg = 85.0;
  config.noise_std_m = 0.03;
  config.depth_noise_per_m = 0.0;
  config.pixel_noise_px = 0.5;
  return config;
}

std::vector<std::size_t> selectKeyframeFrames(const PoseList& frames_T_W_C, const SlamSimulationConfig& config) {
  std::vector<std::size_t> frames;
  if (frames_T_W_C.empty()) return frames;
  frames.push_back(0);
  double travelled = 0.0;
  for (std::size_t i = 1; i < frames_T_W_C.size(); ++i) {
    if (config.keyframe_every_frames > 0) {
      if (i % static_cast<std::size_t>(config.keyframe_every_frames) == 0) frames.push_back(i);
      continue;
    }
    travelled += (frames_T_W_C[i].translation() - frames_T_W_C[i - 1].translation()).norm();
    if (travelled >= config.keyframe_spacing_m) {
      frames.push_back(i);
      travelled = 0.0;
    }
  }
  return frames;
}

SimulatedSlam simulateSlam(const SyntheticScene& scene, const TriangleBvh& bvh, const SlamSimulationConfig& config) {
  config.validate();
  scene.ground_truth.validate();
  if (bvh.faceCount() != scene.ground_truth.mesh.faces.size()) {
    throw std::invalid_argument("simulateSlam: the ray caster was not built from the scene's mesh");
  }
  if (scene.frames_T_W_C.empty()) throw std::invalid_argument("simulateSlam: the scene has no frames");
  return SlamSimulator(scene, bvh, config).run();
}

}  // namespace terramesh::datasets
