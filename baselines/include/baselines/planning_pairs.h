#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "evaluation/ground_truth_traversability.h"
#include "planning/face_graph.h"
#include "traversability/layered_mesh.h"

namespace terramesh::baselines {

/// A start and goal every map is asked to join, in the truth's frame (metres).
struct PlanningPair {
  Eigen::Vector3d start_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d goal_W = Eigen::Vector3d::Zero();
  /// Length of the shortest path over the truth's traversable surface (metres; NaN if unknown).
  double truth_length_m = 0;
};

/// `count` pairs on the ground truth's largest connected traversable area, at least
/// `min_distance_m` apart, with their shortest traversable length (graph A* over the truth's
/// traversable faces). Deterministic for a seed; fewer when the area is too small.
std::vector<PlanningPair> pairsOnTruth(const evaluation::GroundTruthTraversability& truth, std::size_t count,
                                       std::uint64_t seed, double min_distance_m);

/// `count` pairs among `ground_W` (e.g. the road under the camera path), at least
/// `min_distance_m` apart, deterministic for a seed; truth lengths NaN.
std::vector<PlanningPair> pairsOnPoints(const std::vector<Eigen::Vector3d>& ground_W, std::size_t count,
                                        std::uint64_t seed, double min_distance_m);

/// How a map did on the pairs (graph A* over its walkable faces, planning::planOnFaceGraph).
struct PlanningScore {
  std::size_t pairs = 0;
  std::size_t solved = 0;
  std::size_t no_start_or_goal = 0;  ///< nothing walkable within the snap radius
  std::size_t unreachable = 0;       ///< start and goal on different walkable components
  double mean_length_m = 0;          ///< over solved pairs (NaN if none)
  double mean_cost = 0;              ///< over solved pairs (NaN if none)
  /// Mean of path length / truth length over solved pairs with a truth length (NaN if none).
  double mean_length_ratio = 0;
};

/// Plans every pair on `map` (metric, in the pairs' frame) with the graph baseline.
/// @throw std::invalid_argument if the map or config is invalid (planning::FaceGraph).
PlanningScore planPairs(const traversability::LayeredMesh& map, const std::vector<PlanningPair>& pairs,
                        const planning::WalkabilityConfig& walkability, double snap_radius_m);

}  // namespace terramesh::baselines
