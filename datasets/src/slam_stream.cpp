#include "datasets/slam_stream.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "mesher/mesher.h"

namespace terramesh::datasets {

std::size_t SlamStream::keyframeEventCount() const {
  std::size_t count = 0;
  for (const StreamEvent& event : events) {
    if (std::holds_alternative<mesher::Keyframe>(event)) ++count;
  }
  return count;
}

void applyMeshingAdvice(const SlamStream& stream, mesher::MesherConfig& config) {
  if (stream.recommended_min_views > 0) config.min_views = stream.recommended_min_views;
  if (stream.recommended_steiner_step_m > 0) config.steiner_step_m = stream.recommended_steiner_step_m;
}

double observationDistanceQuantile(const SlamStream& stream, double quantile) {
  if (!(quantile >= 0.0 && quantile <= 1.0)) {
    throw std::invalid_argument("observationDistanceQuantile: quantile must be within [0, 1]");
  }
  std::vector<double> distances;
  for (const StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (keyframe == nullptr) continue;
    for (const mesher::PointObservation& observation : keyframe->observations) {
      distances.push_back((observation.position_W - keyframe->position_W_C).norm());
    }
  }
  if (distances.empty()) return 0.0;
  // Nearest rank: the smallest distance with at least `quantile` of all distances at or below it.
  const double rank = std::ceil(quantile * static_cast<double>(distances.size()));
  const std::size_t index = rank < 1.0 ? 0 : static_cast<std::size_t>(rank) - 1;
  std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(index),
                   distances.end());
  return distances[index];
}

std::vector<LatestKeyframePose> latestKeyframePoses(const SlamStream& stream) {
  std::map<mesher::KeyframeId, LatestKeyframePose> latest;
  for (const StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      latest[keyframe->id] = {keyframe->id, keyframe->position_W_C, keyframe->rotation_W_C};
    } else if (const auto* removal = std::get_if<KeyframeRemoval>(&event)) {
      latest.erase(removal->keyframe);
    }
  }
  std::vector<LatestKeyframePose> poses;
  poses.reserve(latest.size());
  for (const auto& entry : latest) poses.push_back(entry.second);
  return poses;
}

std::vector<Eigen::Vector3d> latestKeyframeCentres(const SlamStream& stream) {
  std::vector<Eigen::Vector3d> centres;
  for (const LatestKeyframePose& pose : latestKeyframePoses(stream)) centres.push_back(pose.position_W_C);
  return centres;
}

std::vector<Eigen::Vector3d> latestPointEstimates(const SlamStream& stream) {
  std::unordered_map<mesher::PointId, Eigen::Vector3d> latest;
  for (const StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (keyframe == nullptr) continue;
    for (const mesher::PointObservation& observation : keyframe->observations) {
      latest[observation.point] = observation.position_W;
    }
  }
  std::vector<std::pair<mesher::PointId, Eigen::Vector3d>> sorted(latest.begin(), latest.end());
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> points;
  points.reserve(sorted.size());
  for (const auto& entry : sorted) points.push_back(entry.second);
  return points;
}

mesher::UpdateStats applyEvent(mesher::Mesher& mesher, const StreamEvent& event) {
  return std::visit(
      [&mesher](const auto& message) -> mesher::UpdateStats {
        using Message = std::decay_t<decltype(message)>;
        if constexpr (std::is_same_v<Message, mesher::Keyframe>) {
          return mesher.integrateKeyframe(message);
        } else if constexpr (std::is_same_v<Message, PointRemoval>) {
          return mesher.removePoints(message.points);
        } else {
          return mesher.removeKeyframe(message.keyframe);
        }
      },
      event);
}

}  // namespace terramesh::datasets
