// Where the driven-ground samples go: the robot base under a keyframe's sensor, the stations
// between it and the keyframe before (along the straight way or through a turn), and the samples
// of each patch.
#include "traversability/trajectory_evidence.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/closest_point.h"

namespace terramesh::traversability {

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
  at.rotation_W_C = pose.previous_rotation_W_C.normalized().slerp(t, pose.rotation_W_C.normalized());
  const Eigen::Vector3d chord = pose.position_W - pose.previous_position_W;
  if (!pose.curved) {
    at.position_W = pose.previous_position_W + t * chord;
    return at;
  }
  // Through a turn: the cubic Hermite curve from the previous pose to this one, tangent to both
  // headings (in reverse if the robot backed), as long as the way; it rises linearly along up.
  const Pose before = pose.previousEnd();
  const Eigen::Vector3d rise = chord.dot(up_W_) * up_W_;
  const Eigen::Vector3d f0 = baseAt(before).linear().col(0), f1 = baseAt(pose).linear().col(0);
  const double length = (chord - rise).norm() * ((chord - rise).dot(f0 + f1) < 0 ? -1.0 : 1.0);
  const Eigen::Vector3d m0 = length * f0 + rise, m1 = length * f1 + rise;
  const double t2 = t * t, t3 = t2 * t;
  at.position_W = (2 * t3 - 3 * t2 + 1) * pose.previous_position_W + (t3 - 2 * t2 + t) * m0 +
                  (3 * t2 - 2 * t3) * pose.position_W + (t3 - t2) * m1;
  return at;
}

std::vector<mesher::FreeBox> TrajectoryEvidence::sweptBoxes(const Pose& pose) const {
  std::vector<mesher::FreeBox> boxes;
  const double high_m = std::min(body_high_m_, sensor_height_m_);
  if (!config_.body_boxes || !pose.has_previous || !(high_m > config_.body_box_floor_m))
    return boxes;
  std::vector<Eigen::Isometry3d> bases{baseAt(pose)};
  for (std::size_t station = 1; station <= pose.bodyStations(); ++station) {
    bases.push_back(baseAt(stationPose(pose, station)));
  }
  bases.push_back(baseAt(pose.previousEnd()));
  const double u = metres_per_unit_;
  // The boxes stand level on their base: on a slope the ground rises under one end of a box by
  // the slope times its reach along the way, and its floor rises by as much.
  Eigen::Vector3d way = bases.front().translation() - bases.back().translation();
  const double rise = way.dot(up_W_);
  way -= rise * up_W_;
  const double slope = way.norm() > 0 ? std::abs(rise) / way.norm() : 0.0;
  if (way.norm() > 0) way.normalize();
  const auto box = [&](const Eigen::Vector3d& base_W, const Eigen::Matrix3d& R_W_B, double half_x_m,
                       double half_y_m) {
    const double reach_m =
        half_x_m * std::abs(R_W_B.col(0).dot(way)) + half_y_m * std::abs(R_W_B.col(1).dot(way));
    const double low_m = config_.body_box_floor_m + slope * reach_m;
    mesher::FreeBox b;
    b.centre_W = base_W + R_W_B.col(2) * (0.5 * (high_m + low_m) / u);
    b.rotation_W_B = Eigen::Quaterniond(R_W_B);
    b.half_extents =
        Eigen::Vector3d(half_x_m / u, half_y_m / u, 0.5 * std::max(high_m - low_m, 0.0) / u);
    return b;
  };
  const auto keep = [&](const mesher::FreeBox& b) {
    if (b.half_extents.minCoeff() > 0) boxes.push_back(b);
  };
  if (!disc_) {
    for (const Eigen::Isometry3d& base : bases)
      keep(box(base.translation(), base.linear(), half_length_m_, half_width_m_));
    return boxes;
  }
  for (std::size_t i = 0; i + 1 < bases.size(); ++i) {
    const Eigen::Vector3d a = bases[i].translation(), b = bases[i + 1].translation();
    Eigen::Vector3d along = (b - a) - (b - a).dot(up_W_) * up_W_;
    const double length = along.norm();
    if (!(length > 0)) continue;
    along /= length;
    Eigen::Matrix3d R_W_B;
    R_W_B.col(0) = along;
    R_W_B.col(1) = up_W_.cross(along);
    R_W_B.col(2) = up_W_;
    keep(box(0.5 * (a + b), R_W_B, 0.5 * length * u, radius_m_));
  }
  return boxes;
}

bool TrajectoryEvidence::followsTurn(const Pose& before, const Pose& pose, double sagitta_m) const {
  if (!config_.stations_along_turns || !(sagitta_m <= (disc_ ? radius_m_ : half_width_m_))) return false;
  Eigen::Vector3d way = pose.position_W - before.position_W;
  way -= way.dot(up_W_) * up_W_;
  if (!(way.norm() > 0)) return false;
  way.normalize();
  // Both headings within 60 degrees of the way, forwards or both in reverse: not a robot walking
  // sideways, whose heading says nothing about the curve it took.
  const double a = way.dot(baseAt(before).linear().col(0)), b = way.dot(baseAt(pose).linear().col(0));
  return (a >= 0.5 && b >= 0.5) || (a <= -0.5 && b <= -0.5);
}

std::vector<mesher::PointObservation> TrajectoryEvidence::seenWithinTurn(
    const Pose& pose, const Eigen::Vector3d& from_W, const std::vector<mesher::PointObservation>& samples) const {
  const auto flat = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return p - p.dot(up_W_) * up_W_; };
  // The curve's centre line under the bases, in 16 pieces from the previous keyframe's on.
  const Pose before = pose.previousEnd();
  std::vector<Eigen::Vector3d> line{flat(baseAt(before).translation())};
  Pose dense = pose;
  dense.stations = 15;
  for (std::size_t station = 1; station <= dense.stations; ++station) {
    line.push_back(flat(baseAt(stationPose(dense, station)).translation()));
  }
  line.push_back(flat(baseAt(pose).translation()));
  const double reach = ((disc_ ? radius_m_ : half_width_m_) + 0.01) / metres_per_unit_;
  const auto near_line = [&](const Eigen::Vector3d& q) {
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
      if ((geometry::closestPointOnSegment(q, line[i], line[i + 1]) - q).norm() <= reach) return true;
    }
    return false;
  };
  std::vector<mesher::PointObservation> seen;
  const Eigen::Vector3d from = flat(from_W);
  for (const mesher::PointObservation& sample : samples) {
    const Eigen::Vector3d to = flat(sample.position_W);
    bool inside = true;
    for (int k = 1; k < 8 && inside; ++k) inside = near_line(from + (k / 8.0) * (to - from));
    if (inside) seen.push_back(sample);
  }
  return seen;
}

std::size_t TrajectoryEvidence::turnCount() const {
  return static_cast<std::size_t>(
      std::count_if(poses_.begin(), poses_.end(), [](const auto& entry) { return entry.second.curved; }));
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

}  // namespace terramesh::traversability
