#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "planning/surface_planner.h"

namespace terramesh::planning {

/// A query in SE(2) over a bounded plane whose validity and cost the caller defines (the 2.5D
/// grid of the OctoMap baseline, terramesh::baselines::planOnGrid, is one). Coordinates are the
/// plane's own (metres for the grid); the heading of start and goal is `yaw_rad`.
struct PlaneProblem {
  Eigen::Vector2d low = Eigen::Vector2d::Zero();   ///< lower corner of the bounds
  Eigen::Vector2d high = Eigen::Vector2d::Zero();  ///< upper corner
  /// Whether a robot may stand at a point.
  std::function<bool(const Eigen::Vector2d&)> is_valid;
  /// Cost of the straight motion from a to b (the optimisation objective; >= the distance).
  std::function<double(const Eigen::Vector2d&, const Eigen::Vector2d&)> motion_cost;
  /// Motions are checked for validity every this much distance (plane units).
  double validity_step = 0.1;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();
  double yaw_rad = 0;
};

/// What planOnPlane found: kSolved with the planner's states and the path densified, or
/// kNotFound with the reason.
struct PlanePath {
  PlanStatus status = PlanStatus::kNotFound;
  std::string reason;
  std::string planner;                    ///< canonical name of the planner used
  std::vector<Eigen::Vector2d> waypoints;  ///< the planner's states (after simplification)
  /// The waypoints interpolated to at least 2 states, about one per `dense_step` of SE(2) length.
  std::vector<Eigen::Vector2d> dense;
  double planning_time_s = 0;
};

/// Plans from problem.start to problem.goal in OMPL's SE(2) with the configured planner (same
/// planners, budget, time cap and simplification as planOnSurface; the heuristic is the straight
/// distance). Start and goal must be valid: the caller snaps them. Thread-safe for distinct calls
/// (each builds its own OMPL setup) when the callbacks are.
/// @throw std::invalid_argument if the config does not validate, a callback is missing, or the
///        bounds, validity_step or dense_step are not positive.
PlanePath planOnPlane(const PlaneProblem& problem, const PlannerConfig& config, double dense_step);

}  // namespace terramesh::planning
