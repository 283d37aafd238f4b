#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/ground_truth_traversability.h"
#include "planning/face_graph.h"
#include "traversability/layered_mesh.h"

namespace terramesh::cli {

/// A start and goal every map is asked to join, in the truth's frame (metres).
struct ComparePair {
  Eigen::Vector3d start_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d goal_W = Eigen::Vector3d::Zero();
  /// Shortest traversable length on the truth (metres; NaN if unknown).
  double truth_length_m = 0;
};

/// How `terramesh compare` draws pairs on a labelled ground truth.
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
TruthPairs pairsOnObservedTruth(const evaluation::GroundTruthTraversability& labels, const datasets::TriangleBvh& truth_bvh,
                                const std::vector<Eigen::Vector3d>& cameras_W, const TruthPairsConfig& config);

/// `count` pairs among `ground_W` (e.g. the road under the camera path), at least
/// `min_distance_m` apart, deterministic for a seed; truth lengths NaN.
std::vector<ComparePair> pairsOnPoints(const std::vector<Eigen::Vector3d>& ground_W, std::size_t count,
                                       std::uint64_t seed, double min_distance_m);

/// The labelled truth paths are checked against (planner_demo's checkAgainstTruth).
struct PathTruth {
  const datasets::LabeledMesh* mesh = nullptr;
  const datasets::TriangleBvh* bvh = nullptr;
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  double max_slope_deg = 20;
  /// The robot's body for the footprint test (RobotProfile: circumscribed radius, step, height).
  double footprint_radius_m = 0.3, max_step_m = 0.2, min_clearance_m = 1.0;
};

/// How one map did on the pairs (graph A* over its walkable faces, planning::planOnFaceGraph).
struct PlanningOutcome {
  std::size_t pairs = 0;
  std::size_t solved = 0;
  std::size_t no_start_or_goal = 0;  ///< nothing walkable within the snap radius of an end
  std::size_t unreachable = 0;       ///< start and goal on different walkable components
  std::size_t truth_checked = 0;     ///< solved paths checked against a labelled truth
  std::size_t truth_valid = 0;       ///< ... and drivable on it
  double mean_length_m = 0;          ///< over solved pairs (NaN if none)
  double mean_cost = 0;              ///< over solved pairs (NaN if none)
  double mean_length_ratio = 0;      ///< path length / truth length, over solved pairs (NaN if none)
  /// The map's walkable surface: faces, area (m^2), components, largest component's area.
  std::size_t walkable_faces = 0;
  double walkable_area_m2 = 0;
  std::size_t walkable_components = 0;
  double largest_component_m2 = 0;
  /// Per pair: status name, and the first truth problem of an invalid path.
  std::vector<std::string> statuses;
  std::vector<std::string> truth_reasons;
  /// One line: why the map failed the pairs it failed.
  std::string summary() const;
};

/// Plans every pair on `map` (metric, in the pairs' frame) with the graph baseline; solved paths
/// are checked against `truth` when it has a mesh.
/// @throw std::invalid_argument if the map or config is invalid (planning::FaceGraph).
PlanningOutcome planComparePairs(const traversability::LayeredMesh& map, const std::vector<ComparePair>& pairs,
                                 const planning::WalkabilityConfig& walkability, double snap_radius_m,
                                 const PathTruth& truth);

}  // namespace terramesh::cli
