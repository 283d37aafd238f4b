#pragma once

// Trajectory evidence during `terramesh mesh --robot R` (on by default; traversability/
// trajectory_evidence.h): decides once from the whole stream whether and at which sensor height
// the trajectory was driven, then appends the driven-ground samples to every keyframe event and
// removes a keyframe's samples with it.
#include <cstddef>
#include <optional>
#include <string>

#include "cli_args.h"
#include "datasets/slam_stream.h"
#include "mesher/mesher.h"
#include "traversability/trajectory_evidence.h"
#include "traversability_session.h"

namespace terramesh::cli {

/// --no-trajectory-evidence and --sensor-height-m.
struct TrajectoryEvidenceOptions {
  bool off = false;
  std::optional<double> sensor_height_m;
  /// TrajectoryEvidenceConfig::station_spacing_m (0: no stations between keyframes).
  double station_spacing_m = traversability::TrajectoryEvidenceConfig{}.station_spacing_m;
  /// TrajectoryEvidenceConfig::underside_depth_m (0: no underside under the driven ground).
  double underside_depth_m = traversability::TrajectoryEvidenceConfig{}.underside_depth_m;
};
/// Adds the options to `app`, filling `options`.
void addTrajectoryEvidenceOptions(CLI::App& app, TrajectoryEvidenceOptions& options);

class TrajectoryEvidenceRun {
 public:
  /// Off without a session (no --robot) or with --no-trajectory-evidence; otherwise estimates the
  /// sensor height from the stream's latest keyframe poses and point estimates and decides. A
  /// later obstacle needs `min_views` keyframes, as a point the mesher inserts.
  /// @throw UsageError for --sensor-height-m without --robot or out of (0, 20].
  static TrajectoryEvidenceRun fromOptions(const TrajectoryEvidenceOptions& options, const datasets::SlamStream& stream,
                                           const TraversabilitySession* session, int min_views);

  /// Applies one stream event to the mesher, with the evidence when on (exactly
  /// datasets::applyEvent when off). A keyframe removal also removes its samples (one stats sum).
  /// @throw std::invalid_argument if a SLAM point id uses the range reserved for the samples.
  mesher::UpdateStats apply(mesher::Mesher& mesher, const datasets::StreamEvent& event);
  /// The online freeze: removes keyframes `ids` from `mesher` in one update, with their driven
  /// evidence (TrajectoryEvidence::removeKeyframes; mesher::Mesher::removeKeyframes when off).
  mesher::UpdateStats retire(mesher::Mesher& mesher, const std::vector<mesher::KeyframeId>& ids) {
    return evidence_ ? evidence_->removeKeyframes(mesher, ids) : mesher.removeKeyframes(ids);
  }
  /// The online freeze: forgets the SLAM points farther than `radius_m` from each of `keep_W`
  /// (TrajectoryEvidence::forgetPointsBeyond; nothing when off).
  void forgetPointsBeyond(const std::vector<Eigen::Vector3d>& keep_W, double radius_m) {
    if (evidence_) evidence_->forgetPointsBeyond(keep_W, radius_m);
  }
  /// Brings the keyframe poses up to event `events` without meshing (for --resume).
  void replay(const datasets::SlamStream& stream, std::size_t events);
  /// One event of that replay: what apply() records, without the mesher.
  void replayEvent(const datasets::StreamEvent& event);
  /// What retire() records, without the mesher (--resume of a run with the freeze).
  void replayRetire(const std::vector<mesher::KeyframeId>& ids);

  bool enabled() const { return evidence_.has_value(); }
  /// The mesher's ground rule for this evidence (TrajectoryEvidence::configureMesher); none when off.
  void configureMesher(mesher::MesherConfig& config) const {
    if (evidence_) evidence_->configureMesher(config);
  }
  /// Where the robot stood on each driven-ground sample (TrajectoryEvidence::baseOf); empty when
  /// off. It reads this run, which must outlive it.
  traversability::DrivePoseLookup drivePoses() const;
  /// The sensor's height above the ground contact plane the samples use, metres (0 when off).
  double sensorHeightM() const { return sensor_height_m_; }
  /// Where that height came from: "--sensor-height-m", "the robot profile" or "the data".
  const std::string& sensorHeightSource() const { return sensor_height_source_; }
  /// What was inferred, one line (empty when off by option or without --robot).
  const std::string& summary() const { return summary_; }
  /// SLAM points dropped so far because the robot drove through them (outliers).
  std::size_t contradictedPoints() const { return evidence_ ? evidence_->contradictedCount() : 0; }
  /// SLAM points on the ground the robot drove, left out for the driven samples, so far.
  std::size_t absorbedPoints() const { return evidence_ ? evidence_->absorbedCount() : 0; }
  /// Keyframes whose drive obstacles seen later overrode so far.
  std::size_t overriddenKeyframes() const { return evidence_ ? evidence_->overriddenCount() : 0; }
  /// Keyframes that must see a point before it overrides a drive (the mesher's min_views).
  int laterObstacleMinViews() const { return later_obstacle_min_views_; }
  /// Keyframes driven to through a turn, their stations along the curve.
  std::size_t turnKeyframes() const { return evidence_ ? evidence_->turnCount() : 0; }
  /// Keyframes with a level beneath their drive, whose samples got undersides.
  std::size_t undersidedKeyframes() const { return evidence_ ? evidence_->undersidedCount() : 0; }
  /// A disagreement between a given height and the data, if any.
  const std::optional<std::string>& warning() const { return warning_; }
  /// The settings that decide the samples ("off" or the height and layout): a resumed run must
  /// have the same.
  std::string settings() const;

 private:
  std::optional<traversability::TrajectoryEvidence> evidence_;
  double sensor_height_m_ = 0;
  std::string sensor_height_source_;
  double station_spacing_m_ = 0;
  double underside_depth_m_ = 0;
  int later_obstacle_min_views_ = 1;
  std::string summary_;
  std::optional<std::string> warning_;
};

}  // namespace terramesh::cli
