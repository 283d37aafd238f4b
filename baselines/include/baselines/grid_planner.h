#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "baselines/height_grid.h"
#include "planning/path_planner.h"
#include "planning/surface_planner.h"

namespace terramesh::baselines {

/// Plans in SE(2) over the grid with the configured OMPL planner through planning::planOnPlane
/// (same planners, budget, seed, simplification as planning::planOnSurface). Start and goal (map
/// frame W) move to the nearest valid pose within the snap radius (horizontal distance, and the
/// ground within 1 m vertically); kUnreachable when their valid cells are not 8-connected.
/// The result is a planning::PlanResult like the surface planners': its states are the path on
/// the grid (map frame W, map units, z from the ground heights; no face:
/// planning::FaceGraph::kNoFace), each with the heading of travel and its cell's cost;
/// length_m is the 3D length over the ground heights, cost the integral of (1 + w * cost) over it.
/// @throw std::invalid_argument if the config does not validate or the grid is empty.
planning::PlanResult planOnGrid(const HeightGrid& grid, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                                const planning::PlannerConfig& config, double cost_weight);

/// planOnGrid as a planning::PathPlanner. Keeps references: `grid` and `config` must outlive it.
class GridPlanner final : public planning::PathPlanner {
 public:
  /// @throw std::invalid_argument if the config does not validate (plan: also if the grid is empty).
  GridPlanner(const HeightGrid& grid, const planning::PlannerConfig& config, double cost_weight);
  planning::PlanResult plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W) const override;

 private:
  const HeightGrid& grid_;
  const planning::PlannerConfig& config_;
  double cost_weight_;
};

}  // namespace terramesh::baselines
