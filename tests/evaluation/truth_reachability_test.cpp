// evaluation::TruthReachability on hand-made truths: a ramp joining two levels, an island slab, a
// wall that cuts the ground in two or leaves a gap round its free end.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "evaluation/ground_truth_traversability.h"
#include "evaluation/truth_reachability.h"
#include "labeled_mesh_builder.h"

namespace terramesh::evaluation {
namespace {

using datasets::LabeledMesh;
using datasets::SurfaceLabel;
using test::addFloor;
using test::addQuad;

RobotLimits smallRobot() {
  RobotLimits robot;
  robot.footprint_radius_m = 0.3;
  robot.max_slope_deg = 20;
  robot.max_step_m = 0.2;
  robot.height_m = 0.5;
  return robot;
}

GroundTruthTraversability judge(const LabeledMesh& truth, const RobotLimits& robot = smallRobot()) {
  return labelTraversability(truth, robot, Eigen::Vector3d::UnitZ(), GroundTruthConfig{});
}

/// Ground [0, 10] x [0, 4], a ramp up `slope_deg` along +x over [10, 13], a plateau [13, 18] at
/// its top; and an island slab [22, 26] x [0, 4], 0.4 m up, with vertical edges (walls).
LabeledMesh twoLevelsAndIsland(double slope_deg) {
  LabeledMesh mesh;
  const double top = 3.0 * std::tan(slope_deg * M_PI / 180.0);
  addFloor(mesh, 0, 10, 0, 4, 0, SurfaceLabel::kRoad);
  addQuad(mesh, {10, 0, 0}, {13, 0, top}, {13, 4, top}, {10, 4, 0}, SurfaceLabel::kRamp);
  addFloor(mesh, 13, 18, 0, 4, top, SurfaceLabel::kRoad);
  addFloor(mesh, 22, 26, 0, 4, 0.4, SurfaceLabel::kRoad);
  addQuad(mesh, {22, 4, 0}, {22, 0, 0}, {22, 0, 0.4}, {22, 4, 0.4}, SurfaceLabel::kWall);
  return mesh;
}

/// Ground [0, 10] x [0, 10] with a 0.15 m thick, 1.5 m tall wall at x = 5 over y in [0, length].
LabeledMesh groundWithWall(double length) {
  LabeledMesh mesh;
  addFloor(mesh, 0, 10, 0, 10, 0, SurfaceLabel::kRoad);
  const double x0 = 4.925, x1 = 5.075, h = 1.5;
  addQuad(mesh, {x0, length, 0}, {x0, 0, 0}, {x0, 0, h}, {x0, length, h}, SurfaceLabel::kWall);  // faces -x
  addQuad(mesh, {x1, 0, 0}, {x1, length, 0}, {x1, length, h}, {x1, 0, h}, SurfaceLabel::kWall);  // faces +x
  addQuad(mesh, {x0, length, 0}, {x0, length, h}, {x1, length, h}, {x1, length, 0}, SurfaceLabel::kWall);
  addFloor(mesh, x0, x1, 0, length, h, SurfaceLabel::kWall);
  return mesh;
}

TEST(TruthReachabilityTest, RampWithinTheSlopeLimitJoinsTheLevels) {
  const GroundTruthTraversability labels = judge(twoLevelsAndIsland(16.0));
  const TruthReachability reach(labels);
  const ReachAnswer up_the_ramp = reach.connects({2, 2, 0}, {16, 2, 3 * std::tan(16.0 * M_PI / 180)});
  EXPECT_TRUE(up_the_ramp.reachable()) << toString(up_the_ramp.status);
  ASSERT_TRUE(up_the_ramp.start_face && up_the_ramp.goal_face);
  EXPECT_EQ(reach.component(*up_the_ramp.start_face), reach.component(*up_the_ramp.goal_face));
}

TEST(TruthReachabilityTest, RampSteeperThanTheLimitDoesNot) {
  const double slope = 25.0;
  const TruthReachability reach(judge(twoLevelsAndIsland(slope)));
  const ReachAnswer answer = reach.connects({2, 2, 0}, {16, 2, 3 * std::tan(slope * M_PI / 180)});
  EXPECT_FALSE(answer.reachable());
  EXPECT_EQ(answer.status, ReachStatus::kDifferentComponents);
}

TEST(TruthReachabilityTest, SlabWithoutRampIsAnIsland) {
  const GroundTruthTraversability labels = judge(twoLevelsAndIsland(16.0));
  const TruthReachability reach(labels);
  // The island's top is traversable, but only the 0.4 m edge leads onto it.
  const ReachAnswer onto_slab = reach.connects({5, 2, 0}, {24, 2, 0.4});
  EXPECT_EQ(onto_slab.status, ReachStatus::kDifferentComponents) << toString(onto_slab.status);
  ASSERT_TRUE(onto_slab.goal_face.has_value());
  EXPECT_TRUE(labels.traversable[*onto_slab.goal_face]);
  // Ground, ramp and plateau in one component, the island in another.
  EXPECT_EQ(reach.componentCount(), 2u);
}

TEST(TruthReachabilityTest, WallAcrossTheGroundSplitsItAndOneWithAFreeEndDoesNot) {
  const TruthReachability closed(judge(groundWithWall(10.0)));
  EXPECT_EQ(closed.connects({3, 5, 0}, {7, 5, 0}).status, ReachStatus::kDifferentComponents);
  const TruthReachability open(judge(groundWithWall(7.0)));
  EXPECT_TRUE(open.connects({3, 5, 0}, {7, 5, 0}).reachable());
  // Beside the wall the footprint does not fit: the start is not traversable.
  EXPECT_EQ(open.connects({4.8, 5, 0}, {7, 5, 0}).status, ReachStatus::kStartNotTraversable);
}

TEST(TruthReachabilityTest, PointsOffTheTruthHaveNoSurface) {
  const TruthReachability reach(judge(twoLevelsAndIsland(16.0)));
  EXPECT_EQ(reach.connects({-5, 2, 0}, {2, 2, 0}).status, ReachStatus::kNoSurfaceUnderStart);
  EXPECT_EQ(reach.connects({2, 2, 0}, {2, 2, 3.0}).status, ReachStatus::kNoSurfaceUnderGoal);
  EXPECT_FALSE(reach.faceUnder({2, 2, -1.0}).has_value());
  EXPECT_THROW(reach.connects({NAN, 0, 0}, {2, 2, 0}), std::invalid_argument);
}

TEST(TruthReachabilityTest, ConfigAndMismatchedTruthThrow) {
  ReachabilityConfig config;
  config.edge_tolerance_m = 0;
  config.snap_height_m = -1;
  try {
    config.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("edge_tolerance_m"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("snap_height_m"), std::string::npos);
  }
  GroundTruthTraversability labels = judge(twoLevelsAndIsland(16.0));
  labels.traversable.pop_back();
  EXPECT_THROW(TruthReachability{labels}, std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::evaluation
