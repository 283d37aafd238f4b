#include "trajectory_evidence_run.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <variant>

namespace terramesh::cli {

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
  app.add_option("--underside-depth-m", options.underside_depth_m,
                 "with --robot: the driven ground is solid at least this deep (a parking deck's slab): cameras on "
                 "a level beneath it carve their level up to that depth, not the road above, metres (0: not assumed)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
}

TrajectoryEvidenceRun TrajectoryEvidenceRun::fromOptions(const TrajectoryEvidenceOptions& options,
                                                         const datasets::SlamStream& stream,
                                                         const TraversabilitySession* session, int min_views) {
  if (options.sensor_height_m && !session) throw UsageError("mesh: --sensor-height-m needs --robot");
  if (options.sensor_height_m && !(*options.sensor_height_m > 0 && *options.sensor_height_m <= 20)) {
    throw UsageError("mesh: --sensor-height-m must be in (0, 20]");
  }
  TrajectoryEvidenceRun run;
  if (!session || options.off) return run;
  traversability::TrajectoryEvidenceConfig config;
  config.station_spacing_m = options.station_spacing_m;
  config.underside_depth_m = options.underside_depth_m;
  config.later_obstacle_min_views = min_views;
  const traversability::RobotProfile& profile = session->profile();
  const traversability::MapFrame& frame = session->frame();
  const std::vector<Eigen::Vector3d> sensors_W = datasets::latestKeyframeCentres(stream);
  const std::vector<Eigen::Vector3d> points_W = datasets::latestPointEstimates(stream);
  const traversability::SensorHeightEstimate estimate =
      traversability::estimateSensorHeight(sensors_W, points_W, frame.up_W, frame.metres_per_unit, config);
  const traversability::TrajectoryEvidenceDecision decision = traversability::decideTrajectoryEvidence(
      estimate, profile.mountedSensorHeightM(), options.sensor_height_m, config);
  run.summary_ = decision.summary;
  run.warning_ = decision.warning;
  if (!decision.enabled) return run;
  const Eigen::Vector3d forward_S = traversability::sensorForwardAxis(stream.sensor_up_S);
  run.evidence_.emplace(profile, frame.up_W, frame.metres_per_unit, decision.sensor_height_m, forward_S, config);
  run.sensor_height_m_ = decision.sensor_height_m;
  run.sensor_height_source_ = decision.source;
  run.station_spacing_m_ = config.station_spacing_m;
  run.underside_depth_m_ = config.underside_depth_m;
  run.later_obstacle_min_views_ = config.later_obstacle_min_views;
  std::ostringstream patches;
  patches << "; patches of " << run.evidence_->samplesPerKeyframe() << " driven-ground samples under each keyframe";
  if (config.station_spacing_m > 0) {
    patches << " and at stations at most " << std::max(config.station_spacing_m, run.evidence_->patchLengthM())
            << " m apart between keyframes";
  }
  if (config.underside_depth_m > 0) {
    patches << "; where a keyframe's sensor lies beneath a drive (a level under a deck), that drive's samples get "
               "undersides "
            << config.underside_depth_m << " m below";
  }
  run.summary_ += patches.str();
  return run;
}

mesher::UpdateStats TrajectoryEvidenceRun::apply(mesher::Mesher& mesher, const datasets::StreamEvent& event) {
  if (!evidence_) return datasets::applyEvent(mesher, event);
  if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) return evidence_->integrate(mesher, *keyframe);
  if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
    return evidence_->removeKeyframe(mesher, removal->keyframe);
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
  for (std::size_t i = 0; i < events && i < stream.events.size(); ++i) replayEvent(stream.events[i]);
}

void TrajectoryEvidenceRun::replayEvent(const datasets::StreamEvent& event) {
  if (!evidence_) return;
  if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
    evidence_->augment(*keyframe);
  } else if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
    evidence_->remove(removal->keyframe);
  }
}

void TrajectoryEvidenceRun::replayRetire(const std::vector<mesher::KeyframeId>& ids) {
  if (!evidence_) return;
  for (const mesher::KeyframeId& id : ids) evidence_->remove(id);
}

std::string TrajectoryEvidenceRun::settings() const {
  if (!evidence_) return "off";
  std::ostringstream text;
  text.precision(17);
  text << "sensor_height_m=" << sensor_height_m_ << " samples=" << evidence_->samplesPerKeyframe()
       << " station_spacing_m=" << station_spacing_m_ << " underside_depth_m=" << underside_depth_m_
       << " body_views=1 body_view_ends=2 body_box_floor_m="
       << traversability::TrajectoryEvidenceConfig{}.body_box_floor_m
       << " later_obstacles=1 later_obstacle_views=" << later_obstacle_min_views_
       << " turns=curve start_body=footprint";
  return text.str();
}

traversability::DrivePoseLookup TrajectoryEvidenceRun::drivePoses() const {
  if (!evidence_) return {};
  const traversability::TrajectoryEvidence* evidence = &*evidence_;
  return [evidence](mesher::PointId id) { return evidence->baseOf(id); };
}

}  // namespace terramesh::cli
