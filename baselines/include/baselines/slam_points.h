#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "datasets/slam_stream.h"
#include "mesher/ids.h"

namespace terramesh::baselines {

/// Which SLAM points a point-cloud method gets: the mesher's own input filters.
struct SlamPointsConfig {
  /// A point is kept when at least this many keyframes observe it (the mesher's min_views).
  int min_views = 2;
  /// Observations farther than this from their camera are ignored (map units; <= 0: no limit).
  double max_camera_distance_units = 0;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// The SLAM map at the end of a stream, as a point cloud with the camera that observed each point.
struct SlamPoints {
  std::vector<mesher::PointId> ids;
  /// Last position sent for each point (map frame, map units).
  std::vector<Eigen::Vector3d> positions_W;
  /// Per point, the centre of the nearest keyframe that observes it (map units): the viewpoint
  /// its normal is turned towards. Each point has its own.
  std::vector<Eigen::Vector3d> viewpoints_W;
  /// Per point, the number of keyframes observing it.
  std::vector<std::uint32_t> views;

  std::size_t size() const { return positions_W.size(); }
};

/// The points of the stream's final state: every keyframe's latest observation list (keyframes
/// removed by the stream dropped, removed points dropped), each point at its last position, kept
/// when seen by `config.min_views` keyframes within the camera distance. Sorted by point id.
/// O(observations log points).
/// @throw std::invalid_argument if the config does not validate.
SlamPoints collectSlamPoints(const datasets::SlamStream& stream, const SlamPointsConfig& config);

/// "Up" of a stream: the mean of its keyframes' sensor up axes (stream.sensor_up_S) in the
/// world frame (traversability::estimateUpFromCameras).
/// @throw std::invalid_argument if the stream has no keyframe or the axes cancel out.
Eigen::Vector3d streamUp(const datasets::SlamStream& stream);

}  // namespace terramesh::baselines
