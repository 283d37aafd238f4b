#include "baselines/slam_points.h"

#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_set>
#include <variant>

#include "traversability/traversability_map.h"

namespace terramesh::baselines {

void SlamPointsConfig::validate() const {
  std::ostringstream problems;
  if (min_views < 1) problems << " min_views: " << min_views << " (expected >= 1);";
  if (!std::isfinite(max_camera_distance_units)) {
    problems << " max_camera_distance_units: " << max_camera_distance_units << " (expected finite; <= 0 for none);";
  }
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("SlamPointsConfig:" + text);
}

namespace {

/// The keyframes alive at the end of the stream (latest version of each) and the removed points.
struct FinalState {
  std::map<mesher::KeyframeId, const mesher::Keyframe*> keyframes;
  std::unordered_set<mesher::PointId> removed;
};

FinalState finalState(const datasets::SlamStream& stream) {
  FinalState state;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      state.keyframes[keyframe->id] = keyframe;
      for (const mesher::PointObservation& o : keyframe->observations) state.removed.erase(o.point);
    } else if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
      state.keyframes.erase(removal->keyframe);
    } else {
      for (const mesher::PointId id : std::get<datasets::PointRemoval>(event).points) state.removed.insert(id);
    }
  }
  return state;
}

}  // namespace

SlamPoints collectSlamPoints(const datasets::SlamStream& stream, const SlamPointsConfig& config) {
  config.validate();
  const FinalState state = finalState(stream);
  // Last position of every point over the whole stream, in event order.
  std::map<mesher::PointId, Eigen::Vector3d> last_position;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      for (const mesher::PointObservation& o : keyframe->observations) last_position[o.point] = o.position_W;
    }
  }
  struct Seen {
    std::uint32_t views = 0;
    double nearest = std::numeric_limits<double>::infinity();
    Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
  };
  std::map<mesher::PointId, Seen> seen;
  const bool limited = config.max_camera_distance_units > 0;
  for (const auto& [id, keyframe] : state.keyframes) {
    for (const mesher::PointObservation& o : keyframe->observations) {
      if (state.removed.count(o.point) != 0) continue;
      const Eigen::Vector3d& p = last_position[o.point];
      if (!p.allFinite()) continue;
      const double distance = (p - keyframe->position_W_C).norm();
      if (limited && distance > config.max_camera_distance_units) continue;
      Seen& s = seen[o.point];
      s.views += 1;
      if (distance < s.nearest) {
        s.nearest = distance;
        s.viewpoint = keyframe->position_W_C;
      }
    }
  }
  SlamPoints points;
  for (const auto& [id, s] : seen) {
    if (s.views < static_cast<std::uint32_t>(config.min_views)) continue;
    points.ids.push_back(id);
    points.positions_W.push_back(last_position[id]);
    points.viewpoints_W.push_back(s.viewpoint);
    points.views.push_back(s.views);
  }
  return points;
}

Eigen::Vector3d streamUp(const datasets::SlamStream& stream) {
  std::vector<Eigen::Matrix3d> rotations;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      rotations.push_back(keyframe->rotation_W_C.toRotationMatrix());
    }
  }
  return traversability::estimateUpFromCameras(rotations, stream.sensor_up_S);
}

}  // namespace terramesh::baselines
