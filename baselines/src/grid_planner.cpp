// SE(2) planning over the 2.5D grid of the OctoMap baseline, with planning's OMPL planners.
#include "baselines/grid_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <stdexcept>

#include "planning/plane_planner.h"

namespace terramesh::baselines {
namespace {

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

/// Grid-plane points (metres) as path states in W: on the ground, heading along the path (the last
/// keeps the one before), with their cell's cost.
std::vector<planning::PathState> statesOf(const HeightGrid& grid, const std::vector<Eigen::Vector2d>& points) {
  std::vector<planning::PathState> states;
  states.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& p = points[i];
    planning::PathState state;
    const Eigen::Vector3d p_G(p.x(), p.y(), groundAt(grid, p.x(), p.y()));
    state.location = {planning::FaceGraph::kNoFace, grid.R_G_W.transpose() * p_G / grid.metres_per_unit};
    Eigen::Vector2d step = Eigen::Vector2d::Zero();
    if (i + 1 < points.size()) step = points[i + 1] - p;
    else if (i > 0) step = p - points[i - 1];
    state.yaw_rad = step.squaredNorm() > 0 ? std::atan2(step.y(), step.x()) : 0.0;
    const Eigen::Vector2i c = grid.cellOf(p.x(), p.y());
    state.face_cost = grid.inside(c.x(), c.y()) ? grid.cost[grid.index(c.x(), c.y())] : std::nanf("");
    states.push_back(state);
  }
  return states;
}

}  // namespace

planning::PlanResult planOnGrid(const HeightGrid& grid, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                                const planning::PlannerConfig& config, double cost_weight) {
  config.validate();
  if (grid.width <= 0 || grid.height <= 0) throw std::invalid_argument("planOnGrid: the grid is empty");
  planning::PlanResult result;
  result.planner = planning::canonicalPlannerName(config.planner).value_or(config.planner);
  const Eigen::Vector3d start_G = grid.R_G_W * start_W * grid.metres_per_unit;
  const Eigen::Vector3d goal_G = grid.R_G_W * goal_W * grid.metres_per_unit;
  const auto start_cell = snapCell(grid, start_G, config.snap_radius_m);
  const auto goal_cell = snapCell(grid, goal_G, config.snap_radius_m);
  if (!start_cell || !goal_cell) {
    result.status = start_cell ? planning::PlanStatus::kNoGoal : planning::PlanStatus::kNoStart;
    result.reason = std::string("no valid grid cell near the ") + (start_cell ? "goal" : "start");
    return result;
  }
  if (!connected(grid, *start_cell, *goal_cell)) {
    result.status = planning::PlanStatus::kUnreachable;
    result.reason = "start and goal cells are not connected through valid cells";
    return result;
  }
  auto centre = [&](const Eigen::Vector2i& c) {
    return Eigen::Vector2d(grid.origin_x_m + (c.x() + 0.5) * grid.resolution_m, grid.origin_y_m + (c.y() + 0.5) * grid.resolution_m);
  };
  planning::PlaneProblem problem;
  problem.low = Eigen::Vector2d(grid.origin_x_m, grid.origin_y_m);
  problem.high = Eigen::Vector2d(grid.origin_x_m + grid.width * grid.resolution_m, grid.origin_y_m + grid.height * grid.resolution_m);
  problem.is_valid = [&grid](const Eigen::Vector2d& p) {
    const Eigen::Vector2i c = grid.cellOf(p.x(), p.y());
    return grid.inside(c.x(), c.y()) && grid.valid_pose[grid.index(c.x(), c.y())] != 0;
  };
  problem.motion_cost = [&grid, cost_weight](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return segmentCost(grid, cost_weight, a, b).first;
  };
  problem.validity_step = 0.5 * grid.resolution_m;
  problem.start = centre(*start_cell);
  problem.goal = centre(*goal_cell);
  problem.yaw_rad = std::atan2(problem.goal.y() - problem.start.y(), problem.goal.x() - problem.start.x());
  const planning::PlanePath path = planning::planOnPlane(problem, config, 0.5 * grid.resolution_m);
  result.planning_time_s = path.planning_time_s;
  if (path.status != planning::PlanStatus::kSolved) {
    result.status = path.status;
    result.reason = path.reason;
    return result;
  }
  for (std::size_t i = 1; i < path.waypoints.size(); ++i) {
    const auto [cost, length] = segmentCost(grid, cost_weight, path.waypoints[i - 1], path.waypoints[i]);
    result.cost += cost;
    result.length_m += length;
  }
  result.states = statesOf(grid, path.dense);
  result.waypoints = statesOf(grid, path.waypoints);
  result.start = result.states.front().location;
  result.goal = result.states.back().location;
  result.status = planning::PlanStatus::kSolved;
  return result;
}

GridPlanner::GridPlanner(const HeightGrid& grid, const planning::PlannerConfig& config, double cost_weight)
    : grid_(grid), config_(config), cost_weight_(cost_weight) {
  config_.validate();
}

planning::PlanResult GridPlanner::plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W) const {
  return planOnGrid(grid_, start_W, goal_W, config_, cost_weight_);
}

}  // namespace terramesh::baselines
