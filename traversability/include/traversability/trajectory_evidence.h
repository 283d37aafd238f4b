#pragma once

// Trajectory evidence (docs/traversability.md, "Trajectory evidence"): the robot has driven
// wherever its keyframes were, so the contact patch under each keyframe is driven ground and the
// body volume between consecutive keyframes is observed free space. Both enter the mesher as
// driven-ground samples (mesher::PointKind::kDrivenGround) appended to each keyframe.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "mesher/keyframe.h"
#include "mesher/mesher.h"
#include "traversability/robot_profile.h"

namespace terramesh::traversability {

/// Point ids with this bit set are driven-ground samples; SLAM point ids must not use it.
inline constexpr std::uint64_t kDrivenGroundIdBit = std::uint64_t{1} << 63;
/// A sample's id: kDrivenGroundIdBit | keyframe id << kDrivenSampleIndexBits | sample index. The
/// index's lower half numbers the ground samples, its upper half (kDrivenUndersideIndex + i) the
/// underside of ground sample i.
inline constexpr int kDrivenSampleIndexBits = 7;
/// Most ground samples one keyframe can carry (half the index field).
inline constexpr std::size_t kMaxDrivenSamplesPerKeyframe = std::size_t{1} << (kDrivenSampleIndexBits - 1);
/// Index of the underside of a keyframe's ground sample 0.
inline constexpr std::uint64_t kDrivenUndersideIndex = kMaxDrivenSamplesPerKeyframe;
/// Largest keyframe id that fits in a sample id.
inline constexpr std::uint64_t kMaxDrivenKeyframeId = (std::uint64_t{1} << (63 - kDrivenSampleIndexBits)) - 1;

/// Whether `id` is in the range reserved for driven-ground samples.
inline bool isDrivenGroundId(mesher::PointId id) { return (id.value & kDrivenGroundIdBit) != 0; }

/// Keyframe ids with this bit set are body views (TrajectoryEvidence::bodyViewsOf): view `slot` of
/// keyframe k has id kBodyViewKeyframeBit | slot << kBodyViewSlotShift | k. SLAM keyframe ids stay
/// below the slot bits (they are at most kMaxDrivenKeyframeId).
inline constexpr std::uint64_t kBodyViewKeyframeBit = std::uint64_t{1} << 63;
inline constexpr int kBodyViewSlotShift = 60;
static_assert(kMaxDrivenKeyframeId < (std::uint64_t{1} << kBodyViewSlotShift), "slots above keyframe ids");
/// Body views per keyframe, at the body's top: slots 0-2 over the previous keyframe's base
/// looking ahead, slots 3-5 over this keyframe's base looking back. Slots 0 and 3 lie on the
/// body's centre line, 1 and 4 at its left side, 2 and 5 at its right (their rays reach the upper
/// corners of the body's cross-section, which rays from the centre line leave out). Rays from one
/// end only leave a wedge above the diagonal uncarved, just behind the keyframe: views from both
/// ends carve everything below half the body's height.
inline constexpr std::uint64_t kBodyViewSlots = 6;
/// The body views of one end (TrajectoryEvidence::bodyViewsOf).
inline constexpr std::uint64_t kBodyViewsPerEnd = 3;
/// The id of view `slot` of keyframe `id`.
inline mesher::KeyframeId bodyViewId(mesher::KeyframeId id, std::uint64_t slot = 0) {
  return mesher::KeyframeId{kBodyViewKeyframeBit | slot << kBodyViewSlotShift | id.value};
}
/// The slot of keyframe k's underside view (TrajectoryEvidence::undersideViewOf), after the body views.
inline constexpr std::uint64_t kUndersideViewSlot = kBodyViewSlots;
/// The ids of every body view keyframe `id` can have (to remove them: the mesher ignores unknown ids).
inline std::vector<mesher::KeyframeId> bodyViewIds(mesher::KeyframeId id) {
  std::vector<mesher::KeyframeId> ids;
  for (std::uint64_t slot = 0; slot < kBodyViewSlots; ++slot) ids.push_back(bodyViewId(id, slot));
  return ids;
}

/// How trajectory evidence is estimated, checked and sampled. Lengths in metres.
struct TrajectoryEvidenceConfig {
  // Sampling of the contact patch (the footprint on the ground contact plane).
  /// Largest distance between neighbouring samples of one keyframe's patch.
  double sample_spacing_m = 1.5;
  /// Samples lie within this fraction of the footprint's half extents (disc: of its radius); 1:
  /// the whole footprint was over driven ground.
  double patch_fraction = 1.0;
  /// Each keyframe also observes the samples of the keyframe sent before it, when their sensor
  /// positions are at most this far apart: those rays sweep the body volume between the two
  /// (0: no sweep). (A car's SLAM keyframes are often 5-8 m apart.)
  double max_sweep_distance_m = 10.0;
  /// ... and when the straight line between them stays near the arc the robot drove: the arc's
  /// sagitta, distance x heading change / 8, at most this.
  double max_sweep_sagitta_m = 0.25;
  /// Through a turn whose sagitta exceeds `max_sweep_sagitta_m` but not the footprint's half width
  /// (disc: its radius), with both headings within 60 degrees of the way between the keyframes
  /// (forwards or in reverse), the stations follow the curve through both poses tangent to their
  /// headings (a cubic Hermite curve) instead of the straight line. Its sweep and body views keep
  /// only the rays whose ground track stays within the footprint's half width of that curve (the
  /// others would leave the body the robot swept). Off: such a stretch has no stations, no sweep
  /// and no body views, as one beyond reach.
  bool stations_along_turns = true;
  /// The robot also drove between two keyframes within `max_sweep_distance_m`: the later one
  /// carries patches at stations along the way, at most this far apart along the path, or the
  /// patch's own length if that is longer (0: no stations). A keyframe keeps the number of
  /// stations it was first given; re-sent, it places them between its new pose and the one before.
  /// A keyframe with no keyframe before it within reach starts a drive: the robot stood on its
  /// whole footprint, so its stations run back to the footprint's rear edge instead.
  double station_spacing_m = 0.5;

  // Estimating the sensor height (lower envelope of the points under the path).
  /// Points within this horizontal distance of a sensor's ground projection are "beneath" it.
  double estimate_radius_m = 2.0;
  /// ... and at least this far below the sensor along up (nearer ones are not ground).
  double min_depth_below_m = 0.2;
  /// Depths beneath a sensor further apart than this split into layers; only the nearest layer
  /// with enough points is the ground (the levels under a garage floor are not).
  double layer_gap_m = 1.0;
  /// A keyframe needs this many points beneath it to give a height.
  int min_points_per_keyframe = 3;
  /// The lower envelope of a keyframe's points beneath: this quantile of their depths (the ground
  /// is the lowest surface under the path; objects beside it are above it) ...
  double envelope_quantile = 0.9;
  /// ... and the keyframe's height is the median depth of the points within this band above the
  /// envelope (the ground's points, without the bias of the envelope towards noisy low points).
  double ground_band_m = 0.15;
  /// The estimate needs this many keyframes with a height, and this fraction of all keyframes.
  int min_keyframes = 5;
  double min_keyframe_fraction = 0.2;

  // The not-driven rule.
  /// A sensor higher than this above the points beneath is not on a ground robot (a drone).
  double max_sensor_height_m = 4.0;
  /// A robust spread (1.4826 x MAD) of the per-keyframe heights above this: not driven (a
  /// handheld camera, a drone changing altitude).
  double max_height_spread_m = 0.15;

  /// A given mounting disagrees with the data when it is further than this (or 3 spreads) from
  /// the estimate.
  double disagreement_tolerance_m = 0.1;

  /// SLAM points inside the footprint where the robot drove and within this height of the contact
  /// plane (at most max_step_m above it) are the ground the drive measured: they are left out,
  /// for good, and the driven samples stand for that ground (their noise would otherwise make
  /// steps on the road the robot has just driven). 0: none.
  double ground_absorb_band_m = 0.1;

  /// Later obstacles win over the old drive: a SLAM point first seen after the robot drove on,
  /// inside the body where the robot was two or more keyframes before, withdraws that keyframe's
  /// driven evidence (TrajectoryEvidence::newlyOverridden).
  bool later_obstacles_win = true;
  /// ... once this many keyframes have seen the point (the mesher's min_views: a point seen by
  /// fewer is not in the mesh either; one SLAM outlier does not undo a drive). The drive it
  /// overrides is one before the point's first sighting.
  int later_obstacle_min_views = 2;

  /// Ground a robot drove on is solid at least this deep. Where a level lies beneath the drive (a
  /// parking deck over the floor below), each driven-ground sample gets an underside vertex
  /// (mesher::PointKind::kDrivenUnderside) this far below it: the mesher keeps the layer between
  /// them matter, so the cameras beneath carve their level up to it without carving the road
  /// above away. 0: none.
  double underside_depth_m = 0.1;
  /// A level lies beneath a keyframe's driven ground when a keyframe's sensor lies more than
  /// `beneath_margin_m` below that ground, within `beneath_radius_m` of it horizontally (a hill
  /// rising less than (sensor height + margin) / radius never counts).
  double beneath_radius_m = 20.0;
  double beneath_margin_m = 1.0;

  /// Each keyframe sent after a keyframe within `max_sweep_distance_m` gets its body views
  /// (TrajectoryEvidence::bodyViewsOf) in the mesher; off: none (for ablation studies).
  bool body_views = true;
  /// Body views over both ends (slots 0-5); off: over the previous keyframe's base only (slots
  /// 0-2, for ablation studies).
  bool body_views_from_both_ends = true;
  /// The body volume swept between the two keyframes also enters the mesher as free boxes
  /// (mesher::Keyframe::free_boxes, on the first body view): every cell it meets is free, whether
  /// or not a ray crosses it. Off: rays only (for ablation studies).
  bool body_boxes = true;
  /// The boxes' floor above the ground contact plane, metres: cells reaching no higher are left to
  /// the rays (the ground's own noise stays below it).
  double body_box_floor_m = 0.05;

  /// @throw std::invalid_argument listing every out-of-range field, each "key: value (expected ...)".
  void validate() const;
};

/// What the points under the path say about the sensor's height above the ground.
struct SensorHeightEstimate {
  enum class Status {
    kDriven,     ///< consistent height above the ground beneath: a ground robot
    kNotDriven,  ///< too high or too variable: a drone or a handheld camera
    kNoData,     ///< too few points beneath the path to tell
  };
  Status status = Status::kNoData;
  /// Median over keyframes of each keyframe's median height above the points beneath, metres
  /// (NaN without data).
  double height_m = 0;
  /// 1.4826 x median absolute deviation of the per-keyframe heights, metres.
  double spread_m = 0;
  std::size_t keyframes_used = 0;
  std::size_t keyframes_total = 0;
  /// Why, for kNotDriven and kNoData; empty for kDriven.
  std::string reason;
};

/// Estimates the sensor's height above the ground from the points beneath the path. Per sensor
/// position, the points within `estimate_radius_m` horizontally and at least `min_depth_below_m`
/// below it (along up) give the median of their depths; across positions, the median and its
/// MAD. Then the not-driven rule. Positions in map units; O(P + S * points per grid cell).
/// @param sensors_W    sensor (camera) centres, one per keyframe (its latest pose)
/// @param points_W     the map points (latest estimates)
/// @param up_W         unit vector up
/// @param metres_per_unit  size of one map unit
/// @throw std::invalid_argument for a bad config, up or scale.
SensorHeightEstimate estimateSensorHeight(const std::vector<Eigen::Vector3d>& sensors_W,
                                          const std::vector<Eigen::Vector3d>& points_W, const Eigen::Vector3d& up_W,
                                          double metres_per_unit, const TrajectoryEvidenceConfig& config);

/// The axis of a sensor's frame that points forward, given the one that points up when the sensor
/// is level (SlamStream::sensor_up_S): +x for a LiDAR frame (z up), else +z (a camera, y down).
Eigen::Vector3d sensorForwardAxis(const Eigen::Vector3d& up_S);

/// Whether a run uses trajectory evidence, at which sensor height, and why.
struct TrajectoryEvidenceDecision {
  bool enabled = false;
  /// Sensor height above the ground contact plane used for the samples, metres (0 if off).
  double sensor_height_m = 0;
  /// "--sensor-height-m", "the robot profile" or "the data".
  std::string source;
  SensorHeightEstimate estimate;
  /// One line on what was inferred: the estimate and its spread, or why the evidence is off.
  std::string summary;
  /// When a given height disagrees with the data: a line naming both values.
  std::optional<std::string> warning;
};

/// Decides from the estimate and the heights given by the user (`override_height_m`, e.g. a
/// command-line option) or the profile's mounting (`profile_height_m`): off when the trajectory
/// does not look driven, or when there is no data and no height is given; else the given height
/// (the override first) or the estimate, with a warning if a given height disagrees with it.
TrajectoryEvidenceDecision decideTrajectoryEvidence(const SensorHeightEstimate& estimate,
                                                    std::optional<double> profile_height_m,
                                                    std::optional<double> override_height_m,
                                                    const TrajectoryEvidenceConfig& config);

/// Generates the driven-ground samples of keyframes and keeps the keyframes' current poses, so
/// that a keyframe's samples follow its corrected pose and go with it.
///
/// Samples of keyframe k: the contact patch points (footprint-shaped layout, `samplesPerKeyframe`
/// of them) placed with the robot base frame B under the sensor: B = T_W_C * T_B_S^-1 with the
/// profile's full mounting, else origin `sensor_height_m` below the sensor along up, x the
/// sensor's forward axis projected on the ground plane, z up. Ids: kDrivenGroundIdBit |
/// k << kDrivenSampleIndexBits | index. Not thread-safe.
class TrajectoryEvidence {
 public:
  /// @param profile    footprint and (optional) full sensor mounting
  /// @param up_W       unit up in the map frame
  /// @param metres_per_unit  size of one map unit
  /// @param sensor_height_m  height of the sensor above the ground contact plane (a decision's)
  /// @param forward_S  the sensor-frame axis that points forward (+z for cameras, +x for LiDAR)
  /// @throw std::invalid_argument for a bad config, profile, up, scale or height, or a layout of
  ///        more than kMaxDrivenSamplesPerKeyframe samples.
  TrajectoryEvidence(const RobotProfile& profile, const Eigen::Vector3d& up_W, double metres_per_unit,
                     double sensor_height_m, const Eigen::Vector3d& forward_S, const TrajectoryEvidenceConfig& config);
  ~TrajectoryEvidence();
  TrajectoryEvidence(TrajectoryEvidence&&) noexcept;
  TrajectoryEvidence& operator=(TrajectoryEvidence&&) noexcept;
  TrajectoryEvidence(const TrajectoryEvidence&) = delete;
  TrajectoryEvidence& operator=(const TrajectoryEvidence&) = delete;

  /// Integrates `keyframe` into `mesher` with its evidence, the one sequence of a run with
  /// trajectory evidence: the keyframe with its samples (augment); the points the drive
  /// contradicts out of the mesher (newlyContradicted); the drive of the keyframes later obstacles
  /// overrode withdrawn (newlyWithdrawnViews, then their samples); then this keyframe's body views
  /// (bodyViewsOf, when `body_views` is on), or the removal of the ones it had; then the underside
  /// views of this keyframe and of the keyframes it newly found a level beneath
  /// (undersideViewOf, newlyUndersided). Returns the sum of the mesher's updates.
  /// @throw std::invalid_argument as augment and mesher::Mesher::integrateKeyframe do.
  mesher::UpdateStats integrate(mesher::Mesher& mesher, const mesher::Keyframe& keyframe);
  /// Removes keyframe `id` from `mesher` with its body views and then its samples, and forgets it
  /// (remove). Unknown ids change nothing. Returns the sum of the mesher's updates.
  mesher::UpdateStats removeKeyframe(mesher::Mesher& mesher, mesher::KeyframeId id);
  /// removeKeyframe for several keyframes at once: one mesher update for the keyframes and their
  /// views, one for their samples (the online freeze retiring the keyframes of a region).
  mesher::UpdateStats removeKeyframes(mesher::Mesher& mesher, const std::vector<mesher::KeyframeId>& ids);

  /// The samples of `keyframe` at its pose (no state change).
  /// A keyframe already recorded (augment) also gets the patches at its stations, between this pose
  /// and the previous keyframe's pose recorded with it.
  /// @throw std::invalid_argument if the keyframe id exceeds kMaxDrivenKeyframeId.
  std::vector<mesher::PointObservation> samplesOf(const mesher::Keyframe& keyframe) const;

  /// `keyframe` with its own samples appended, and the samples of the keyframe sent (first)
  /// before it when within `max_sweep_distance_m` (the body-volume sweep). Records its pose.
  /// Leaves out the SLAM points the drive contradicts (newlyContradicted), now and for good.
  /// @throw std::invalid_argument if an observation already uses the reserved id range, or the
  ///        keyframe id exceeds kMaxDrivenKeyframeId; nothing is recorded then.
  mesher::Keyframe augment(const mesher::Keyframe& keyframe);

  /// The body views of a keyframe augment() has recorded, when it was sent after a keyframe within
  /// `max_sweep_distance_m`: kBodyViewSlots keyframes with ids bodyViewId(id, slot), each with its
  /// centre in the robot's body, `min_clearance_m` (at most the sensor height) above a base: the
  /// previous keyframe's (as recorded with this one; slots 0-2) and this keyframe's (slots 3-5),
  /// on the centre line and at the left and right edges of the footprint (the disc's radius, the
  /// rectangle's half width). Each observes this keyframe's samples: its own patch and its
  /// stations. Their rays run inside the body volume swept between the two, low, where the
  /// sensor's own rays (from above and ahead) leave closing faces over the driven strip and up its
  /// sides. Through a turn (stations_along_turns), each keeps the samples its rays reach without
  /// leaving the body swept along the curve, and a view left with none is not listed. Empty when
  /// the keyframe is unknown or had no previous keyframe near enough (remove the views not listed).
  std::vector<mesher::Keyframe> bodyViewsOf(mesher::KeyframeId id) const;

  /// Forgets keyframe `id` and returns the ids of its samples (to remove from the mesher after
  /// removing the keyframe: the next keyframe still observes them). Empty if it is unknown.
  std::vector<mesher::PointId> remove(mesher::KeyframeId id);

  /// Forgets the SLAM points (seen, positions, left out) lying farther than `radius_m` (plan
  /// distance) from each of `keep_W` (map units): the online freeze, once the keyframes of a
  /// region left behind are removed. Such a point seen again counts as new (a later obstacle)
  /// and, if it had been left out, is judged again. Returns how many points were forgotten.
  /// O(points known).
  std::size_t forgetPointsBeyond(const std::vector<Eigen::Vector3d>& keep_W, double radius_m);

  /// The points the last augment() left out for good; remove them from the mesher (an earlier
  /// keyframe may have inserted them):
  /// - inside the robot's body (between max_step_m and min_clearance_m above the contact plane,
  ///   within the footprint) at the keyframe, at its stations, at the one before it (the sweep) or
  ///   half way: the robot drove through them, so they are outliers. Both the points this keyframe
  ///   sees and those seen before (a forward camera sees the road ahead, not under the robot).
  ///   An obstacle placed on the road later is made of other points, seen when the robot is
  ///   elsewhere: it stays (newlyOverridden).
  /// - on the ground it drove: within `ground_absorb_band_m` of the contact plane inside the
  ///   footprint at any of the drive's stations; the driven samples stand for that ground.
  const std::vector<mesher::PointId>& newlyContradicted() const { return newly_contradicted_; }
  /// How many points the drive has contradicted (inside the body) so far.
  std::size_t contradictedCount() const { return contradicted_count_; }
  /// How many points on the driven ground the drive has stood for so far.
  std::size_t absorbedCount() const { return absorbed_count_; }

  /// The keyframes whose drive the last augment() found overridden by an obstacle seen later:
  /// a SLAM point it saw for the first time lies inside the body at one of their stations, and
  /// they were sent before the keyframe before it (so the point was not there when the robot
  /// was); and, with each, the keyframe sent before it (its sensor's sweep rays ran to that one's
  /// samples, past the obstacle). From now on they have no samples, no sweep to them and no body
  /// view; remove their samples (sampleIdsOf) from the mesher, after the body views of
  /// newlyWithdrawnViews(). With `later_obstacles_win` off, always empty.
  const std::vector<mesher::KeyframeId>& newlyOverridden() const { return newly_overridden_; }
  /// Body views the last augment() withdrew: those of the overridden keyframes and of the keyframe
  /// sent after each (its view stands at the overridden keyframe's base). Remove them from the
  /// mesher (unknown ids are ignored there).
  const std::vector<mesher::KeyframeId>& newlyWithdrawnViews() const { return newly_withdrawn_views_; }
  /// How many keyframes have a level beneath their drive (undersideViewOf) so far.
  std::size_t undersidedCount() const { return undersided_.size(); }
  /// How many keyframes later obstacles have overridden so far.
  std::size_t overriddenCount() const { return overridden_.size(); }
  /// How many recorded keyframes were driven to through a turn (stations_along_turns).
  std::size_t turnCount() const;
  /// The ids of all samples keyframe `id` has or had (its patch and stations, and their
  /// undersides); empty if unknown.
  std::vector<mesher::PointId> sampleIdsOf(mesher::KeyframeId id) const;

  /// The robot base frame (map frame, map units) where driven-ground sample `id` was put down: at
  /// its keyframe's current pose or station. nullopt for an id that is not a sample of a recorded
  /// keyframe. (TraversabilityMap::setDrivePoses.)
  std::optional<Eigen::Isometry3d> baseOf(mesher::PointId id) const;

  /// The underside view of keyframe `id`: a keyframe of its own (id bodyViewId(id,
  /// kUndersideViewSlot)) at its sensor, observing the undersides of its samples (patch and
  /// stations), when a level lies beneath its drive (`beneath_radius_m`); else empty (remove an
  /// earlier one then). Its observations trace no ray.
  std::optional<mesher::Keyframe> undersideViewOf(mesher::KeyframeId id) const;
  /// Keyframes sent before, whose drive the last augment() found to have a level beneath (its
  /// sensor lies under their ground): send their underside views (undersideViewOf).
  const std::vector<mesher::KeyframeId>& newlyUndersided() const { return newly_undersided_; }

  /// Sets the mesher's ground rule for this evidence: `driven_ground_up_W` and
  /// `driven_underside_depth_m` (mesher::MesherConfig), before the mesher is made.
  void configureMesher(mesher::MesherConfig& config) const;

  /// Samples of one patch (a keyframe carries one patch, plus one per station).
  std::size_t samplesPerKeyframe() const { return layout_B_m_.size(); }
  /// Most stations one keyframe can carry: the id range of its samples holds this many patches
  /// besides its own.
  std::size_t maxStationsPerKeyframe() const { return kMaxDrivenSamplesPerKeyframe / layout_B_m_.size() - 1; }
  /// The patch layout's extent along the driving direction, metres.
  double patchLengthM() const { return patch_length_m_; }
  /// How many stations a keyframe this far (metres) from the one before it gets.
  std::size_t stationsFor(double gap_m) const;
  /// The sample layout in the base frame B (x forward, y left, z up; metres).
  const std::vector<Eigen::Vector3d>& layoutB() const { return layout_B_m_; }

 private:
  struct Pose {
    Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
    Eigen::Quaterniond rotation_W_C = Eigen::Quaterniond::Identity();
    std::uint64_t order = 0;  ///< when it was first sent
    /// Stations between the previous keyframe's pose (as it was when this one was last sent) and
    /// this one; fixed when the keyframe is first sent.
    std::size_t stations = 0;
    Eigen::Vector3d previous_position_W = Eigen::Vector3d::Zero();
    Eigen::Quaterniond previous_rotation_W_C = Eigen::Quaterniond::Identity();
    /// Whether the last send found a previous keyframe near enough (the body view exists), and which.
    bool has_previous = false;
    std::uint64_t previous_id = 0;
    /// Whether the way from the previous keyframe is a turn (stations_along_turns): stations on
    /// the curve; the sweep and the body views keep the rays that stay over it (seenWithinTurn).
    bool curved = false;
    /// The stations at which the body stood whole (1..bodyStations()): those between keyframes.
    /// At a drive's start the stations lie under the first footprint, back to its rear edge: the
    /// keyframe's own body covers them, and a body centred on them would reach half a footprint
    /// behind where the robot ever was.
    std::size_t bodyStations() const { return has_previous ? stations : 0; }
    /// This pose moved to the previous keyframe's position and rotation (the way's other end).
    Pose previousEnd() const {
      Pose end = *this;
      end.position_W = previous_position_W;
      end.rotation_W_C = previous_rotation_W_C;
      return end;
    }
  };
  std::vector<mesher::PointObservation> samplesAt(mesher::KeyframeId id, const Pose& pose) const;
  /// The body volume swept from the previous keyframe to `pose` as boxes (Config::body_boxes): a
  /// disc's between consecutive stations, a rectangle's at each station; level, each floor raised
  /// by the stretch's slope times the box's reach along the way.
  std::vector<mesher::FreeBox> sweptBoxes(const Pose& pose) const;
  /// The underside vertices of `samples` (underside_depth_m below each; none at 0).
  std::vector<mesher::PointObservation> undersidesOf(const std::vector<mesher::PointObservation>& samples) const;
  /// Marks keyframe `id` (its pose recorded) and the keyframes near it as undersided where a
  /// sensor lies beneath a drive (newly_undersided_ lists the earlier ones).
  void findLevelsBeneath(mesher::KeyframeId id, const Pose& pose);
  /// The pose at `station` (0: the keyframe's own; 1..stations from the previous pose on).
  Pose stationPose(const Pose& pose, std::size_t station) const;
  /// Whether the way from `before` to `pose` is a turn its stations can follow (stations_along_turns),
  /// given the arc's sagitta in metres.
  bool followsTurn(const Pose& before, const Pose& pose, double sagitta_m) const;
  /// Of `samples`, those seen from `from_W` along a ray whose ground track stays within the
  /// footprint's half width of the curve a turn's stations follow (`pose` curved).
  std::vector<mesher::PointObservation> seenWithinTurn(const Pose& pose, const Eigen::Vector3d& from_W,
                                                       const std::vector<mesher::PointObservation>& samples) const;
  /// The robot base frame B at a keyframe's pose (map units).
  Eigen::Isometry3d baseAt(const Pose& pose) const;
  /// Whether p_W lies inside the robot's body with its base at T_W_B.
  bool insideBody(const Eigen::Isometry3d& T_W_B, const Eigen::Vector3d& p_W) const;
  /// Whether p_W lies on the driven ground under the footprint with its base at T_W_B (within
  /// the absorb band of the contact plane).
  bool onDrivenGround(const Eigen::Isometry3d& T_W_B, const Eigen::Vector3d& p_W) const;
  /// Whether p_W lies on the driven ground of any recorded keyframe's station.
  bool onRecordedDrivenGround(const Eigen::Vector3d& p_W) const;
  /// Leaves `id` out for good (on the driven ground: `absorbed`).
  void leaveOut(mesher::PointId id, const Eigen::Vector3d& p_W, bool absorbed);
  /// Leaves the contradicted points out of `keyframe` (poses: where the body was), checks the
  /// points seen before against the new bodies, and records the positions of the rest.
  void dropContradicted(mesher::Keyframe& keyframe, const std::vector<Eigen::Isometry3d>& bodies_W_B,
                        std::size_t new_bodies);
  /// Marks overridden the keyframes with a body containing a point that `keyframe`'s sighting
  /// brings to later_obstacle_min_views keyframes, sent before `before_order` as it stood at the
  /// point's first sighting.
  void findLaterObstacles(const mesher::Keyframe& keyframe, std::uint64_t before_order);
  /// Overrides keyframe `id` (if not yet): no samples, no body view, and the same for the
  /// keyframe before it when `with_previous`.
  void overrideDrive(std::uint64_t id, bool with_previous);
  /// Lists or unlists a keyframe's station bases in the body index.
  void indexBodies(mesher::KeyframeId id, const Pose& pose, bool add);

  Eigen::Vector3d up_W_;
  double metres_per_unit_;
  double sensor_height_m_;
  Eigen::Vector3d forward_S_;
  std::optional<Eigen::Isometry3d> T_B_S_;
  TrajectoryEvidenceConfig config_;
  std::vector<Eigen::Vector3d> layout_B_m_;
  /// The body: footprint (disc radius or rectangle half-extents) and height band, metres.
  bool disc_ = true;
  double patch_length_m_ = 0;  ///< the layout's extent along x, metres
  double radius_m_ = 0, half_length_m_ = 0, half_width_m_ = 0, body_low_m_ = 0, body_high_m_ = 0;
  double absorb_band_m_ = 0;
  /// How far the footprint reaches behind the base (a keyframe that starts a drive has stations
  /// back to there), metres.
  double rear_m_ = 0;
  /// Points left out for good, with their plan position (metres).
  std::unordered_map<std::uint64_t, Eigen::Vector2d> contradicted_;
  std::size_t contradicted_count_ = 0, absorbed_count_ = 0;
  std::vector<mesher::PointId> newly_contradicted_;
  /// Keyframe ids by the horizontal cell of their station bases, and the SLAM points seen so far.
  struct BodyIndex;
  std::unique_ptr<BodyIndex> bodies_;
  std::unordered_set<std::uint64_t> overridden_;
  std::vector<mesher::KeyframeId> newly_overridden_;
  std::vector<mesher::KeyframeId> newly_withdrawn_views_;
  /// Keyframes whose drive has a level beneath it (undersideViewOf), and the newly found ones.
  std::unordered_set<std::uint64_t> undersided_;
  std::vector<mesher::KeyframeId> newly_undersided_;
  std::unordered_map<std::uint64_t, Pose> poses_;
  std::map<std::uint64_t, mesher::KeyframeId> by_order_;
  std::uint64_t next_order_ = 0;
};

}  // namespace terramesh::traversability
