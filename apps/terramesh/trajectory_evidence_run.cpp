#include "trajectory_evidence_run.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <variant>

namespace terramesh::cli {
namespace {

/// Latest pose of every keyframe and latest estimate of every point in the stream.
void latestEstimates(const datasets::SlamStream& stream, std::vector<Eigen::Vector3d>& sensors_W,
                     std::vector<Eigen::Vector3d>& points_W) {
  std::unordered_map<mesher::KeyframeId, Eigen::Vector3d> keyframes;
  std::unordered_map<mesher::PointId, Eigen::Vector3d> points;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      keyframes[keyframe->id] = keyframe->position_W_C;
      for (const mesher::PointObservation& observation : keyframe->observations) {
        points[observation.point] = observation.position_W;
      }
    } else if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
      keyframes.erase(removal->keyframe);
    }
  }
  // Keyframe order only changes which keyframe comes first in the medians' input: sort for
  // determinism.
  std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> sorted;
  for (const auto& [id, position] : keyframes) sorted.emplace_back(id.value, position);
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& entry : sorted) sensors_W.push_back(entry.second);
  points_W.reserve(points.size());
  for (const auto& entry : points) points_W.push_back(entry.second);
}

}  // namespace

void addTrajectoryEvidenceOptions(CLI::App& app, TrajectoryEvidenceOptions& options) {
  app.add_flag("--no-trajectory-evidence", options.off,
               "with --robot: do not add the driven ground under the keyframes and the body volume along the path "
               "as evidence (on by default when the trajectory looks driven)");
  app.add_option("--sensor-height-m", options.sensor_height_m,
                 "with --robot: height of the sensor above the ground contact plane, metres (overrides the profile's "
                 "sensor_height_m and the estimate from the data)")
      ->check(positiveNumber());
  app.add_option("--station-spacing-m", options.station_spacing_m,
                 "with --robot: driven-ground patches between keyframes at most this far apart along the path, "
                 "metres (0: only under the keyframes)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
}

TrajectoryEvidenceRun TrajectoryEvidenceRun::fromOptions(const TrajectoryEvidenceOptions& options,
                                                         const datasets::SlamStream& stream,
                                                         const TraversabilitySession* session) {
  if (options.sensor_height_m && !session) throw UsageError("mesh: --sensor-height-m needs --robot");
  if (options.sensor_height_m && !(*options.sensor_height_m > 0 && *options.sensor_height_m <= 20)) {
    throw UsageError("mesh: --sensor-height-m must be in (0, 20]");
  }
  TrajectoryEvidenceRun run;
  if (!session || options.off) return run;
  traversability::TrajectoryEvidenceConfig config;
  config.station_spacing_m = options.station_spacing_m;
  const traversability::RobotProfile& profile = session->profile();
  const traversability::MapFrame& frame = session->frame();
  std::vector<Eigen::Vector3d> sensors_W, points_W;
  latestEstimates(stream, sensors_W, points_W);
  const traversability::SensorHeightEstimate estimate =
      traversability::estimateSensorHeight(sensors_W, points_W, frame.up_W, frame.metres_per_unit, config);
  const traversability::TrajectoryEvidenceDecision decision = traversability::decideTrajectoryEvidence(
      estimate, profile.mountedSensorHeightM(), options.sensor_height_m, config);
  run.summary_ = decision.summary;
  run.warning_ = decision.warning;
  if (!decision.enabled) return run;
  // The sensor's forward axis: +x for a LiDAR frame (z up), +z for a camera (y down).
  const Eigen::Vector3d forward_S =
      std::abs(stream.sensor_up_S.normalized().z()) > 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
  run.evidence_.emplace(profile, frame.up_W, frame.metres_per_unit, decision.sensor_height_m, forward_S, config);
  run.sensor_height_m_ = decision.sensor_height_m;
  run.sensor_height_source_ = decision.source;
  run.station_spacing_m_ = config.station_spacing_m;
  std::ostringstream patches;
  patches << "; patches of " << run.evidence_->samplesPerKeyframe() << " driven-ground samples under each keyframe";
  if (config.station_spacing_m > 0) {
    patches << " and at stations at most " << std::max(config.station_spacing_m, run.evidence_->patchLengthM())
            << " m apart between keyframes";
  }
  run.summary_ += patches.str();
  return run;
}

mesher::UpdateStats TrajectoryEvidenceRun::apply(mesher::Mesher& mesher, const datasets::StreamEvent& event) {
  if (!evidence_) return datasets::applyEvent(mesher, event);
  if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
    mesher::UpdateStats stats = mesher.integrateKeyframe(evidence_->augment(*keyframe));
    // Points the robot drove through: outliers, out of the map (an earlier keyframe may have
    // inserted them).
    if (!evidence_->newlyContradicted().empty()) stats += mesher.removePoints(evidence_->newlyContradicted());
    // Obstacles seen later where the robot drove before: that drive's evidence goes.
    for (const mesher::KeyframeId& view : evidence_->newlyWithdrawnViews()) stats += mesher.removeKeyframe(view);
    for (const mesher::KeyframeId& overridden : evidence_->newlyOverridden()) {
      stats += mesher.removePoints(evidence_->sampleIdsOf(overridden));
    }
    // The body views from the previous keyframe (or none any more: the mesher ignores unknown ids).
    const std::vector<mesher::Keyframe> views = evidence_->bodyViewsOf(keyframe->id);
    for (const mesher::Keyframe& view : views) stats += mesher.integrateKeyframe(view);
    if (views.empty()) {
      for (const mesher::KeyframeId& view : traversability::bodyViewIds(keyframe->id)) stats += mesher.removeKeyframe(view);
    }
    return stats;
  }
  if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
    mesher::UpdateStats stats = mesher.removeKeyframe(removal->keyframe);
    for (const mesher::KeyframeId& view : traversability::bodyViewIds(removal->keyframe)) {
      stats += mesher.removeKeyframe(view);
    }
    const std::vector<mesher::PointId> samples = evidence_->remove(removal->keyframe);
    // The keyframe after it still observes them (its sweep rays): they go with their keyframe.
    if (!samples.empty()) stats += mesher.removePoints(samples);
    return stats;
  }
  const auto& points = std::get<datasets::PointRemoval>(event).points;
  for (const mesher::PointId& id : points) {
    if (traversability::isDrivenGroundId(id)) {
      throw std::invalid_argument("remove_points: point id " + std::to_string(id.value) +
                                  " is in the range reserved for driven-ground samples; use --no-trajectory-evidence");
    }
  }
  return mesher.removePoints(points);
}

void TrajectoryEvidenceRun::replay(const datasets::SlamStream& stream, std::size_t events) {
  if (!evidence_) return;
  for (std::size_t i = 0; i < events && i < stream.events.size(); ++i) {
    const datasets::StreamEvent& event = stream.events[i];
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      evidence_->augment(*keyframe);
    } else if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
      evidence_->remove(removal->keyframe);
    }
  }
}

std::string TrajectoryEvidenceRun::settings() const {
  if (!evidence_) return "off";
  std::ostringstream text;
  text.precision(17);
  text << "sensor_height_m=" << sensor_height_m_ << " samples=" << evidence_->samplesPerKeyframe()
       << " station_spacing_m=" << station_spacing_m_ << " body_views=1 later_obstacles=1";
  return text.str();
}

traversability::DrivePoseLookup TrajectoryEvidenceRun::drivePoses() const {
  if (!evidence_) return {};
  const traversability::TrajectoryEvidence* evidence = &*evidence_;
  return [evidence](mesher::PointId id) { return evidence->baseOf(id); };
}

}  // namespace terramesh::cli
