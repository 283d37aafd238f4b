#include "traversability/trajectory_evidence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <unordered_set>
#include <utility>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "ground_frame.h"

namespace terramesh::traversability {
namespace {

using internal::requireFrame;

/// The contact patch layout in the base frame (metres): the footprint's cross-section across the
/// heading through its centre (a disc's diameter, a rectangle's width), samples at most `spacing`
/// apart out to both edges. Patches along the path then form a ladder whose rails are the swept
/// footprint's edges. A ring would leave a notch between neighbouring stations that closing
/// geometry from beside the path reaches into; a grid over a long rectangle puts the rows of
/// overlapping patches nearly on top of each other, at heights that differ by the poses' noise.
/// A face's layers hold for the footprint centred on its centroid, which reaches as far past the
/// strip the drive swept as the centroid lies off the drive's centre line. A cross-section no
/// wider than `spacing` gets three rails, one on the centre line: its vertices are where the whole
/// footprint was driven (vertex planners such as mesh_navigation's move on them), and the faces
/// beside it lie a third and two thirds of the half width off it. Wider ones get an even number
/// of rails, none on the centre line: the faces between the two innermost rails straddle it
/// (with a centre rail the nearest lie a third of a gap off it, 0.3 m for the car).
std::vector<Eigen::Vector3d> patchLayout(const RobotProfile& profile, const TrajectoryEvidenceConfig& config) {
  const double half_width = config.patch_fraction * (profile.footprint == FootprintShape::kDisc
                                                         ? profile.footprint_radius_m
                                                         : 0.5 * profile.footprint_width_m);
  const int gaps = std::max(1, static_cast<int>(std::ceil(2.0 * half_width / config.sample_spacing_m)));
  const int count = gaps == 1 ? 3 : gaps + 1 + (gaps + 1) % 2;
  std::vector<Eigen::Vector3d> layout;
  for (int i = 0; i < count; ++i) layout.emplace_back(0, half_width * (2.0 * i / (count - 1) - 1.0), 0);
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
  require(max_sweep_sagitta_m >= 0 && max_sweep_sagitta_m <= 100, "max_sweep_sagitta_m", max_sweep_sagitta_m,
          "[0, 100]");
  require(station_spacing_m >= 0 && station_spacing_m <= 100, "station_spacing_m", station_spacing_m, "[0, 100]");
  require(underside_depth_m >= 0 && underside_depth_m <= 10, "underside_depth_m", underside_depth_m, "[0, 10]");
  require(beneath_radius_m > 0 && beneath_radius_m <= 1000, "beneath_radius_m", beneath_radius_m, "(0, 1000]");
  require(beneath_margin_m >= 0 && beneath_margin_m <= 100, "beneath_margin_m", beneath_margin_m, "[0, 100]");
  require(layer_gap_m > 0 && layer_gap_m <= 100, "layer_gap_m", layer_gap_m, "(0, 100]");
  require(body_box_floor_m >= 0 && body_box_floor_m <= 10, "body_box_floor_m", body_box_floor_m,
          "[0, 10]");
  require(estimate_radius_m > 0 && estimate_radius_m <= 100, "estimate_radius_m", estimate_radius_m, "(0, 100]");
  require(min_depth_below_m >= 0 && min_depth_below_m <= 100, "min_depth_below_m", min_depth_below_m, "[0, 100]");
  require(min_points_per_keyframe >= 1, "min_points_per_keyframe", min_points_per_keyframe, "an integer >= 1");
  require(envelope_quantile >= 0 && envelope_quantile <= 1, "envelope_quantile", envelope_quantile, "[0, 1]");
  require(ground_band_m >= 0 && ground_band_m <= 100, "ground_band_m", ground_band_m, "[0, 100]");
  require(min_keyframes >= 1, "min_keyframes", min_keyframes, "an integer >= 1");
  require(later_obstacle_min_views >= 1, "later_obstacle_min_views", later_obstacle_min_views, "an integer >= 1");
  require(min_keyframe_fraction >= 0 && min_keyframe_fraction <= 1, "min_keyframe_fraction", min_keyframe_fraction,
          "[0, 1]");
  require(max_sensor_height_m > 0 && max_sensor_height_m <= 1000, "max_sensor_height_m", max_sensor_height_m,
          "(0, 1000]");
  require(max_height_spread_m > 0 && max_height_spread_m <= 100, "max_height_spread_m", max_height_spread_m,
          "(0, 100]");
  require(ground_absorb_band_m >= 0 && ground_absorb_band_m <= 10, "ground_absorb_band_m", ground_absorb_band_m,
          "[0, 10]");
  require(disagreement_tolerance_m >= 0 && disagreement_tolerance_m <= 100, "disagreement_tolerance_m",
          disagreement_tolerance_m, "[0, 100]");
  if (problems.empty()) return;
  std::string message = "invalid trajectory evidence config:";
  for (const std::string& problem : problems) message += "\n  " + problem;
  throw std::invalid_argument(message);
}

struct TrajectoryEvidence::BodyIndex {
  BodyIndex(const Eigen::Vector3d& up_W, double cell, double beneath_cell)
      : plane(geometry::planFrame(up_W)), bases(beneath_cell), cells(cell), point_cells(cell) {}
  geometry::PlanFrame plane;
  /// Keyframe ids under the horizontal cell of their base (cell: beneath_radius_m).
  internal::HorizontalGrid<std::uint64_t> bases;
  /// Keyframe ids under the horizontal cell of each of their station bases (cell: the footprint's
  /// circumradius, so a body holding a point has its base in the 3 x 3 cells around it).
  internal::HorizontalGrid<std::uint64_t> cells;
  /// Every SLAM point seen: the drive order before its first sighting and, until
  /// later_obstacle_min_views keyframes saw it (`counted`), those that did.
  struct Sightings {
    std::uint64_t before_order = 0;
    std::vector<std::uint64_t> keyframes;
    bool counted = false;
  };
  std::unordered_map<std::uint64_t, Sightings> seen_points;
  /// The latest position of every SLAM point seen and not left out, and their ids by cell.
  std::unordered_map<std::uint64_t, Eigen::Vector3d> positions_W;
  internal::HorizontalGrid<std::uint64_t> point_cells;
};

TrajectoryEvidence::~TrajectoryEvidence() = default;
TrajectoryEvidence::TrajectoryEvidence(TrajectoryEvidence&&) noexcept = default;
TrajectoryEvidence& TrajectoryEvidence::operator=(TrajectoryEvidence&&) noexcept = default;

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
  rear_m_ = disc_ ? radius_m_ : half_length_m_;
  body_low_m_ = profile.max_step_m;
  body_high_m_ = profile.min_clearance_m;
  absorb_band_m_ = std::min(config_.ground_absorb_band_m, profile.max_step_m);
  bodies_ = std::make_unique<BodyIndex>(up_W_, profile.footprintCircumradiusM() / metres_per_unit_,
                                        config_.beneath_radius_m / metres_per_unit_);
  if (layout_B_m_.size() > kMaxDrivenSamplesPerKeyframe) {
    throw std::invalid_argument("trajectory evidence: " + std::to_string(layout_B_m_.size()) +
                                " samples per keyframe (at most " + std::to_string(kMaxDrivenSamplesPerKeyframe) +
                                "): increase sample_spacing_m");
  }
}

void TrajectoryEvidence::findLevelsBeneath(mesher::KeyframeId id, const Pose& pose) {
  newly_undersided_.clear();
  if (!(config_.underside_depth_m > 0)) return;
  const Eigen::Vector3d base = baseAt(pose).translation();
  const Eigen::Vector2d at = bodies_->plane.project(base);
  const double radius = config_.beneath_radius_m / metres_per_unit_, margin = config_.beneath_margin_m / metres_per_unit_;
  bodies_->bases.around(at, [&](std::uint64_t other_id) {
    if (other_id == id.value) return;
    const Pose& other = poses_.at(other_id);
    const Eigen::Vector3d other_base = baseAt(other).translation();
    if ((bodies_->plane.project(other_base) - at).norm() > radius) return;
    // This sensor under the other's ground, or the other's sensor under this ground.
    if (up_W_.dot(other_base - pose.position_W) > margin && undersided_.insert(other_id).second) {
      newly_undersided_.push_back(mesher::KeyframeId{other_id});
    }
    if (up_W_.dot(base - other.position_W) > margin) undersided_.insert(id.value);
  });
  bodies_->bases.add(at, id.value);
}

std::optional<mesher::Keyframe> TrajectoryEvidence::undersideViewOf(mesher::KeyframeId id) const {
  const auto it = poses_.find(id.value);
  if (it == poses_.end() || undersided_.count(id.value) == 0 || overridden_.count(id.value) != 0) return std::nullopt;
  mesher::Keyframe view;
  view.id = bodyViewId(id, kUndersideViewSlot);
  view.position_W_C = it->second.position_W;
  view.rotation_W_C = it->second.rotation_W_C;
  view.observations = undersidesOf(samplesAt(id, it->second));
  if (view.observations.empty()) return std::nullopt;
  return view;
}

void TrajectoryEvidence::configureMesher(mesher::MesherConfig& config) const {
  config.driven_ground_up_W = up_W_;
  config.driven_underside_depth_m = config_.underside_depth_m;
}

std::vector<mesher::PointObservation> TrajectoryEvidence::undersidesOf(
    const std::vector<mesher::PointObservation>& samples) const {
  std::vector<mesher::PointObservation> undersides;
  if (!(config_.underside_depth_m > 0)) return undersides;
  undersides.reserve(samples.size());
  for (mesher::PointObservation sample : samples) {
    sample.point.value += kDrivenUndersideIndex;
    sample.position_W -= (config_.underside_depth_m / metres_per_unit_) * up_W_;
    sample.kind = mesher::PointKind::kDrivenUnderside;
    undersides.push_back(sample);
  }
  return undersides;
}

bool TrajectoryEvidence::insideBody(const Eigen::Isometry3d& T_W_B, const Eigen::Vector3d& p_W) const {
  const Eigen::Vector3d p_B = (T_W_B.inverse() * p_W) * metres_per_unit_;
  if (!(p_B.z() > body_low_m_ && p_B.z() <= body_high_m_)) return false;
  if (disc_) return p_B.head<2>().norm() <= radius_m_;
  return std::abs(p_B.x()) <= half_length_m_ && std::abs(p_B.y()) <= half_width_m_;
}

bool TrajectoryEvidence::onDrivenGround(const Eigen::Isometry3d& T_W_B, const Eigen::Vector3d& p_W) const {
  if (!(absorb_band_m_ > 0)) return false;
  const Eigen::Vector3d p_B = (T_W_B.inverse() * p_W) * metres_per_unit_;
  if (!(std::abs(p_B.z()) <= absorb_band_m_)) return false;
  const double f = config_.patch_fraction;
  if (disc_) return p_B.head<2>().norm() <= f * radius_m_;
  return std::abs(p_B.x()) <= f * half_length_m_ && std::abs(p_B.y()) <= f * half_width_m_;
}

bool TrajectoryEvidence::onRecordedDrivenGround(const Eigen::Vector3d& p_W) const {
  if (!(absorb_band_m_ > 0)) return false;
  bool found = false;
  bodies_->cells.around(bodies_->plane.project(p_W), [&](std::uint64_t id) {
    if (found || overridden_.count(id) != 0) return;
    const Pose& pose = poses_.at(id);
    for (std::size_t station = 0; station <= pose.bodyStations() && !found; ++station) {
      found = onDrivenGround(baseAt(stationPose(pose, station)), p_W);
    }
  });
  return found;
}

void TrajectoryEvidence::leaveOut(mesher::PointId id, const Eigen::Vector3d& p_W, bool absorbed) {
  if (!contradicted_.emplace(id.value, bodies_->plane.project(p_W)).second) return;
  absorbed_count_ += absorbed ? 1 : 0;
  contradicted_count_ += absorbed ? 0 : 1;
  newly_contradicted_.push_back(id);
  const auto it = bodies_->positions_W.find(id.value);
  if (it == bodies_->positions_W.end()) return;
  bodies_->point_cells.erase(bodies_->plane.project(it->second), id.value);
  bodies_->positions_W.erase(it);
}

std::size_t TrajectoryEvidence::forgetPointsBeyond(const std::vector<Eigen::Vector3d>& keep_W, double radius_m) {
  const double radius = radius_m / metres_per_unit_;
  internal::HorizontalGrid<std::size_t> keep(keep_W, bodies_->plane, radius);
  const auto far = [&](const Eigen::Vector2d& at) {
    bool near = false;
    keep.around(at, [&](std::size_t i) { near = near || (bodies_->plane.project(keep_W[i]) - at).norm() <= radius; });
    return !near;
  };
  std::size_t forgotten = 0;
  for (auto it = bodies_->positions_W.begin(); it != bodies_->positions_W.end();) {
    const Eigen::Vector2d at = bodies_->plane.project(it->second);
    if (!far(at)) {
      ++it;
      continue;
    }
    bodies_->point_cells.erase(at, it->first);
    bodies_->seen_points.erase(it->first);
    it = bodies_->positions_W.erase(it);
    ++forgotten;
  }
  for (auto it = contradicted_.begin(); it != contradicted_.end();) {
    if (!far(it->second)) {
      ++it;
      continue;
    }
    bodies_->seen_points.erase(it->first);
    it = contradicted_.erase(it);
    ++forgotten;
  }
  return forgotten;
}

void TrajectoryEvidence::dropContradicted(mesher::Keyframe& keyframe, const std::vector<Eigen::Isometry3d>& bodies_W_B,
                                          std::size_t new_bodies) {
  newly_contradicted_.clear();
  // The points seen before, under the bodies new with this keyframe (its own and its stations').
  std::vector<std::tuple<std::uint64_t, Eigen::Vector3d, bool>> found;
  for (std::size_t b = 0; b < new_bodies && b < bodies_W_B.size(); ++b) {
    const Eigen::Isometry3d& T_W_B = bodies_W_B[b];
    bodies_->point_cells.around(bodies_->plane.project(T_W_B.translation()), [&](std::uint64_t id) {
      const Eigen::Vector3d& p_W = bodies_->positions_W.at(id);
      if (insideBody(T_W_B, p_W)) found.emplace_back(id, p_W, false);
      else if (onDrivenGround(T_W_B, p_W)) found.emplace_back(id, p_W, true);
    });
  }
  for (const auto& [id, p_W, absorbed] : found) leaveOut(mesher::PointId{id}, p_W, absorbed);
  // The points this keyframe sees: inside a body of this keyframe's drive, or on any drive's ground.
  const auto left_out = [&](const mesher::PointObservation& o) {
    if (contradicted_.count(o.point.value) != 0) return true;
    for (const Eigen::Isometry3d& T_W_B : bodies_W_B) {
      const bool inside = insideBody(T_W_B, o.position_W);
      if (!inside && !onDrivenGround(T_W_B, o.position_W)) continue;
      leaveOut(o.point, o.position_W, !inside);
      return true;
    }
    if (!onRecordedDrivenGround(o.position_W)) return false;
    leaveOut(o.point, o.position_W, true);
    return true;
  };
  auto& observations = keyframe.observations;
  observations.erase(std::remove_if(observations.begin(), observations.end(), left_out), observations.end());
  for (const mesher::PointObservation& o : observations) {
    auto [it, added] = bodies_->positions_W.try_emplace(o.point.value, o.position_W);
    if (!added) {
      if (it->second == o.position_W) continue;
      bodies_->point_cells.erase(bodies_->plane.project(it->second), o.point.value);
      it->second = o.position_W;
    }
    bodies_->point_cells.add(bodies_->plane.project(o.position_W), o.point.value);
  }
}

void TrajectoryEvidence::indexBodies(mesher::KeyframeId id, const Pose& pose, bool add) {
  for (std::size_t station = 0; station <= pose.stations; ++station) {
    const Eigen::Vector2d at = bodies_->plane.project(baseAt(stationPose(pose, station)).translation());
    if (add) {
      bodies_->cells.add(at, id.value);
    } else {
      bodies_->cells.erase(at, id.value);
    }
  }
}

void TrajectoryEvidence::findLaterObstacles(const mesher::Keyframe& keyframe, std::uint64_t before_order) {
  if (!config_.later_obstacles_win) return;
  const auto views = static_cast<std::size_t>(config_.later_obstacle_min_views);
  for (const mesher::PointObservation& o : keyframe.observations) {
    auto [seen, first] = bodies_->seen_points.try_emplace(o.point.value);
    BodyIndex::Sightings& sightings = seen->second;
    if (first) sightings.before_order = before_order;
    if (sightings.counted) continue;
    // Only the sighting that brings the point to `views` keyframes (a keyframe sent again counts once).
    if (views > 1) {
      std::vector<std::uint64_t>& by = sightings.keyframes;
      if (std::find(by.begin(), by.end(), keyframe.id.value) != by.end()) continue;
      by.push_back(keyframe.id.value);
      if (by.size() < views) continue;
      std::vector<std::uint64_t>().swap(by);
    }
    sightings.counted = true;
    bodies_->cells.around(bodies_->plane.project(o.position_W), [&](std::uint64_t id) {
      if (overridden_.count(id) != 0) return;
      const Pose& pose = poses_.at(id);
      if (pose.order >= sightings.before_order) return;
      for (std::size_t station = 0; station <= pose.bodyStations(); ++station) {
        if (!insideBody(baseAt(stationPose(pose, station)), o.position_W)) continue;
        overrideDrive(id, true);
        return;
      }
    });
  }
}

void TrajectoryEvidence::overrideDrive(std::uint64_t id, bool with_previous) {
  if (!overridden_.insert(id).second) return;
  newly_overridden_.push_back(mesher::KeyframeId{id});
  for (const mesher::KeyframeId& view : bodyViewIds(mesher::KeyframeId{id})) newly_withdrawn_views_.push_back(view);
  newly_withdrawn_views_.push_back(bodyViewId(mesher::KeyframeId{id}, kUndersideViewSlot));
  const Pose& pose = poses_.at(id);
  // The keyframe sent after it has its body view at this one's base.
  const auto after = by_order_.upper_bound(pose.order);
  if (after != by_order_.end()) {
    for (const mesher::KeyframeId& view : bodyViewIds(after->second)) newly_withdrawn_views_.push_back(view);
  }
  if (with_previous && pose.has_previous && poses_.count(pose.previous_id) != 0) overrideDrive(pose.previous_id, false);
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
  pose.curved = false;
  const auto before = by_order_.lower_bound(pose.order);
  if (before != by_order_.begin() && config_.max_sweep_distance_m > 0) {
    const mesher::KeyframeId id = std::prev(before)->second;
    const Pose& candidate = poses_.at(id.value);
    const double distance_m = (candidate.position_W - pose.position_W).norm() * metres_per_unit_;
    const Eigen::Vector3d forward = baseAt(pose).linear().col(0), before_forward = baseAt(candidate).linear().col(0);
    const double turn = std::atan2(forward.cross(before_forward).norm(), forward.dot(before_forward));
    const double sagitta_m = distance_m * turn / 8.0;
    if (distance_m <= config_.max_sweep_distance_m && sagitta_m <= config_.max_sweep_sagitta_m) {
      previous.emplace(id, candidate);
    } else if (distance_m <= config_.max_sweep_distance_m && followsTurn(candidate, pose, sagitta_m)) {
      previous.emplace(id, candidate);
      pose.curved = true;
    }
  }
  if (known == poses_.end()) {
    pose.stations = previous ? stationsFor((previous->second.position_W - pose.position_W).norm() * metres_per_unit_)
                             : stationsFor(rear_m_);
  }
  if (previous) {
    pose.previous_position_W = previous->second.position_W;
    pose.previous_rotation_W_C = previous->second.rotation_W_C;
  } else {
    // The start of a drive: the robot stood on its whole footprint, so its stations run back to
    // the footprint's rear edge (the last one on it) from a pose behind it, along its heading.
    const double n = static_cast<double>(pose.stations);
    const double back_m = pose.stations > 0 ? rear_m_ * (n + 1) / n : 0.0;
    pose.previous_position_W = pose.position_W - baseAt(pose).linear().col(0) * (back_m / metres_per_unit_);
    pose.previous_rotation_W_C = pose.rotation_W_C;
  }
  pose.has_previous = previous.has_value();
  pose.previous_id = previous ? previous->first.value : 0;
  // Where the body was: at this keyframe, at its stations, half way and at the one before it.
  std::vector<Eigen::Isometry3d> bodies{baseAt(pose)};
  for (std::size_t station = 1; station <= pose.bodyStations(); ++station) {
    bodies.push_back(baseAt(stationPose(pose, station)));
  }
  const std::size_t new_bodies = bodies.size();
  if (previous) {
    bodies.push_back(baseAt(previous->second));
    // Half way along the straight line (a turn's stations already follow its curve).
    Pose half = pose;
    half.position_W = 0.5 * (previous->second.position_W + pose.position_W);
    if (!pose.curved) bodies.push_back(baseAt(half));
  }
  const std::vector<mesher::PointObservation> own = samplesAt(keyframe.id, pose);  // throws before any change
  dropContradicted(augmented, bodies, new_bodies);
  newly_overridden_.clear();
  newly_withdrawn_views_.clear();
  findLaterObstacles(augmented, previous ? previous->second.order : pose.order);
  const bool overridden = overridden_.count(keyframe.id.value) != 0;
  if (!overridden) augmented.observations.insert(augmented.observations.end(), own.begin(), own.end());
  // No sweep from an overridden keyframe's sensor, nor to an overridden keyframe's samples.
  const bool sweep = previous && !overridden && overridden_.count(previous->first.value) == 0;
  if (sweep) {
    // The sweep: this sensor also observes the previous keyframe's samples (through a turn, those
    // its rays reach over the curve).
    std::vector<mesher::PointObservation> swept = samplesAt(previous->first, previous->second);
    if (pose.curved) swept = seenWithinTurn(pose, pose.position_W, swept);
    augmented.observations.insert(augmented.observations.end(), swept.begin(), swept.end());
  }
  if (known == poses_.end()) {
    by_order_.emplace(next_order_++, keyframe.id);
    poses_.emplace(keyframe.id.value, pose);
  } else {
    indexBodies(keyframe.id, known->second, false);
    bodies_->bases.erase(bodies_->plane.project(baseAt(known->second).translation()), keyframe.id.value);
    known->second = pose;
  }
  indexBodies(keyframe.id, pose, true);
  findLevelsBeneath(keyframe.id, pose);
  return augmented;
}

std::optional<Eigen::Isometry3d> TrajectoryEvidence::baseOf(mesher::PointId id) const {
  if (!isDrivenGroundId(id)) return std::nullopt;
  // The underside of ground sample i was put down with it.
  const std::uint64_t index = id.value & (kMaxDrivenSamplesPerKeyframe - 1);
  const std::uint64_t keyframe = (id.value & ~kDrivenGroundIdBit) >> kDrivenSampleIndexBits;
  const auto it = poses_.find(keyframe);
  if (it == poses_.end()) return std::nullopt;
  const std::size_t station = static_cast<std::size_t>(index) / layout_B_m_.size();
  if (station > it->second.stations) return std::nullopt;
  return baseAt(stationPose(it->second, station));
}

std::vector<mesher::PointId> TrajectoryEvidence::sampleIdsOf(mesher::KeyframeId id) const {
  const auto it = poses_.find(id.value);
  if (it == poses_.end()) return {};
  std::vector<mesher::PointId> ids;
  const std::vector<mesher::PointObservation> samples = samplesAt(id, it->second);
  for (const mesher::PointObservation& sample : samples) ids.push_back(sample.point);
  for (const mesher::PointObservation& sample : undersidesOf(samples)) ids.push_back(sample.point);
  return ids;
}

std::vector<mesher::Keyframe> TrajectoryEvidence::bodyViewsOf(mesher::KeyframeId id) const {
  const auto it = poses_.find(id.value);
  if (it == poses_.end() || !it->second.has_previous || overridden_.count(id.value) != 0 ||
      overridden_.count(it->second.previous_id) != 0) {
    return {};
  }
  const Pose previous = it->second.previousEnd();
  const double height_m = std::min(body_high_m_, sensor_height_m_);
  const double side_m = disc_ ? radius_m_ : half_width_m_;
  const std::vector<mesher::PointObservation> samples = samplesAt(id, it->second);
  // On the centre line, on the left (+y) and on the right; over each end's base.
  const double lateral_m[kBodyViewsPerEnd] = {0.0, side_m, -side_m};
  const Pose* ends[2] = {&previous, &it->second};
  std::vector<mesher::Keyframe> views(config_.body_views_from_both_ends ? kBodyViewSlots : kBodyViewsPerEnd);
  for (std::uint64_t slot = 0; slot < views.size(); ++slot) {
    const Pose& end = *ends[slot / kBodyViewsPerEnd];
    mesher::Keyframe& view = views[slot];
    view.id = bodyViewId(id, slot);
    const Eigen::Vector3d top_B(0, lateral_m[slot % kBodyViewsPerEnd], height_m);
    view.position_W_C = baseAt(end) * (top_B / metres_per_unit_);
    view.rotation_W_C = end.rotation_W_C;
    view.observations = it->second.curved ? seenWithinTurn(it->second, view.position_W_C, samples) : samples;
  }
  views.front().free_boxes = sweptBoxes(it->second);
  const auto blind = [](const mesher::Keyframe& view) {
    return view.observations.empty() && view.free_boxes.empty();
  };
  views.erase(std::remove_if(views.begin(), views.end(), blind), views.end());
  return views;
}

std::vector<mesher::PointId> TrajectoryEvidence::remove(mesher::KeyframeId id) {
  const auto it = poses_.find(id.value);
  if (it == poses_.end()) return {};
  std::vector<mesher::PointId> ids = sampleIdsOf(id);
  indexBodies(id, it->second, false);
  bodies_->bases.erase(bodies_->plane.project(baseAt(it->second).translation()), id.value);
  overridden_.erase(id.value);
  undersided_.erase(id.value);
  by_order_.erase(it->second.order);
  poses_.erase(it);
  return ids;
}

}  // namespace terramesh::traversability
