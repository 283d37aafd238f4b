// SE(2) planning over a plane the caller describes: a 10 x 6 field with a wall across it that
// leaves a gap at one end.
#include <gtest/gtest.h>

#include <stdexcept>

#include "planning/plane_planner.h"

namespace terramesh::planning {
namespace {

bool inWall(const Eigen::Vector2d& p) { return p.x() > 4.5 && p.x() < 5.5 && p.y() < 4.0; }

/// Deeper than `depth` inside the wall. Motions are checked every validity_step (0.05), as OMPL's
/// discrete motion validator does, so a motion may cut the wall's corner by less than that.
bool deepInWall(const Eigen::Vector2d& p, double depth) {
  return p.x() > 4.5 + depth && p.x() < 5.5 - depth && p.y() < 4.0 - depth;
}

PlaneProblem fieldWithWall() {
  PlaneProblem problem;
  problem.low = Eigen::Vector2d(0, 0);
  problem.high = Eigen::Vector2d(10, 6);
  problem.is_valid = [](const Eigen::Vector2d& p) { return !inWall(p); };
  problem.motion_cost = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return (b - a).norm(); };
  problem.validity_step = 0.05;
  problem.start = Eigen::Vector2d(1, 1);
  problem.goal = Eigen::Vector2d(9, 1);
  return problem;
}

PlannerConfig quickConfig() {
  setOmplLogging(false);
  PlannerConfig config;
  config.planner = "RRT*";
  config.time_budget_s = 0.3;
  config.time_cap_s = 60;  // found or not must not depend on the machine's load
  return config;
}

TEST(PlanOnPlaneTest, GoesRoundTheWallThroughTheGap) {
  const PlanePath path = planOnPlane(fieldWithWall(), quickConfig(), 0.1);
  ASSERT_EQ(path.status, PlanStatus::kSolved) << path.reason;
  EXPECT_EQ(path.planner, "rrtstar");
  ASSERT_GE(path.waypoints.size(), 2u);
  EXPECT_TRUE(path.waypoints.front().isApprox(Eigen::Vector2d(1, 1)));
  EXPECT_TRUE(path.waypoints.back().isApprox(Eigen::Vector2d(9, 1)));
  ASSERT_GT(path.dense.size(), path.waypoints.size());
  bool through_gap = false;
  for (const Eigen::Vector2d& p : path.dense) {
    EXPECT_FALSE(deepInWall(p, 0.05)) << p.transpose();
    if (p.x() > 4.5 && p.x() < 5.5) through_gap = through_gap || p.y() >= 4.0;
  }
  EXPECT_TRUE(through_gap);
}

TEST(PlanOnPlaneTest, RejectsMissingCallbacksAndEmptyBounds) {
  PlaneProblem no_cost = fieldWithWall();
  no_cost.motion_cost = nullptr;
  EXPECT_THROW(planOnPlane(no_cost, quickConfig(), 0.1), std::invalid_argument);
  PlaneProblem empty = fieldWithWall();
  empty.high = empty.low;
  EXPECT_THROW(planOnPlane(empty, quickConfig(), 0.1), std::invalid_argument);
  EXPECT_THROW(planOnPlane(fieldWithWall(), quickConfig(), 0.0), std::invalid_argument);
  PlannerConfig unknown = quickConfig();
  unknown.planner = "no-such-planner";
  EXPECT_THROW(planOnPlane(fieldWithWall(), unknown, 0.1), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::planning
