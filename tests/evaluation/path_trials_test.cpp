// evaluation::runPathTrials, the planning comparison harness of `compare` and `planner_demo`:
// scripted planners on a labelled truth with a wall, so that every count it keeps can be wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "datasets/triangle_bvh.h"
#include "evaluation/path_trials.h"
#include "labeled_mesh_builder.h"

namespace terramesh::evaluation {
namespace {

using Eigen::Vector3d;

/// A planner that answers each query from a script, and logs the order it was asked in.
class ScriptedPlanner final : public planning::PathPlanner {
 public:
  ScriptedPlanner(std::string name, std::vector<planning::PlanResult> script, std::vector<std::string>& log)
      : name_(std::move(name)), script_(std::move(script)), log_(log) {}
  planning::PlanResult plan(const Vector3d& start_W, const Vector3d& goal_W) const override {
    if (!start_W.allFinite() || !goal_W.allFinite()) throw std::invalid_argument("not finite");
    log_.push_back(name_ + std::to_string(asked_));
    return script_.at(asked_++);
  }

 private:
  std::string name_;
  std::vector<planning::PlanResult> script_;
  std::vector<std::string>& log_;
  mutable std::size_t asked_ = 0;
};

/// A straight path along x at y, z = 0, solved, with its length and a cost twice that.
planning::PlanResult straight(double x0, double x1, double y, double time_s) {
  planning::PlanResult r;
  r.status = planning::PlanStatus::kSolved;
  for (double x = x0; x <= x1 + 1e-9; x += 0.5) {
    planning::PathState s;
    s.location.point_W = Vector3d(x, y, 0);
    r.states.push_back(s);
  }
  r.length_m = x1 - x0;
  r.cost = 2 * r.length_m;
  r.planning_time_s = time_s;
  return r;
}

planning::PlanResult refused(planning::PlanStatus status, double time_s) {
  planning::PlanResult r;
  r.status = status;
  r.reason = planning::toString(status);
  r.planning_time_s = time_s;
  return r;
}

/// Road over [0, 10] x [-5, 5]; a 1 m high wall along x at y = 2 from x = 4 to 6.
datasets::LabeledMesh roadWithWall() {
  datasets::LabeledMesh truth;
  test::addFloor(truth, 0, 10, -5, 5, 0, datasets::SurfaceLabel::kRoad);
  test::addQuad(truth, {4, 2, 0}, {6, 2, 0}, {6, 2, 1}, {4, 2, 1}, datasets::SurfaceLabel::kWall);
  return truth;
}

/// roadWithWall() with its checker, for the truth of a comparison.
struct RoadWithWall {
  datasets::LabeledMesh truth = roadWithWall();
  datasets::TriangleBvh bvh{truth.mesh};
  TruthChecker checker{truth, bvh};
  PathTruth pathTruth(const TruthCheckConfig& config) const {
    PathTruth path_truth;
    path_truth.checker = &checker;
    path_truth.config = config;
    return path_truth;
  }
};

TEST(PathTrialsTest, RunsPairByPairInPlannerOrderAndChecksEverySolvedPathOnTheTruth) {
  const RoadWithWall road;
  TruthCheckConfig disc;
  disc.footprint_radius_m = 0.34;
  disc.max_step_m = 0.18;
  disc.min_clearance_m = 0.5;
  const PathTruth path_truth = road.pathTruth(disc);
  std::vector<std::string> log;
  // a: clear of the wall, then into it (y = 2.1 passes the wall's face at 0.1 m), then refused.
  const ScriptedPlanner a("a", {straight(1, 9, -3, 0.5), straight(1, 9, 2.1, 0.25), refused(planning::PlanStatus::kNoGoal, 0.125)}, log);
  // b: unreachable, solved clear, not found.
  const ScriptedPlanner b("b", {refused(planning::PlanStatus::kUnreachable, 1), straight(2, 8, -1, 2), refused(planning::PlanStatus::kNotFound, 4)}, log);
  const std::vector<std::pair<Vector3d, Vector3d>> pairs(3, {Vector3d(1, 0, 0), Vector3d(9, 0, 0)});
  const std::vector<PlannerTrials> trials = runPathTrials({&a, &b}, pairs, path_truth);

  EXPECT_EQ(log, (std::vector<std::string>{"a0", "b0", "a1", "b1", "a2", "b2"}));
  ASSERT_EQ(trials.size(), 2u);
  const PlannerTrials& ta = trials[0];
  ASSERT_EQ(ta.trials.size(), 3u);
  EXPECT_EQ(ta.solved, 2u);
  EXPECT_EQ(ta.truth_checked, 2u);
  EXPECT_EQ(ta.truth_valid, 1u);
  EXPECT_TRUE(ta.trials[0].checked && ta.trials[0].check.valid) << ta.trials[0].check.reason;
  EXPECT_TRUE(ta.trials[1].checked);
  EXPECT_FALSE(ta.trials[1].check.valid);
  EXPECT_NE(ta.trials[1].check.reason.find("wall"), std::string::npos) << ta.trials[1].check.reason;
  EXPECT_FALSE(ta.trials[2].checked);
  EXPECT_EQ(ta.no_start_or_goal, 1u);
  EXPECT_EQ(ta.unreachable, 0u);
  EXPECT_DOUBLE_EQ(ta.length_m, 16.0);
  EXPECT_DOUBLE_EQ(ta.cost, 32.0);
  EXPECT_DOUBLE_EQ(ta.time_s, 0.875);

  const PlannerTrials& tb = trials[1];
  EXPECT_EQ(tb.solved, 1u);
  EXPECT_EQ(tb.truth_valid, 1u);
  EXPECT_EQ(tb.unreachable, 1u);
  EXPECT_EQ(tb.no_start_or_goal, 0u);
  EXPECT_DOUBLE_EQ(tb.length_m, 6.0);
  EXPECT_DOUBLE_EQ(tb.time_s, 7.0);
  EXPECT_EQ(tb.trials[2].result.status, planning::PlanStatus::kNotFound);
}

TEST(PathTrialsTest, ABodyThatKeepsItsOwnHeadingIsCheckedAtThePathsYaw) {
  // A 1.1 x 0.5 m rectangle 0.4 m beside the wall's face (y = 1.6): along its path (yaw 0) its
  // half width clears it; walking the same path sideways (yaw 90 deg) its half length does not.
  const RoadWithWall road;
  TruthCheckConfig legged;
  legged.footprint_length_m = 1.1;
  legged.footprint_width_m = 0.5;
  legged.footprint_radius_m = 0.5 * std::hypot(1.1, 0.5);
  legged.max_step_m = 0.3;
  legged.own_heading = true;
  const PathTruth path_truth = road.pathTruth(legged);
  planning::PlanResult sideways = straight(1, 9, 1.6, 0.5);
  for (planning::PathState& state : sideways.states) state.yaw_rad = M_PI / 2;
  std::vector<std::string> log;
  const ScriptedPlanner a("a", {straight(1, 9, 1.6, 0.5), sideways}, log);
  const std::vector<std::pair<Vector3d, Vector3d>> pairs(2, {Vector3d(1, 0, 0), Vector3d(9, 0, 0)});
  const PlannerTrials tally = runPathTrials({&a}, pairs, path_truth).front();
  ASSERT_EQ(tally.truth_checked, 2u);
  EXPECT_TRUE(tally.trials[0].check.valid) << tally.trials[0].check.reason;
  EXPECT_FALSE(tally.trials[1].check.valid);
  EXPECT_NE(tally.trials[1].check.reason.find("the body's heading"), std::string::npos) << tally.trials[1].check.reason;
}

TEST(PathTrialsTest, WithoutATruthNothingIsCheckedAndANullPlannerIsRefused) {
  std::vector<std::string> log;
  const ScriptedPlanner a("a", {straight(1, 9, 2.1, 0.5)}, log);
  const std::vector<std::pair<Vector3d, Vector3d>> pairs = {{Vector3d(1, 0, 0), Vector3d(9, 0, 0)}};
  const std::vector<PlannerTrials> trials = runPathTrials({&a}, pairs, PathTruth{});
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].solved, 1u);
  EXPECT_EQ(trials[0].truth_checked, 0u);
  EXPECT_FALSE(trials[0].trials[0].checked);
  EXPECT_THROW(runPathTrials({&a, nullptr}, pairs, PathTruth{}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::evaluation
