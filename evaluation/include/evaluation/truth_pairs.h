#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "datasets/triangle_bvh.h"
#include "evaluation/ground_truth_traversability.h"

namespace terramesh::evaluation {

/// A start and goal every map is asked to join, in the truth's frame (metres).
struct ComparePair {
  Eigen::Vector3d start_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d goal_W = Eigen::Vector3d::Zero();
  /// Shortest traversable length on the truth (metres; NaN if unknown).
  double truth_length_m = 0;
};

/// How pairs are drawn on a labelled ground truth (`terramesh compare`, `terramesh pairs`).
struct TruthPairsConfig {
  std::size_t count = 10;
  std::uint64_t seed = 1;
  /// Straight-line distance between start and goal, at least (metres).
  double min_distance_m = 5;
  /// The truth's traversable area is sampled on a grid of this cell (metres, 3D cells).
  double cell_m = 0.2;
  /// Samples closer than this are joined (metres): the graph the truth lengths are measured on.
  double link_radius_m = 0.45;
  /// A sample is observed when at least `min_views` keyframe centres within this distance
  /// (metres) see it unoccluded on the truth.
  double max_view_distance_m = 40;
  int min_views = 2;
};

/// The pairs and how they were drawn (for the report).
struct TruthPairs {
  std::vector<ComparePair> pairs;
  std::size_t samples = 0;           ///< traversable truth samples
  std::size_t observed = 0;          ///< ... of them observed
  std::size_t component_samples = 0; ///< ... in the connected part the pairs are drawn on
  std::size_t component_votes = 0;   ///< keyframes whose nearest observed sample is on that part
  std::size_t largest_component_samples = 0;  ///< samples in the largest observed connected part
  double component_extent_m = 0;     ///< the part's largest straight-line extent from its first sample
};

/// `config.count` pairs on the connected part of the truth's traversable area that the stream
/// observed and drove on (samples on a `cell_m` grid joined within `link_radius_m`; a sample is
/// observed when `min_views` keyframe centres `cameras_W` within `max_view_distance_m` see it
/// unoccluded on `truth_bvh`; the part is the one holding most keyframes' nearest observed sample,
/// the ground under the camera path; the largest part without keyframes), start and goal at least `min_distance_m` apart, each with its shortest length
/// over that graph (Dijkstra; it overestimates the geodesic slightly by zig-zagging between
/// samples). Deterministic for a seed; fewer pairs if the component is too small.
/// All positions in the truth's frame, metres.
TruthPairs pairsOnObservedTruth(const GroundTruthTraversability& labels, const datasets::TriangleBvh& truth_bvh,
                                const std::vector<Eigen::Vector3d>& cameras_W, const TruthPairsConfig& config);

/// `count` pairs among `ground_W` (e.g. the road under the camera path), at least
/// `min_distance_m` apart, deterministic for a seed; truth lengths NaN.
std::vector<ComparePair> pairsOnPoints(const std::vector<Eigen::Vector3d>& ground_W, std::size_t count,
                                       std::uint64_t seed, double min_distance_m);

}  // namespace terramesh::evaluation
