// The OctoMap baseline on an analytic scene: a floor at z = 0 and a 1 m box, seen from cameras
// driving along x at 1.5 m height.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "baselines/grid_planner.h"
#include "baselines/octomap_baseline.h"
#include "planning/surface_planner.h"
#include "test_support/temp_dir.h"

namespace terramesh::baselines {
namespace {

bool inBox(double x, double y) { return x > 4 && x < 6 && y > -1 && y < 1; }

/// Dense points on the floor [0, 10] x [-3, 3] (not under the box) and on the box's top and sides.
std::vector<mesher::Keyframe> floorAndBoxKeyframes() {
  std::vector<mesher::Keyframe> keyframes;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(0, 10), uy(-3, 3), unit(0, 1);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 30000; ++i) {
    const double x = ux(rng), y = uy(rng);
    if (!inBox(x, y)) points.emplace_back(x, y, 0.0);
  }
  for (int i = 0; i < 2000; ++i) points.emplace_back(4 + 2 * unit(rng), -1 + 2 * unit(rng), 1.0);  // top
  for (int i = 0; i < 2000; ++i) points.emplace_back(4.0, -1 + 2 * unit(rng), unit(rng));          // sides
  for (int i = 0; i < 2000; ++i) points.emplace_back(6.0, -1 + 2 * unit(rng), unit(rng));
  for (int i = 0; i < 2000; ++i) points.emplace_back(4 + 2 * unit(rng), -1.0, unit(rng));
  for (int i = 0; i < 2000; ++i) points.emplace_back(4 + 2 * unit(rng), 1.0, unit(rng));
  for (int k = 0; k < 6; ++k) {
    mesher::Keyframe keyframe;
    keyframe.id = mesher::KeyframeId{static_cast<std::uint64_t>(k)};
    keyframe.position_W_C = Eigen::Vector3d(2.0 * k, k % 2 == 0 ? -2.5 : 2.5, 1.5);
    for (std::size_t p = 0; p < points.size(); ++p) {
      if ((points[p] - keyframe.position_W_C).norm() < 6.0) {
        keyframe.observations.push_back({mesher::PointId{p}, points[p]});
      }
    }
    keyframes.push_back(keyframe);
  }
  return keyframes;
}

TEST(OctomapBaselineTest, GroundHeightsStepsAndAPathRoundTheBox) {
  OctomapConfig config;
  config.resolution_m = 0.2;
  OctomapBaseline octomap(config);
  for (const mesher::Keyframe& keyframe : floorAndBoxKeyframes()) octomap.insertKeyframe(keyframe);
  const OctomapStats stats = octomap.stats();
  EXPECT_EQ(stats.keyframes, 6u);
  EXPECT_GT(stats.occupied_leaves, 100u);
  EXPECT_GT(stats.memory_bytes, 0u);
  test::TempDir dir;
  octomap.writeBinary(dir / "map.bt");
  EXPECT_GT(std::filesystem::file_size(dir / "map.bt"), 100u);

  GridRobotConfig robot;
  robot.max_step_m = 0.25;
  robot.footprint_radius_m = 0.3;
  const HeightGrid grid = octomap.heightGrid(robot);
  ASSERT_GT(grid.knownCells(), 500u);
  std::size_t floor_cells = 0, box_cells = 0;
  for (int j = 0; j < grid.height; ++j) {
    for (int i = 0; i < grid.width; ++i) {
      const float h = grid.ground_z_m[grid.index(i, j)];
      if (std::isnan(h)) continue;
      const double x = grid.origin_x_m + (i + 0.5) * grid.resolution_m, y = grid.origin_y_m + (j + 0.5) * grid.resolution_m;
      // Ground = the top of the voxel holding the surface: within one voxel above the truth.
      const double truth = inBox(x, y) ? 1.0 : 0.0;
      if (std::abs(x - 4) < 0.3 || std::abs(x - 6) < 0.3 || std::abs(std::abs(y) - 1) < 0.3) continue;  // box edges
      EXPECT_GE(h, truth - 1e-6) << x << ' ' << y;
      EXPECT_LE(h, truth + 0.2 + 1e-6) << x << ' ' << y;
      (inBox(x, y) ? box_cells : floor_cells) += 1;
    }
  }
  EXPECT_GT(floor_cells, 300u);
  EXPECT_GT(box_cells, 5u);
  // Cells at the box's rim see a ~1 m step: never traversable.
  std::size_t rim_cells = 0;
  for (std::size_t c = 0; c < grid.step_m.size(); ++c) {
    if (!(grid.step_m[c] > 0.7)) continue;
    ++rim_cells;
    EXPECT_FALSE(grid.traversable[c]);
  }
  EXPECT_GT(rim_cells, 5u);

  planning::setOmplLogging(false);
  planning::PlannerConfig planner;
  planner.planner = "rrtstar";
  planner.time_budget_s = 0.5;
  planner.time_cap_s = 60;  // found or not must not depend on the machine's load
  planner.snap_radius_m = 0.6;
  const GridPlanner grid_planner(grid, planner, robot.cost_weight);
  const planning::PlanResult result = grid_planner.plan({2, 0, 0}, {8, 0, 0});
  ASSERT_TRUE(result.solved()) << result.reason;
  ASSERT_GE(result.states.size(), 2u);
  for (const planning::PathState& s : result.states) {
    const Eigen::Vector3d& p = s.location.point_W;
    EXPECT_FALSE(p.x() > 3.95 && p.x() < 6.05 && p.y() > -1.05 && p.y() < 1.05) << "through the box at " << p.transpose();
    EXPECT_EQ(s.location.face, planning::FaceGraph::kNoFace);
    EXPECT_TRUE(s.face_cost >= 0 && s.face_cost <= 1) << s.face_cost;
  }
  // Headings follow the path: the first state looks towards the second.
  const Eigen::Vector3d first_step = result.states[1].location.point_W - result.states[0].location.point_W;
  EXPECT_NEAR(std::remainder(result.states[0].yaw_rad - std::atan2(first_step.y(), first_step.x()), 2 * M_PI), 0, 1e-6);
  EXPECT_GT(result.length_m, 6.0);
  // The box top is an island: unreachable.
  EXPECT_NE(planOnGrid(grid, {2, 0, 0}, {5, 0, 1}, planner, robot.cost_weight).status, planning::PlanStatus::kSolved);
}

}  // namespace
}  // namespace terramesh::baselines
