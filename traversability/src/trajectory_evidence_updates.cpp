// The mesher updates of a run with trajectory evidence (TrajectoryEvidence::integrate and
// removeKeyframe): which of the evidence's outputs reach the mesher, and in which order; and the
// sensor's forward axis the samples are laid out along.
#include "traversability/trajectory_evidence.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace terramesh::traversability {

Eigen::Vector3d sensorForwardAxis(const Eigen::Vector3d& up_S) {
  return std::abs(up_S.normalized().z()) > 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
}

mesher::UpdateStats TrajectoryEvidence::integrate(mesher::Mesher& mesher, const mesher::Keyframe& keyframe) {
  mesher::UpdateStats stats = mesher.integrateKeyframe(augment(keyframe));
  // Points the robot drove through: outliers, out of the map (an earlier keyframe may have
  // inserted them).
  if (!newly_contradicted_.empty()) stats += mesher.removePoints(newly_contradicted_);
  // Obstacles seen later where the robot drove before: that drive's evidence goes, its views
  // before its samples (the views observe them).
  for (const mesher::KeyframeId& view : newly_withdrawn_views_) stats += mesher.removeKeyframe(view);
  for (const mesher::KeyframeId& overridden : newly_overridden_) stats += mesher.removePoints(sampleIdsOf(overridden));
  // The body views from the previous keyframe, or none any more (the mesher ignores unknown ids).
  const std::vector<mesher::Keyframe> views =
      config_.body_views ? bodyViewsOf(keyframe.id) : std::vector<mesher::Keyframe>{};
  for (const mesher::Keyframe& view : views) stats += mesher.integrateKeyframe(view);
  for (const mesher::KeyframeId& id : bodyViewIds(keyframe.id)) {
    const auto same = [&](const mesher::Keyframe& view) { return view.id == id; };
    if (std::none_of(views.begin(), views.end(), same)) stats += mesher.removeKeyframe(id);
  }
  // The undersides of the drives with a level beneath: this keyframe's (at its pose now), and those
  // of earlier keyframes its sensor lies beneath.
  if (const std::optional<mesher::Keyframe> view = undersideViewOf(keyframe.id)) stats += mesher.integrateKeyframe(*view);
  for (const mesher::KeyframeId& id : newly_undersided_) {
    if (const std::optional<mesher::Keyframe> view = undersideViewOf(id)) stats += mesher.integrateKeyframe(*view);
  }
  return stats;
}

mesher::UpdateStats TrajectoryEvidence::removeKeyframe(mesher::Mesher& mesher, mesher::KeyframeId id) {
  mesher::UpdateStats stats = mesher.removeKeyframe(id);
  for (const mesher::KeyframeId& view : bodyViewIds(id)) stats += mesher.removeKeyframe(view);
  stats += mesher.removeKeyframe(bodyViewId(id, kUndersideViewSlot));
  // The keyframe after it still observes the samples (its sweep rays): they go with their keyframe.
  const std::vector<mesher::PointId> samples = remove(id);
  if (!samples.empty()) stats += mesher.removePoints(samples);
  return stats;
}

mesher::UpdateStats TrajectoryEvidence::removeKeyframes(mesher::Mesher& mesher,
                                                        const std::vector<mesher::KeyframeId>& ids) {
  std::vector<mesher::KeyframeId> keyframes;
  for (const mesher::KeyframeId& id : ids) {
    keyframes.push_back(id);
    for (const mesher::KeyframeId& view : bodyViewIds(id)) keyframes.push_back(view);
    keyframes.push_back(bodyViewId(id, kUndersideViewSlot));
  }
  mesher::UpdateStats stats = mesher.removeKeyframes(keyframes);
  std::vector<mesher::PointId> samples;
  for (const mesher::KeyframeId& id : ids) {
    const std::vector<mesher::PointId> own = remove(id);
    samples.insert(samples.end(), own.begin(), own.end());
  }
  if (!samples.empty()) stats += mesher.removePoints(samples);
  return stats;
}

}  // namespace terramesh::traversability
