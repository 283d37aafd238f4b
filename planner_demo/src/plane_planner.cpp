// SE(2) planning over a bounded plane with the caller's validity and motion cost (the OctoMap
// baseline's 2.5D grid), with the same OMPL planners as the surface.
#include "planning/plane_planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <stdexcept>

#include "planner_factory.h"

namespace terramesh::planning {
namespace {

using Clock = std::chrono::steady_clock;

Eigen::Vector2d xy(const ompl::base::State* s) {
  const auto* se2 = s->as<ompl::base::SE2StateSpace::StateType>();
  return {se2->getX(), se2->getY()};
}

class PlaneCostObjective : public ompl::base::OptimizationObjective {
 public:
  PlaneCostObjective(const ompl::base::SpaceInformationPtr& si, const PlaneProblem& problem)
      : ompl::base::OptimizationObjective(si), problem_(problem) {
    description_ = "the caller's motion cost";
  }
  ompl::base::Cost stateCost(const ompl::base::State*) const override { return identityCost(); }
  ompl::base::Cost motionCost(const ompl::base::State* s1, const ompl::base::State* s2) const override {
    return ompl::base::Cost(problem_.motion_cost(xy(s1), xy(s2)));
  }
  ompl::base::Cost motionCostHeuristic(const ompl::base::State* s1, const ompl::base::State* s2) const override {
    return ompl::base::Cost((xy(s1) - xy(s2)).norm());
  }

 private:
  const PlaneProblem& problem_;
};

void checkProblem(const PlaneProblem& problem, double dense_step) {
  if (!problem.is_valid || !problem.motion_cost) throw std::invalid_argument("planOnPlane: is_valid and motion_cost are required");
  if (!(problem.high.x() > problem.low.x()) || !(problem.high.y() > problem.low.y())) {
    throw std::invalid_argument("planOnPlane: the bounds are empty");
  }
  if (!(problem.validity_step > 0) || !(dense_step > 0)) throw std::invalid_argument("planOnPlane: validity_step and dense_step must be > 0");
}

}  // namespace

PlanePath planOnPlane(const PlaneProblem& problem, const PlannerConfig& config, double dense_step) {
  config.validate();
  checkProblem(problem, dense_step);
  PlanePath result;
  result.planner = canonicalPlannerName(config.planner).value_or(config.planner);
  auto space = std::make_shared<ompl::base::SE2StateSpace>();
  ompl::base::RealVectorBounds bounds(2);
  bounds.setLow(0, problem.low.x());
  bounds.setHigh(0, problem.high.x());
  bounds.setLow(1, problem.low.y());
  bounds.setHigh(1, problem.high.y());
  space->setBounds(bounds);
  ompl::geometric::SimpleSetup setup(space);
  const ompl::base::SpaceInformationPtr si = setup.getSpaceInformation();
  setup.setStateValidityChecker([&problem](const ompl::base::State* s) { return problem.is_valid(xy(s)); });
  si->setStateValidityCheckingResolution(problem.validity_step / space->getMaximumExtent());
  setup.setOptimizationObjective(std::make_shared<PlaneCostObjective>(si, problem));
  ompl::base::ScopedState<ompl::base::SE2StateSpace> start(space), goal(space);
  start->setXY(problem.start.x(), problem.start.y());
  start->setYaw(problem.yaw_rad);
  goal->setXY(problem.goal.x(), problem.goal.y());
  goal->setYaw(problem.yaw_rad);
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
  for (std::size_t i = 0; i < path.getStateCount(); ++i) result.waypoints.push_back(xy(path.getState(i)));
  const double total = path.length();
  path.interpolate(static_cast<unsigned int>(std::max(2.0, std::ceil(total / dense_step))));
  for (std::size_t i = 0; i < path.getStateCount(); ++i) result.dense.push_back(xy(path.getState(i)));
  result.status = PlanStatus::kSolved;
  return result;
}

}  // namespace terramesh::planning
