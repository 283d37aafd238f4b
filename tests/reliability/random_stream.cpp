#include "random_stream.h"

#include <algorithm>
#include <cmath>

namespace terramesh::test {
namespace {

constexpr double kCameraRadius_m = 8.0;
constexpr double kPillarRadius_m = 4.0;
constexpr double kWallRadius_m = 12.0;
constexpr double kCeiling_m = 3.0;
/// Corrections and removals pick among this many newest alive keyframes.
constexpr std::size_t kRecentKeyframes = 100;

}  // namespace

RandomStream::RandomStream(const RandomStreamConfig& config) : config_(config), rng_(config.seed) {}

mesher::AxisAlignedBox RandomStream::bounds() {
  return {Eigen::Vector3d(-26, -26, -12), Eigen::Vector3d(26, 26, 15)};
}

double RandomStream::uniform(double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng_);
}

bool RandomStream::chance(double p) { return uniform(0.0, 1.0) < p; }

Eigen::Vector3d RandomStream::noisy(const Eigen::Vector3d& p) {
  std::normal_distribution<double> noise(0.0, config_.noise_std_m);
  // One statement per draw: the order of a constructor's arguments is unspecified (gcc draws the
  // last first, clang the first), so a one-line form gives each compiler a different stream.
  // Drawn z, y, x: the order gcc used, so Release streams stay as they were.
  const double dz = noise(rng_);
  const double dy = noise(rng_);
  const double dx = noise(rng_);
  return p + Eigen::Vector3d(dx, dy, dz);
}

Eigen::Vector3d RandomStream::surfaceSample(const Eigen::Vector3d& camera_W) {
  const double phi_c = std::atan2(camera_W.y(), camera_W.x());
  Eigen::Vector3d p = camera_W;
  for (int attempt = 0; attempt < 10; ++attempt) {
    const double phi = phi_c + uniform(-0.7, 0.7);
    const double kind = uniform(0.0, 1.0);
    if (kind < 0.5) {  // floor or ceiling
      const double r = std::sqrt(uniform(kPillarRadius_m * kPillarRadius_m, kWallRadius_m * kWallRadius_m));
      p = Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), kind < 0.3 ? 0.0 : kCeiling_m);
    } else {  // outer wall or pillar
      const double r = kind < 0.8 ? kWallRadius_m : kPillarRadius_m;
      p = Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), uniform(0.0, kCeiling_m));
    }
    if ((p - camera_W).norm() <= config_.range_m) return p;
  }
  return p;
}

bool RandomStream::next(StreamEvent& event) {
  if (pending_.empty()) {
    if (counts_.keyframes >= config_.keyframes) return false;
    StreamEvent keyframe;
    makeKeyframe(keyframe);
    pending_.push_back(std::move(keyframe));
    const std::size_t newest_safe = alive_.size() >= 2 ? alive_.size() - 1 : 0;
    if (newest_safe > 0 && chance(config_.correction_probability)) {
      StreamEvent correction;
      makeCorrection(correction);
      pending_.push_back(std::move(correction));
    }
    if (chance(config_.cull_probability)) {
      StreamEvent cull;
      makeCull(cull);
      if (!cull.points.empty()) pending_.push_back(std::move(cull));
    }
    if (alive_.size() >= 3 && chance(config_.keyframe_removal_probability)) {
      const std::size_t first = alive_.size() > kRecentKeyframes ? alive_.size() - kRecentKeyframes : 0;
      const auto index = static_cast<std::size_t>(uniform(static_cast<double>(first),
                                                          static_cast<double>(alive_.size() - 1)));
      StreamEvent removal;
      removal.kind = StreamEvent::Kind::kRemoveKeyframe;
      removal.removed = alive_[index].id;
      alive_.erase(alive_.begin() + static_cast<std::ptrdiff_t>(index));
      ++counts_.keyframe_removals;
      pending_.push_back(std::move(removal));
    }
    while (config_.window > 0 && alive_.size() > config_.window) {
      StreamEvent eviction;
      eviction.kind = StreamEvent::Kind::kRemoveKeyframe;
      eviction.removed = alive_.front().id;
      alive_.pop_front();
      ++counts_.keyframe_removals;
      pending_.push_back(std::move(eviction));
    }
  }
  event = std::move(pending_.front());
  pending_.pop_front();
  return true;
}

void RandomStream::makeKeyframe(StreamEvent& event) {
  const std::size_t k = counts_.keyframes++;
  const double theta = static_cast<double>(k) * config_.step_rad;
  mesher::Keyframe& keyframe = event.keyframe;
  keyframe.id.value = next_keyframe_id_++;
  keyframe.position_W_C = Eigen::Vector3d(kCameraRadius_m * std::cos(theta), kCameraRadius_m * std::sin(theta),
                                          1.5 + uniform(-0.3, 0.3));
  keyframe.rotation_W_C = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ());
  // Forget points too old to be tracked.
  while (!recent_points_.empty() && points_.at(recent_points_.front()).created + config_.track_keyframes < k) {
    points_.erase(recent_points_.front());
    recent_points_.pop_front();
  }
  std::vector<std::uint64_t> seen;
  for (std::uint64_t id : recent_points_) {
    Point& point = points_.at(id);
    if (point.culled || (point.true_W - keyframe.position_W_C).norm() > config_.range_m ||
        !chance(config_.match_probability)) {
      continue;
    }
    if (chance(config_.move_probability)) {
      point.estimate_W = noisy(point.true_W);
      ++counts_.moved_observations;
    }
    keyframe.observations.push_back({point.id, point.estimate_W});
    seen.push_back(id);
  }
  for (int i = 0; i < config_.new_points_per_keyframe; ++i) {
    Point point;
    point.id.value = next_point_id_++;
    point.created = k;
    point.true_W = surfaceSample(keyframe.position_W_C);
    point.estimate_W = noisy(point.true_W);
    if (chance(config_.outlier_fraction)) {
      const double factor = chance(0.5) ? uniform(0.5, 0.8) : uniform(1.25, 2.0);
      const mesher::AxisAlignedBox box = bounds();
      point.estimate_W = (keyframe.position_W_C + factor * (point.true_W - keyframe.position_W_C))
                             .cwiseMax(box.min_W + Eigen::Vector3d::Constant(1.0))
                             .cwiseMin(box.max_W - Eigen::Vector3d::Constant(1.0));
      ++counts_.outliers;
    } else if (!seen.empty() && chance(config_.duplicate_probability)) {
      point.estimate_W = points_.at(seen[rng_() % seen.size()]).estimate_W;
      ++counts_.duplicates;
    }
    keyframe.observations.push_back({point.id, point.estimate_W});
    seen.push_back(point.id.value);
    points_.emplace(point.id.value, point);
    recent_points_.push_back(point.id.value);
  }
  counts_.observations += keyframe.observations.size();
  alive_.push_back({keyframe.id, keyframe.position_W_C, seen});
}

void RandomStream::makeCorrection(StreamEvent& event) {
  // Any alive keyframe but the newest, among the recent ones.
  const std::size_t first = alive_.size() > kRecentKeyframes ? alive_.size() - kRecentKeyframes : 0;
  const auto index = static_cast<std::size_t>(uniform(static_cast<double>(first),
                                                      static_cast<double>(alive_.size() - 1)));
  SentKeyframe& sent = alive_[index];
  const double dz = uniform(-0.05, 0.05);  // one draw per statement, z first (see noisy())
  const double dy = uniform(-0.1, 0.1);
  const double dx = uniform(-0.1, 0.1);
  sent.centre_W += Eigen::Vector3d(dx, dy, dz);
  mesher::Keyframe& keyframe = event.keyframe;
  keyframe.id = sent.id;
  keyframe.position_W_C = sent.centre_W;
  std::vector<std::uint64_t> kept;
  for (std::uint64_t id : sent.points) {
    const auto it = points_.find(id);
    if (it == points_.end()) continue;  // too old to know: SLAM drops it from the keyframe
    if (it->second.culled) continue;
    if (chance(config_.move_probability)) it->second.estimate_W = noisy(it->second.true_W);
    keyframe.observations.push_back({it->second.id, it->second.estimate_W});
    kept.push_back(id);
  }
  sent.points = std::move(kept);
  counts_.observations += keyframe.observations.size();
  ++counts_.corrections;
}

void RandomStream::makeCull(StreamEvent& event) {
  event.kind = StreamEvent::Kind::kRemovePoints;
  for (std::uint64_t id : recent_points_) {
    Point& point = points_.at(id);
    if (!point.culled && chance(config_.cull_fraction)) {
      point.culled = true;
      event.points.push_back(point.id);
    }
  }
  counts_.point_removals += event.points.size();
}

}  // namespace terramesh::test
