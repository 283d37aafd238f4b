#include "traversability/trajectory_evidence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <optional>
#include <utility>
#include <sstream>
#include <stdexcept>

namespace terramesh::traversability {
namespace {

/// MAD to standard deviation for Gaussian data.
constexpr double kMadToSigma = 1.4826;

/// The q-quantile (0 <= q <= 1) of `values`, linearly interpolated; NaN if empty.
double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (at - static_cast<double>(below)) * (values[above] - values[below]);
}

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  if (values.size() % 2 == 1) return *mid;
  const double upper = *mid;
  const double lower = *std::max_element(values.begin(), mid);
  return 0.5 * (lower + upper);
}

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f m", value);
  return text;
}

void requireFrame(const Eigen::Vector3d& up_W, double metres_per_unit) {
  if (!up_W.allFinite() || std::abs(up_W.norm() - 1.0) > 1e-6) {
    throw std::invalid_argument("trajectory evidence: up must be a finite unit vector");
  }
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    throw std::invalid_argument("trajectory evidence: metres_per_unit must be finite and > 0");
  }
}

/// Horizontal coordinates in a plane orthogonal to up.
struct GroundPlane {
  Eigen::Vector3d up, e1, e2;

  explicit GroundPlane(const Eigen::Vector3d& up_W) : up(up_W) {
    const Eigen::Vector3d seed = std::abs(up.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    e1 = (seed - seed.dot(up) * up).normalized();
    e2 = up.cross(e1);
  }
  Eigen::Vector2d project(const Eigen::Vector3d& p) const { return {p.dot(e1), p.dot(e2)}; }
};

/// Points bucketed by horizontal grid cell (cell size = the search radius).
class HorizontalGrid {
 public:
  HorizontalGrid(const std::vector<Eigen::Vector3d>& points, const GroundPlane& plane, double cell)
      : cell_(cell) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      cells_[key(plane.project(points[i]))].push_back(static_cast<std::uint32_t>(i));
    }
  }
  /// Calls `visit(index)` for every point in the 3x3 cells around `at`.
  template <class Visit>
  void around(const Eigen::Vector2d& at, Visit visit) const {
    const auto [cx, cy] = cellOf(at);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find(pack(cx + dx, cy + dy));
        if (it == cells_.end()) continue;
        for (std::uint32_t index : it->second) visit(index);
      }
    }
  }

 private:
  std::pair<std::int64_t, std::int64_t> cellOf(const Eigen::Vector2d& p) const {
    // Clamped so that absurd coordinates (refused later by the mesher) cannot overflow the cast.
    const auto index = [this](double x) {
      return static_cast<std::int64_t>(std::clamp(std::floor(x / cell_), -1e15, 1e15));
    };
    return {index(p.x()), index(p.y())};
  }
  static std::uint64_t pack(std::int64_t x, std::int64_t y) {
    return (static_cast<std::uint64_t>(x) << 32) ^ (static_cast<std::uint64_t>(y) & 0xffffffffull);
  }
  std::uint64_t key(const Eigen::Vector2d& p) const {
    const auto [x, y] = cellOf(p);
    return pack(x, y);
  }

  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

/// Keeps, of the depths beneath one sensor, the nearest layer that holds min_points_per_keyframe
/// of them: depths sorted and split where consecutive ones are more than layer_gap_m apart (a
/// floor of a multi-storey garage hides the levels below it; they are not the ground under the
/// path). Objects beside the path lie within the ground's layer. Empty if no layer holds enough.
void keepNearestLayer(std::vector<double>& depths, const TrajectoryEvidenceConfig& config) {
  std::sort(depths.begin(), depths.end());
  const auto needed = static_cast<std::size_t>(config.min_points_per_keyframe);
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= depths.size(); ++i) {
    if (i < depths.size() && depths[i] - depths[i - 1] <= config.layer_gap_m) continue;
    if (i - begin >= needed) {
      depths.erase(depths.begin() + static_cast<std::ptrdiff_t>(i), depths.end());
      depths.erase(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(begin));
      return;
    }
    begin = i;
  }
  depths.clear();
}

/// The contact patch layout in the base frame (metres): the footprint's cross-section across the
/// heading through its centre (a disc's diameter, a rectangle's width), samples at most `spacing`
/// apart out to both edges. Patches along the path then form a ladder whose rails are the swept
/// footprint's edges. A ring would leave a notch between neighbouring stations that closing
/// geometry from beside the path reaches into; a grid over a long rectangle puts the rows of
/// overlapping patches nearly on top of each other, at heights that differ by the poses' noise.
std::vector<Eigen::Vector3d> patchLayout(const RobotProfile& profile, const TrajectoryEvidenceConfig& config) {
  const double half_width = config.patch_fraction * (profile.footprint == FootprintShape::kDisc
                                                         ? profile.footprint_radius_m
                                                         : 0.5 * profile.footprint_width_m);
  const int half = std::max(1, static_cast<int>(std::ceil(half_width / config.sample_spacing_m)));
  std::vector<Eigen::Vector3d> layout;
  for (int i = -half; i <= half; ++i) layout.emplace_back(0, half_width * i / half, 0);
  return layout;
}

}  // namespace

void TrajectoryEvidenceConfig::validate() const {
  std::vector<std::string> problems;
  auto require = [&](bool ok, const char* key, double value, const char* expected) {
    if (ok && std::isfinite(value)) return;
    std::ostringstream text;
    text << key << ": " << value << " (expected " << expected << ")";
    problems.push_back(text.str());
  };
  require(sample_spacing_m > 0.01 && sample_spacing_m <= 100, "sample_spacing_m", sample_spacing_m, "(0.01, 100]");
  require(patch_fraction > 0 && patch_fraction <= 1, "patch_fraction", patch_fraction, "(0, 1]");
  require(max_sweep_distance_m >= 0 && max_sweep_distance_m <= 1000, "max_sweep_distance_m", max_sweep_distance_m,
          "[0, 1000]");
  require(station_spacing_m >= 0 && station_spacing_m <= 100, "station_spacing_m", station_spacing_m, "[0, 100]");
  require(layer_gap_m > 0 && layer_gap_m <= 100, "layer_gap_m", layer_gap_m, "(0, 100]");
  require(estimate_radius_m > 0 && estimate_radius_m <= 100, "estimate_radius_m", estimate_radius_m, "(0, 100]");
  require(min_depth_below_m >= 0 && min_depth_below_m <= 100, "min_depth_below_m", min_depth_below_m, "[0, 100]");
  require(min_points_per_keyframe >= 1, "min_points_per_keyframe", min_points_per_keyframe, "an integer >= 1");
  require(envelope_quantile >= 0 && envelope_quantile <= 1, "envelope_quantile", envelope_quantile, "[0, 1]");
  require(ground_band_m >= 0 && ground_band_m <= 100, "ground_band_m", ground_band_m, "[0, 100]");
  require(min_keyframes >= 1, "min_keyframes", min_keyframes, "an integer >= 1");
  require(min_keyframe_fraction >= 0 && min_keyframe_fraction <= 1, "min_keyframe_fraction", min_keyframe_fraction,
          "[0, 1]");
  require(max_sensor_height_m > 0 && max_sensor_height_m <= 1000, "max_sensor_height_m", max_sensor_height_m,
          "(0, 1000]");
  require(max_height_spread_m > 0 && max_height_spread_m <= 100, "max_height_spread_m", max_height_spread_m,
          "(0, 100]");
  require(disagreement_tolerance_m >= 0 && disagreement_tolerance_m <= 100, "disagreement_tolerance_m",
          disagreement_tolerance_m, "[0, 100]");
  if (problems.empty()) return;
  std::string message = "invalid trajectory evidence config:";
  for (const std::string& problem : problems) message += "\n  " + problem;
  throw std::invalid_argument(message);
}

SensorHeightEstimate estimateSensorHeight(const std::vector<Eigen::Vector3d>& sensors_W,
                                          const std::vector<Eigen::Vector3d>& points_W, const Eigen::Vector3d& up_W,
                                          double metres_per_unit, const TrajectoryEvidenceConfig& config) {
  config.validate();
  requireFrame(up_W, metres_per_unit);
  const GroundPlane plane(up_W);
  const double radius = config.estimate_radius_m / metres_per_unit;
  const HorizontalGrid grid(points_W, plane, radius);
  SensorHeightEstimate estimate;
  estimate.keyframes_total = sensors_W.size();
  std::vector<double> heights;
  std::vector<double> depths;
  for (const Eigen::Vector3d& sensor : sensors_W) {
    const Eigen::Vector2d at = plane.project(sensor);
    depths.clear();
    grid.around(at, [&](std::uint32_t index) {
      const Eigen::Vector3d& p = points_W[index];
      const double depth_m = (sensor - p).dot(up_W) * metres_per_unit;
      if (depth_m >= config.min_depth_below_m && (plane.project(p) - at).norm() <= radius) depths.push_back(depth_m);
    });
    if (depths.size() < static_cast<std::size_t>(config.min_points_per_keyframe)) continue;
    keepNearestLayer(depths, config);
    if (depths.size() < static_cast<std::size_t>(config.min_points_per_keyframe)) continue;
    const double envelope = quantile(depths, config.envelope_quantile);
    depths.erase(std::remove_if(depths.begin(), depths.end(),
                                [&](double d) { return d < envelope - config.ground_band_m; }),
                 depths.end());
    heights.push_back(median(depths));
  }
  estimate.keyframes_used = heights.size();
  const double needed = std::max(static_cast<double>(config.min_keyframes),
                                 config.min_keyframe_fraction * static_cast<double>(sensors_W.size()));
  if (static_cast<double>(heights.size()) < needed) {
    std::ostringstream reason;
    reason << "only " << heights.size() << " of " << sensors_W.size() << " keyframes have "
           << config.min_points_per_keyframe << " or more points within " << config.estimate_radius_m
           << " m beneath them (needed " << std::ceil(needed) << ")";
    estimate.reason = reason.str();
    estimate.height_m = std::numeric_limits<double>::quiet_NaN();
    estimate.spread_m = std::numeric_limits<double>::quiet_NaN();
    return estimate;
  }
  estimate.height_m = median(heights);
  std::vector<double> deviations;
  deviations.reserve(heights.size());
  for (double h : heights) deviations.push_back(std::abs(h - estimate.height_m));
  estimate.spread_m = kMadToSigma * median(deviations);
  if (estimate.height_m > config.max_sensor_height_m) {
    estimate.status = SensorHeightEstimate::Status::kNotDriven;
    estimate.reason = "the sensor is " + metres(estimate.height_m) + " above the points beneath the path (more than " +
                      metres(config.max_sensor_height_m) + ": not a ground robot)";
  } else if (estimate.spread_m > config.max_height_spread_m) {
    estimate.status = SensorHeightEstimate::Status::kNotDriven;
    estimate.reason = "the sensor's height above the points beneath the path varies by " + metres(estimate.spread_m) +
                      " (more than " + metres(config.max_height_spread_m) + ": not a sensor mounted on a ground robot)";
  } else {
    estimate.status = SensorHeightEstimate::Status::kDriven;
  }
  return estimate;
}

TrajectoryEvidenceDecision decideTrajectoryEvidence(const SensorHeightEstimate& estimate,
                                                    std::optional<double> profile_height_m,
                                                    std::optional<double> override_height_m,
                                                    const TrajectoryEvidenceConfig& config) {
  TrajectoryEvidenceDecision decision;
  decision.estimate = estimate;
  const std::optional<double> given = override_height_m ? override_height_m : profile_height_m;
  const std::string given_source = override_height_m ? "--sensor-height-m" : "the robot profile";
  const std::string measured = "sensor height estimated from the points beneath the path: " +
                               metres(estimate.height_m) + " (spread " + metres(estimate.spread_m) + ", " +
                               std::to_string(estimate.keyframes_used) + " of " +
                               std::to_string(estimate.keyframes_total) + " keyframes)";
  using Status = SensorHeightEstimate::Status;
  if (estimate.status == Status::kNotDriven) {
    decision.summary = "trajectory evidence: off, the trajectory does not look driven: " + estimate.reason;
    return decision;
  }
  if (estimate.status == Status::kNoData && !given) {
    decision.summary = "trajectory evidence: off, no sensor height given and none can be estimated: " + estimate.reason;
    return decision;
  }
  decision.enabled = true;
  if (!given) {
    decision.sensor_height_m = estimate.height_m;
    decision.source = "the data";
    decision.summary = "trajectory evidence: on, " + measured;
    return decision;
  }
  decision.sensor_height_m = *given;
  decision.source = given_source;
  decision.summary = "trajectory evidence: on, sensor height " + metres(*given) + " from " + given_source;
  if (estimate.status == Status::kNoData) {
    decision.summary += " (not checked against the data: " + estimate.reason + ")";
    return decision;
  }
  decision.summary += "; " + measured;
  const double tolerance = std::max(config.disagreement_tolerance_m, 3 * estimate.spread_m);
  if (std::abs(*given - estimate.height_m) > tolerance) {
    decision.warning = "the sensor height from " + given_source + " (" + metres(*given) +
                       ") disagrees with the data (" + metres(estimate.height_m) + " +- " +
                       metres(estimate.spread_m) + " above the points beneath the path); using " + metres(*given);
  }
  return decision;
}

TrajectoryEvidence::TrajectoryEvidence(const RobotProfile& profile, const Eigen::Vector3d& up_W,
                                       double metres_per_unit, double sensor_height_m,
                                       const Eigen::Vector3d& forward_S, const TrajectoryEvidenceConfig& config)
    : up_W_(up_W),
      metres_per_unit_(metres_per_unit),
      sensor_height_m_(sensor_height_m),
      forward_S_(forward_S),
      T_B_S_(profile.T_B_S),
      config_(config) {
  config_.validate();
  profile.validate();
  requireFrame(up_W, metres_per_unit);
  if (!(sensor_height_m > 0) || !std::isfinite(sensor_height_m)) {
    throw std::invalid_argument("trajectory evidence: sensor_height_m must be finite and > 0");
  }
  if (!forward_S.allFinite() || forward_S.norm() < 1e-12) {
    throw std::invalid_argument("trajectory evidence: forward_S must be a finite non-zero vector");
  }
  forward_S_.normalize();
  if (T_B_S_) T_B_S_->translation().z() = sensor_height_m;  // the decision's height wins
  layout_B_m_ = patchLayout(profile, config_);
  double x_min = 0, x_max = 0;
  for (const Eigen::Vector3d& p : layout_B_m_) {
    x_min = std::min(x_min, p.x());
    x_max = std::max(x_max, p.x());
  }
  patch_length_m_ = x_max - x_min;
  disc_ = profile.footprint == FootprintShape::kDisc;
  radius_m_ = profile.footprint_radius_m;
  half_length_m_ = 0.5 * profile.footprint_length_m;
  half_width_m_ = 0.5 * profile.footprint_width_m;
  body_low_m_ = profile.max_step_m;
  body_high_m_ = profile.min_clearance_m;
  if (layout_B_m_.size() > kMaxDrivenSamplesPerKeyframe) {
    throw std::invalid_argument("trajectory evidence: " + std::to_string(layout_B_m_.size()) +
                                " samples per keyframe (at most " + std::to_string(kMaxDrivenSamplesPerKeyframe) +
                                "): increase sample_spacing_m");
  }
}

std::size_t TrajectoryEvidence::stationsFor(double gap_m) const {
  if (!(config_.station_spacing_m > 0) || !(gap_m > 0)) return 0;
  const double spacing = std::max(config_.station_spacing_m, patch_length_m_);
  const double wanted = std::ceil(gap_m / spacing) - 1;
  return wanted <= 0 ? 0 : std::min(maxStationsPerKeyframe(), static_cast<std::size_t>(wanted));
}

TrajectoryEvidence::Pose TrajectoryEvidence::stationPose(const Pose& pose, std::size_t station) const {
  if (station == 0) return pose;
  const double t = static_cast<double>(station) / static_cast<double>(pose.stations + 1);
  Pose at = pose;
  at.position_W = pose.previous_position_W + t * (pose.position_W - pose.previous_position_W);
  at.rotation_W_C = pose.previous_rotation_W_C.normalized().slerp(t, pose.rotation_W_C.normalized());
  return at;
}

std::vector<mesher::PointObservation> TrajectoryEvidence::samplesAt(mesher::KeyframeId id, const Pose& pose) const {
  if (id.value > kMaxDrivenKeyframeId) {
    throw std::invalid_argument("keyframe " + std::to_string(id.value) + ": trajectory evidence needs keyframe ids <= " +
                                std::to_string(kMaxDrivenKeyframeId) + " (they are part of the samples' point ids)");
  }
  const std::size_t patch = layout_B_m_.size();
  std::vector<mesher::PointObservation> samples;
  samples.reserve(patch * (1 + pose.stations));
  // Station 0 is the keyframe; stations 1..n lie between the previous keyframe and it.
  for (std::size_t station = 0; station <= pose.stations; ++station) {
    const Eigen::Isometry3d T_W_B = baseAt(stationPose(pose, station));
    for (std::size_t i = 0; i < patch; ++i) {
      mesher::PointObservation sample;
      sample.point = mesher::PointId{kDrivenGroundIdBit | (id.value << kDrivenSampleIndexBits) | (station * patch + i)};
      sample.position_W = T_W_B * (layout_B_m_[i] / metres_per_unit_);
      sample.kind = mesher::PointKind::kDrivenGround;
      samples.push_back(sample);
    }
  }
  return samples;
}

bool TrajectoryEvidence::insideBody(const Eigen::Isometry3d& T_W_B, const Eigen::Vector3d& p_W) const {
  const Eigen::Vector3d p_B = (T_W_B.inverse() * p_W) * metres_per_unit_;
  if (!(p_B.z() > body_low_m_ && p_B.z() <= body_high_m_)) return false;
  if (disc_) return p_B.head<2>().norm() <= radius_m_;
  return std::abs(p_B.x()) <= half_length_m_ && std::abs(p_B.y()) <= half_width_m_;
}

void TrajectoryEvidence::dropContradicted(mesher::Keyframe& keyframe, const std::vector<Eigen::Isometry3d>& bodies_W_B) {
  newly_contradicted_.clear();
  auto& observations = keyframe.observations;
  observations.erase(std::remove_if(observations.begin(), observations.end(),
                                    [&](const mesher::PointObservation& o) {
                                      if (contradicted_.count(o.point.value) != 0) return true;
                                      for (const Eigen::Isometry3d& T_W_B : bodies_W_B) {
                                        if (!insideBody(T_W_B, o.position_W)) continue;
                                        contradicted_.insert(o.point.value);
                                        newly_contradicted_.push_back(o.point);
                                        return true;
                                      }
                                      return false;
                                    }),
                     observations.end());
}

Eigen::Isometry3d TrajectoryEvidence::baseAt(const Pose& pose) const {
  Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
  const Eigen::Matrix3d R_W_C = pose.rotation_W_C.normalized().toRotationMatrix();
  if (T_B_S_) {
    Eigen::Isometry3d T_W_C = Eigen::Isometry3d::Identity();
    T_W_C.linear() = R_W_C;
    T_W_C.translation() = pose.position_W;
    Eigen::Isometry3d T_B_S_units = *T_B_S_;
    T_B_S_units.translation() /= metres_per_unit_;
    T_W_B = T_W_C * T_B_S_units.inverse();
  } else {
    // Heading: the sensor's forward axis on the ground plane (its right axis if it looks straight down).
    Eigen::Vector3d forward = R_W_C * forward_S_;
    forward -= forward.dot(up_W_) * up_W_;
    if (forward.norm() < 1e-6) {
      forward = R_W_C * forward_S_.unitOrthogonal();
      forward -= forward.dot(up_W_) * up_W_;
    }
    forward.normalize();
    T_W_B.linear().col(0) = forward;
    T_W_B.linear().col(1) = up_W_.cross(forward);
    T_W_B.linear().col(2) = up_W_;
    T_W_B.translation() = pose.position_W - (sensor_height_m_ / metres_per_unit_) * up_W_;
  }
  return T_W_B;
}

std::vector<mesher::PointObservation> TrajectoryEvidence::samplesOf(const mesher::Keyframe& keyframe) const {
  Pose pose;
  const auto known = poses_.find(keyframe.id.value);
  if (known != poses_.end()) pose = known->second;
  pose.position_W = keyframe.position_W_C;
  pose.rotation_W_C = keyframe.rotation_W_C;
  return samplesAt(keyframe.id, pose);
}

mesher::Keyframe TrajectoryEvidence::augment(const mesher::Keyframe& keyframe) {
  for (const mesher::PointObservation& observation : keyframe.observations) {
    if (isDrivenGroundId(observation.point)) {
      throw std::invalid_argument("keyframe " + std::to_string(keyframe.id.value) + ": point id " +
                                  std::to_string(observation.point.value) +
                                  " is in the range reserved for driven-ground samples (top bit set); "
                                  "turn trajectory evidence off for this stream");
    }
  }
  mesher::Keyframe augmented = keyframe;
  const auto known = poses_.find(keyframe.id.value);
  Pose pose;
  if (known != poses_.end()) pose = known->second;
  pose.position_W = keyframe.position_W_C;
  pose.rotation_W_C = keyframe.rotation_W_C;
  pose.order = known != poses_.end() ? known->second.order : next_order_;
  // The keyframe sent before it, if near enough to have been driven to in one go.
  std::optional<std::pair<mesher::KeyframeId, Pose>> previous;
  const auto before = by_order_.lower_bound(pose.order);
  if (before != by_order_.begin() && config_.max_sweep_distance_m > 0) {
    const mesher::KeyframeId id = std::prev(before)->second;
    const Pose& candidate = poses_.at(id.value);
    if ((candidate.position_W - pose.position_W).norm() * metres_per_unit_ <= config_.max_sweep_distance_m) {
      previous.emplace(id, candidate);
    }
  }
  if (previous) {
    pose.previous_position_W = previous->second.position_W;
    pose.previous_rotation_W_C = previous->second.rotation_W_C;
  }
  if (known == poses_.end()) {
    pose.stations = previous ? stationsFor((previous->second.position_W - pose.position_W).norm() * metres_per_unit_) : 0;
  }
  // Where the body was: at this keyframe, at its stations, half way and at the one before it.
  std::vector<Eigen::Isometry3d> bodies{baseAt(pose)};
  for (std::size_t station = 1; station <= pose.stations; ++station) {
    bodies.push_back(baseAt(stationPose(pose, station)));
  }
  if (previous) {
    bodies.push_back(baseAt(previous->second));
    Pose half = pose;
    half.position_W = 0.5 * (previous->second.position_W + pose.position_W);
    bodies.push_back(baseAt(half));
  }
  const std::vector<mesher::PointObservation> own = samplesAt(keyframe.id, pose);  // throws before any change
  dropContradicted(augmented, bodies);
  augmented.observations.insert(augmented.observations.end(), own.begin(), own.end());
  if (previous) {
    // The sweep: this sensor also observes the previous keyframe's samples.
    const std::vector<mesher::PointObservation> swept = samplesAt(previous->first, previous->second);
    augmented.observations.insert(augmented.observations.end(), swept.begin(), swept.end());
  }
  if (known == poses_.end()) {
    by_order_.emplace(next_order_++, keyframe.id);
    poses_.emplace(keyframe.id.value, pose);
  } else {
    known->second = pose;
  }
  return augmented;
}

std::vector<mesher::PointId> TrajectoryEvidence::remove(mesher::KeyframeId id) {
  const auto it = poses_.find(id.value);
  if (it == poses_.end()) return {};
  std::vector<mesher::PointId> ids;
  for (const mesher::PointObservation& sample : samplesAt(id, it->second)) ids.push_back(sample.point);
  by_order_.erase(it->second.order);
  poses_.erase(it);
  return ids;
}

}  // namespace terramesh::traversability
