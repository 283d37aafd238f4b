#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <utility>
#include <vector>

#include "evaluation/truth_checker.h"
#include "planning/path_planner.h"

namespace terramesh::evaluation {

/// One planner's answer to one start/goal pair, and what the truth says of its path.
struct PathTrial {
  planning::PlanResult result;
  /// Whether the path was checked on the truth (it was solved and there is a truth) ...
  bool checked = false;
  /// ... and what the check found; a default (valid) check when it was not.
  TruthCheck check;
};

/// How one planner did on every pair of a comparison.
struct PlannerTrials {
  /// One per pair, in the pairs' order.
  std::vector<PathTrial> trials;
  std::size_t solved = 0;
  std::size_t truth_checked = 0;
  std::size_t truth_valid = 0;
  /// Pairs refused before planning: no walkable place near an end (kNoStart, kNoGoal), or the
  /// ends on different walkable components (kUnreachable).
  std::size_t no_start_or_goal = 0;
  std::size_t unreachable = 0;
  /// Sums of the solved paths' lengths (metres) and costs, and of every query's planning time.
  double length_m = 0;
  double cost = 0;
  double time_s = 0;
};

/// The truth the paths are checked on: a checker over the labelled truth, the robot it checks
/// and the map frame the paths are in. Without a checker nothing is checked.
struct PathTruth {
  const TruthChecker* checker = nullptr;
  TruthCheckConfig config;
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  double metres_per_unit = 1.0;
};

/// The comparison harness of `terramesh compare` and `planner_demo`: runs every planner on every
/// pair (map frame, map units), pair by pair with the planners in the given order (the order in
/// which OMPL's process-wide generator is drawn from, so a seeded run repeats), and checks every
/// solved path on the truth when there is one (a body that keeps its own heading,
/// TruthCheckConfig::own_heading, at each state's yaw about `up_W`, geometry::headingDirection).
/// Returns one PlannerTrials per planner, in order.
/// @throw std::invalid_argument if a planner is null, a point is not finite, or the truth check
///        config does not validate.
std::vector<PlannerTrials> runPathTrials(const std::vector<const planning::PathPlanner*>& planners,
                                         const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& pairs,
                                         const PathTruth& truth);

}  // namespace terramesh::evaluation
