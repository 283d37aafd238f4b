#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>
#include <unordered_map>
#include <utility>
#include <unordered_set>
#include <vector>

#include "cgal_types.h"
#include "mesher/ids.h"
#include "mesher/keyframe.h"
#include "ray_store.h"

namespace terramesh::mesher::internal {

/// A SLAM point as the mesher knows it.
struct PointRecord {
  PointId id;
  bool alive = false;
  /// SLAM point or driven-ground sample; set when the record is created, kept until erased.
  PointKind kind = PointKind::kSlam;
  /// Latest estimate received from SLAM.
  Eigen::Vector3d latest_W = Eigen::Vector3d::Zero();
  /// Position of its vertex; meaningful while `vertex` is set.
  Eigen::Vector3d inserted_W = Eigen::Vector3d::Zero();
  /// Its vertex in the triangulation; default (null) while not inserted.
  VertexHandle vertex;
  /// Keyframes that observe it (KeyframeRegistry indices), in no order.
  std::vector<std::uint32_t> keyframes;
  /// Its stored rays, one per keyframe within range; only while inserted.
  std::vector<RayId> rays;

  bool inserted() const { return vertex != VertexHandle(); }
};

/// A keyframe as the mesher knows it.
struct KeyframeRecord {
  KeyframeId id;
  bool alive = false;
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation_W_C = Eigen::Quaterniond::Identity();
  /// Points it observes (PointRegistry indices).
  std::vector<std::uint32_t> points;
  /// Last cell found to contain the camera: a hint for locating it again.
  StampedCell camera_hint;
};

/// Points and keyframes by external id, with dense recycled indices.
class PointRegistry {
 public:
  /// Index of the point with `id`, creating a record if unknown.
  std::uint32_t findOrCreatePoint(PointId id);
  /// Index of the point with `id`, or kNone.
  std::uint32_t findPoint(PointId id) const;
  void erasePoint(std::uint32_t index);

  std::uint32_t findOrCreateKeyframe(KeyframeId id, bool& created);
  std::uint32_t findKeyframe(KeyframeId id) const;
  void eraseKeyframe(std::uint32_t index);

  PointRecord& point(std::uint32_t index) { return points_[index]; }
  const PointRecord& point(std::uint32_t index) const { return points_[index]; }
  KeyframeRecord& keyframe(std::uint32_t index) { return keyframes_[index]; }
  const KeyframeRecord& keyframe(std::uint32_t index) const { return keyframes_[index]; }

  std::size_t pointSlots() const { return points_.size(); }
  std::size_t keyframeSlots() const { return keyframes_.size(); }
  std::size_t pointCount() const { return point_index_.size(); }
  std::size_t keyframeCount() const { return keyframe_index_.size(); }

  /// A keyframe's observation list, emptied (for rebuilding or removal).
  std::vector<std::uint32_t> takeKeyframePoints(std::uint32_t keyframe);
  /// Appends `point` to `keyframe`'s observation list (the caller keeps it free of repeats).
  void addKeyframePoint(std::uint32_t keyframe, std::uint32_t point);
  /// Removes `point` from `keyframe`'s observation list, if there.
  void removeKeyframePoint(std::uint32_t keyframe, std::uint32_t point);
  /// Observation links (entries of the keyframes' lists, mirrored in the points' lists).
  std::size_t observationLinks() const { return observation_links_; }

  /// Points observed but not inserted (SLAM points waiting for `min_views` keyframes in range):
  /// indices kept current by refreshWaiting. O(1) to read.
  const std::unordered_set<std::uint32_t>& waitingPoints() const { return waiting_; }
  /// Re-reads whether the point at `index` is waiting: alive, a SLAM point, observed, not inserted.
  void refreshWaiting(std::uint32_t index);
  /// Rebuilds the waiting set from the records (after loading a checkpoint). O(point slots).
  /// Forgets the journal: no revision before this one can be answered.
  void rebuildWaiting();

  /// The journal of the waiting set: every point refreshWaiting re-read or erasePoint erased
  /// (its membership or position may have changed) is logged at the revision that the next
  /// commitWaiting() closes. Revisions older than kWaitingRevisionsKept are dropped.
  static constexpr std::uint64_t kWaitingRevisionsKept = 256;
  /// Closes the current revision (once per mesher update). O(entries dropped).
  void commitWaiting();
  std::uint64_t waitingRevision() const { return waiting_revision_; }
  /// The ids logged after revision `from`, sorted and unique; nullopt if the journal no longer
  /// reaches back to `from` (or `from` is newer than the current revision).
  std::optional<std::vector<PointId>> waitingChangesSince(std::uint64_t from) const;

  /// Estimated bytes of the point and keyframe records and their lists, given the ray count. O(1).
  std::size_t pointBytes(std::size_t rays) const;
  /// Estimated bytes of the id maps. O(1).
  std::size_t indexBytes() const;

 private:
  friend class CheckpointAccess;

  std::vector<PointRecord> points_;
  std::vector<std::uint32_t> free_points_;
  std::unordered_map<PointId, std::uint32_t> point_index_;
  std::vector<KeyframeRecord> keyframes_;
  std::vector<std::uint32_t> free_keyframes_;
  std::unordered_map<KeyframeId, std::uint32_t> keyframe_index_;
  std::size_t observation_links_ = 0;
  std::unordered_set<std::uint32_t> waiting_;
  std::uint64_t waiting_revision_ = 0;
  /// (revision, id) in revision order; revisions <= waiting_forgotten_ are gone.
  std::deque<std::pair<std::uint64_t, PointId>> waiting_journal_;
  std::uint64_t waiting_forgotten_ = 0;
};

}  // namespace terramesh::mesher::internal
