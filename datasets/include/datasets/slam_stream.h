#pragma once

#include <map>
#include <string>
#include <variant>
#include <vector>

#include "mesher/ids.h"
#include "mesher/keyframe.h"
#include "mesher/mesher_config.h"

namespace terramesh::mesher {
class Mesher;
struct UpdateStats;
}  // namespace terramesh::mesher

namespace terramesh::datasets {

/// The SLAM system deleted these points.
struct PointRemoval {
  std::vector<mesher::PointId> points;
};

/// The SLAM system deleted this keyframe.
struct KeyframeRemoval {
  mesher::KeyframeId keyframe;
};

/// One message of a SLAM stream, in the order the SLAM system produced it.
using StreamEvent = std::variant<mesher::Keyframe, PointRemoval, KeyframeRemoval>;

/// A whole SLAM stream as read from a file.
struct SlamStream {
  std::vector<StreamEvent> events;
  /// Size of one map unit in metres, when the source says it (1 for metric maps).
  double metres_per_unit = 1.0;
  /// Whether the source stated metres_per_unit (the authors' JSON does not).
  bool scale_known = false;
  /// Views a point needs before insertion that suits this source (0: no advice). LiDAR streams,
  /// where every return is seen once, advise 1.
  int recommended_min_views = 0;
  /// Steiner lattice spacing that suits this source, in metres (0: no advice, the mesher's
  /// default). LiDAR streams advise kLidarSteinerStepM (lidar_scan_filter.h).
  double recommended_steiner_step_m = 0;
  /// Whether the mesher's camera-distance filter should be derived from the data rather than a
  /// fixed distance in metres: structure-from-motion models (COLMAP, OpenMVG, Bundler) have an
  /// arbitrary scale, so that "40 m" means nothing in their units.
  bool recommend_auto_max_distance = false;
  /// The axis of a keyframe's sensor frame that points up when the sensor is level: -y for
  /// cameras (OpenCV/KITTI convention, x right, y down), +z for a Velodyne scanner (x forward).
  Eigen::Vector3d sensor_up_S = -Eigen::Vector3d::UnitY();
  /// Free text: where the stream came from.
  std::string description;
  /// The image (or scan) file of each keyframe, when the source names one (COLMAP, OpenMVG,
  /// Bundler's list file, KITTI scans).
  std::map<mesher::KeyframeId, std::string> keyframe_names;
  /// What the reader inferred from the data (which topics, frames and fields it used) and what
  /// it dropped, one sentence each, for the application to report (libraries do not print).
  std::vector<std::string> reader_notes;
  /// The same for what looks wrong, e.g. a filter that dropped most of the input.
  std::vector<std::string> reader_warnings;

  std::size_t keyframeEventCount() const;
};

/// Sets in `config` what `stream` advises for meshing (recommended_min_views,
/// recommended_steiner_step_m); what it gives no advice on keeps its value. Flags that override
/// the advice are applied after it.
void applyMeshingAdvice(const SlamStream& stream, mesher::MesherConfig& config);

/// The `quantile` (0-1) of the distances from each keyframe event's camera centre to the points it
/// observes, in map units, over every observation of the stream (nearest rank); 0 when the stream
/// has no observation. O(observations log observations).
/// @throw std::invalid_argument if quantile is not within [0, 1].
double observationDistanceQuantile(const SlamStream& stream, double quantile);

/// The last pose sent for a keyframe.
struct LatestKeyframePose {
  mesher::KeyframeId id;
  Eigen::Vector3d position_W_C = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation_W_C = Eigen::Quaterniond::Identity();
};
/// The last pose sent for every keyframe the stream has not removed by its end, in id order.
/// O(events + keyframes log keyframes).
std::vector<LatestKeyframePose> latestKeyframePoses(const SlamStream& stream);
/// The camera centres of latestKeyframePoses, in the same order.
std::vector<Eigen::Vector3d> latestKeyframeCentres(const SlamStream& stream);
/// The last estimate sent for every point any keyframe observed (removed points included), in
/// point id order. O(observations + points log points).
std::vector<Eigen::Vector3d> latestPointEstimates(const SlamStream& stream);

/// Feeds one event to the mesher and returns what the update did.
mesher::UpdateStats applyEvent(mesher::Mesher& mesher, const StreamEvent& event);

}  // namespace terramesh::datasets
