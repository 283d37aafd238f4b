// SE(2) planning over the 2.5D grid of the OctoMap baseline, with the same OMPL planners.
#include "planning/grid_planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <optional>
#include <queue>
#include <stdexcept>

#include "planner_factory.h"

namespace terramesh::planning {
namespace {

using Clock = std::chrono::steady_clock;

double groundAt(const HeightGrid& grid, double x, double y) {
  const Eigen::Vector2i c = grid.cellOf(x, y);
  if (!grid.inside(c.x(), c.y())) return std::numeric_limits<double>::quiet_NaN();
  return grid.ground_z_m[grid.index(c.x(), c.y())];
}

/// Integral of (1 + w * cost) along the straight segment, over the ground heights, in metres;
/// also its 3D length.
std::pair<double, double> segmentCost(const HeightGrid& grid, double w, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double d = (b - a).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(d / (0.5 * grid.resolution_m))));
  double cost = 0, length = 0;
  Eigen::Vector3d previous(a.x(), a.y(), groundAt(grid, a.x(), a.y()));
  for (int s = 1; s <= steps; ++s) {
    const Eigen::Vector2d p2 = a + (b - a) * (static_cast<double>(s) / steps);
    const Eigen::Vector3d p(p2.x(), p2.y(), groundAt(grid, p2.x(), p2.y()));
    const double piece = std::isnan(p.z()) || std::isnan(previous.z()) ? (p2 - previous.head<2>()).norm() : (p - previous).norm();
    const Eigen::Vector2i c = grid.cellOf(p2.x(), p2.y());
    const double c_cost = grid.inside(c.x(), c.y()) && !std::isnan(grid.cost[grid.index(c.x(), c.y())])
                              ? grid.cost[grid.index(c.x(), c.y())] : 1.0;
    cost += piece * (1.0 + w * c_cost);
    length += piece;
    previous = p;
  }
  return {cost, length};
}

class GridCostObjective : public ompl::base::OptimizationObjective {
 public:
  GridCostObjective(const ompl::base::SpaceInformationPtr& si, const HeightGrid& grid, double w)
      : ompl::base::OptimizationObjective(si), grid_(grid), w_(w) {
    description_ = "ground length weighted by grid cost";
  }
  ompl::base::Cost stateCost(const ompl::base::State*) const override { return identityCost(); }
  ompl::base::Cost motionCost(const ompl::base::State* s1, const ompl::base::State* s2) const override {
    return ompl::base::Cost(segmentCost(grid_, w_, xy(s1), xy(s2)).first);
  }
  ompl::base::Cost motionCostHeuristic(const ompl::base::State* s1, const ompl::base::State* s2) const override {
    return ompl::base::Cost((xy(s1) - xy(s2)).norm());
  }
  static Eigen::Vector2d xy(const ompl::base::State* s) {
    const auto* se2 = s->as<ompl::base::SE2StateSpace::StateType>();
    return {se2->getX(), se2->getY()};
  }

 private:
  const HeightGrid& grid_;
  double w_;
};

/// The nearest valid pose cell to p (G, metres) within `radius_m` horizontally and 1 m vertically.
std::optional<Eigen::Vector2i> snapCell(const HeightGrid& grid, const Eigen::Vector3d& p, double radius_m) {
  const Eigen::Vector2i centre = grid.cellOf(p.x(), p.y());
  const int r = static_cast<int>(std::ceil(radius_m / grid.resolution_m)) + 1;
  std::optional<Eigen::Vector2i> best;
  double best_d = std::numeric_limits<double>::infinity();
  for (int dj = -r; dj <= r; ++dj) {
    for (int di = -r; di <= r; ++di) {
      const int i = centre.x() + di, j = centre.y() + dj;
      if (!grid.inside(i, j) || !grid.valid_pose[grid.index(i, j)]) continue;
      const double cx = grid.origin_x_m + (i + 0.5) * grid.resolution_m, cy = grid.origin_y_m + (j + 0.5) * grid.resolution_m;
      const double d = std::hypot(cx - p.x(), cy - p.y());
      if (d > radius_m + 0.71 * grid.resolution_m || std::abs(grid.ground_z_m[grid.index(i, j)] - p.z()) > 1.0) continue;
      if (d < best_d) {
        best_d = d;
        best = Eigen::Vector2i(i, j);
      }
    }
  }
  return best;
}

bool connected(const HeightGrid& grid, const Eigen::Vector2i& a, const Eigen::Vector2i& b) {
  std::vector<std::uint8_t> seen(grid.valid_pose.size(), 0);
  std::queue<Eigen::Vector2i> open;
  open.push(a);
  seen[grid.index(a.x(), a.y())] = 1;
  while (!open.empty()) {
    const Eigen::Vector2i c = open.front();
    open.pop();
    if (c == b) return true;
    for (int dj = -1; dj <= 1; ++dj) {
      for (int di = -1; di <= 1; ++di) {
        const int i = c.x() + di, j = c.y() + dj;
        if (!grid.inside(i, j) || seen[grid.index(i, j)] || !grid.valid_pose[grid.index(i, j)]) continue;
        seen[grid.index(i, j)] = 1;
        open.emplace(i, j);
      }
    }
  }
  return false;
}

}  // namespace

GridPlanResult planOnGrid(const HeightGrid& grid, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                          const PlannerConfig& config, double cost_weight) {
  config.validate();
  if (grid.width <= 0 || grid.height <= 0) throw std::invalid_argument("planOnGrid: the grid is empty");
  GridPlanResult result;
  result.planner = internal::canonicalPlannerName(config.planner).value_or(config.planner);
  const Eigen::Vector3d start_G = grid.R_G_W * start_W * grid.metres_per_unit;
  const Eigen::Vector3d goal_G = grid.R_G_W * goal_W * grid.metres_per_unit;
  const auto start_cell = snapCell(grid, start_G, config.snap_radius_m);
  const auto goal_cell = snapCell(grid, goal_G, config.snap_radius_m);
  if (!start_cell || !goal_cell) {
    result.status = start_cell ? PlanStatus::kNoGoal : PlanStatus::kNoStart;
    result.reason = std::string("no valid grid cell near the ") + (start_cell ? "goal" : "start");
    return result;
  }
  if (!connected(grid, *start_cell, *goal_cell)) {
    result.status = PlanStatus::kUnreachable;
    result.reason = "start and goal cells are not connected through valid cells";
    return result;
  }
  auto space = std::make_shared<ompl::base::SE2StateSpace>();
  ompl::base::RealVectorBounds bounds(2);
  bounds.setLow(0, grid.origin_x_m);
  bounds.setHigh(0, grid.origin_x_m + grid.width * grid.resolution_m);
  bounds.setLow(1, grid.origin_y_m);
  bounds.setHigh(1, grid.origin_y_m + grid.height * grid.resolution_m);
  space->setBounds(bounds);
  ompl::geometric::SimpleSetup setup(space);
  const ompl::base::SpaceInformationPtr si = setup.getSpaceInformation();
  setup.setStateValidityChecker([&grid](const ompl::base::State* s) {
    const Eigen::Vector2d p = GridCostObjective::xy(s);
    const Eigen::Vector2i c = grid.cellOf(p.x(), p.y());
    return grid.inside(c.x(), c.y()) && grid.valid_pose[grid.index(c.x(), c.y())] != 0;
  });
  si->setStateValidityCheckingResolution(0.5 * grid.resolution_m / space->getMaximumExtent());
  setup.setOptimizationObjective(std::make_shared<GridCostObjective>(si, grid, cost_weight));
  ompl::base::ScopedState<ompl::base::SE2StateSpace> start(space), goal(space);
  auto centre = [&](const Eigen::Vector2i& c) {
    return Eigen::Vector2d(grid.origin_x_m + (c.x() + 0.5) * grid.resolution_m, grid.origin_y_m + (c.y() + 0.5) * grid.resolution_m);
  };
  const Eigen::Vector2d s2 = centre(*start_cell), g2 = centre(*goal_cell);
  const double yaw = std::atan2(g2.y() - s2.y(), g2.x() - s2.x());
  start->setXY(s2.x(), s2.y());
  start->setYaw(yaw);
  goal->setXY(g2.x(), g2.y());
  goal->setYaw(yaw);
  setup.setStartAndGoalStates(start, goal, 1e-9);
  setup.setPlanner(internal::makePlanner(config.planner, si, config.range_m));
  const auto started = Clock::now();
  const internal::PlannerClearer clearer(setup);
  const auto [status, planner_error] = internal::solveWithinCap(setup, config.time_budget_s, config.time_cap_s, started);
  result.planning_time_s = std::chrono::duration<double>(Clock::now() - started).count();
  if (status != ompl::base::PlannerStatus::EXACT_SOLUTION || !setup.haveExactSolutionPath()) {
    result.status = PlanStatus::kNotFound;
    result.reason = "the planner found no path within the budget (" + (planner_error.empty() ? status.asString() : planner_error) + ")";
    return result;
  }
  if (config.simplify) setup.simplifySolution(std::max(0.05, 0.25 * config.time_budget_s));
  ompl::geometric::PathGeometric path = setup.getSolutionPath();
  for (std::size_t i = 1; i < path.getStateCount(); ++i) {
    const auto [cost, length] = segmentCost(grid, cost_weight, GridCostObjective::xy(path.getState(i - 1)),
                                            GridCostObjective::xy(path.getState(i)));
    result.cost += cost;
    result.length_m += length;
  }
  const double total_xy = path.length();
  path.interpolate(static_cast<unsigned int>(std::max(2.0, std::ceil(total_xy / (0.5 * grid.resolution_m)))));
  for (std::size_t i = 0; i < path.getStateCount(); ++i) {
    const Eigen::Vector2d p = GridCostObjective::xy(path.getState(i));
    const Eigen::Vector3d p_G(p.x(), p.y(), groundAt(grid, p.x(), p.y()));
    result.points_W.push_back(grid.R_G_W.transpose() * p_G / grid.metres_per_unit);
  }
  result.status = PlanStatus::kSolved;
  return result;
}

}  // namespace terramesh::planning
