#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/truth_checker.h"
#include "evaluation/truth_pairs.h"
#include "planning/face_graph.h"
#include "traversability/layered_mesh.h"

namespace terramesh::cli {

/// The labelled truth paths are checked against (evaluation::TruthChecker).
struct PathTruth {
  const datasets::LabeledMesh* mesh = nullptr;
  const datasets::TriangleBvh* bvh = nullptr;
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  /// The robot's check (evaluation::truthCheckConfigFrom).
  evaluation::TruthCheckConfig config;
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
PlanningOutcome planComparePairs(const traversability::LayeredMesh& map,
                                 const std::vector<evaluation::ComparePair>& pairs,
                                 const planning::WalkabilityConfig& walkability, double snap_radius_m,
                                 const PathTruth& truth);

}  // namespace terramesh::cli
