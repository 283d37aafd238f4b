#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "baselines/height_grid.h"
#include "planning/surface_planner.h"

namespace terramesh::baselines {

/// A path on the grid, in the map frame W (map units), with z from the ground heights.
struct GridPlanResult {
  planning::PlanStatus status = planning::PlanStatus::kNotFound;
  std::string reason;
  std::string planner;
  std::vector<Eigen::Vector3d> points_W;
  double length_m = 0;  ///< 3D length over the ground heights
  double cost = 0;      ///< integral of (1 + w * cost) over the 3D length
  double planning_time_s = 0;
  bool solved() const { return status == planning::PlanStatus::kSolved; }
};

/// Plans in SE(2) over the grid with the configured OMPL planner through planning::planOnPlane
/// (same planners, budget, seed, simplification as planning::planOnSurface). Start and goal (map
/// frame W) move to the nearest valid pose within the snap radius (horizontal distance, and the
/// ground within 1 m vertically); kUnreachable when their valid cells are not 8-connected.
/// @throw std::invalid_argument if the config does not validate or the grid is empty.
GridPlanResult planOnGrid(const HeightGrid& grid, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                          const planning::PlannerConfig& config, double cost_weight);

}  // namespace terramesh::baselines
