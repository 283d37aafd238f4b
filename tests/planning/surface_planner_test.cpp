// Planning on the surface over hand-built maps with known geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "planning/face_graph.h"
#include "planning/surface_planner.h"
#include "planning_fixtures.h"

namespace terramesh::planning {
namespace {

using traversability::FaceClass;

class SurfacePlannerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    setOmplLogging(false);
    seedOmpl(7);
  }
};

WalkabilityConfig walkability() {
  WalkabilityConfig config;
  config.min_lethal_distance_m = 0.3;
  return config;
}

/// Whether a planner finds a path must not depend on how loaded the machine running the test is:
/// past `budget_s` without an exact path it keeps searching, up to a generous cap (only reached
/// if the planner is truly stuck). What the tests check of a solved path holds for any valid
/// path, however little time it had to improve.
constexpr double kTimeCapS = 60.0;

PlannerConfig plannerConfig(const std::string& name, double budget_s) {
  PlannerConfig config;
  config.planner = name;
  config.time_budget_s = budget_s;
  config.time_cap_s = kTimeCapS;
  config.seed = 3;
  return config;
}

/// Every state on a free face of the map, every piece between states inside one face or across
/// a shared edge of two walkable faces (checked by the faces' shared vertices), and the length
/// equal to the polyline's.
void expectOnWalkableSurface(const FaceGraph& graph, const PlanResult& result) {
  ASSERT_GE(result.states.size(), 2u);
  double length = 0;
  for (std::size_t i = 0; i < result.states.size(); ++i) {
    const SurfaceLocation& location = result.states[i].location;
    ASSERT_LT(location.face, graph.faceCount());
    EXPECT_TRUE(graph.walkable(location.face)) << "state " << i << " on face " << location.face;
    EXPECT_EQ(graph.layers(location.face).face_class, FaceClass::kFree);
    const auto& t = graph.face(location.face);
    // The point lies on its face: distance to the face's plane ~ 0 and barycentric coords >= 0.
    const Eigen::Vector3d n = graph.normal(location.face);
    EXPECT_NEAR((location.point_W - graph.vertex(t[0])).dot(n), 0.0, 1e-6) << "state " << i;
    if (i > 0) {
      const SurfaceLocation& previous = result.states[i - 1].location;
      length += (location.point_W - previous.point_W).norm();
      // The piece lies on the previous state's face: its end is on that face's plane.
      const auto& tp = graph.face(previous.face);
      EXPECT_NEAR((location.point_W - graph.vertex(tp[0])).dot(graph.normal(previous.face)), 0.0, 1e-6)
          << "piece " << i << " leaves the surface";
    }
  }
  EXPECT_NEAR(length * graph.metresPerUnit(), result.length_m, 1e-6);
  EXPECT_GE(result.cost, result.length_m - 1e-9);
}

/// Whether the segment (a, b) in the plane z = 0 meets the axis-aligned rectangle.
bool segmentMeetsRectangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double x0, double x1, double y0, double y1) {
  for (int k = 0; k <= 200; ++k) {
    const Eigen::Vector3d p = a + (b - a) * (k / 200.0);
    if (p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1) return true;
  }
  return false;
}

TEST_F(SurfacePlannerTest, RoundTheWallThroughTheGapWithEveryPlanner) {
  const FaceGraph graph(test::wallWithGapMap(), walkability());
  const Eigen::Vector3d start(3, 2, 0), goal(17, 2, 0);
  const PlanResult baseline = planOnFaceGraph(graph, start, goal, plannerConfig("rrtstar", 1));
  ASSERT_TRUE(baseline.solved()) << baseline.reason;
  // Any way round the strip's end (x in 9.5..10.5, y < 7) is at least this long.
  const double lower_bound = (Eigen::Vector2d(9.5, 7) - Eigen::Vector2d(3, 2)).norm() + 1.0 +
                             (Eigen::Vector2d(17, 2) - Eigen::Vector2d(10.5, 7)).norm();
  EXPECT_GE(baseline.length_m, lower_bound - 1e-6);
  for (const std::string& name : plannerNames()) {
    SCOPED_TRACE(name);
    const PlanResult result = planOnSurface(graph, start, goal, plannerConfig(name, 0.7));
    ASSERT_TRUE(result.solved()) << result.reason;
    expectOnWalkableSurface(graph, result);
    EXPECT_GE(result.length_m, lower_bound - 1e-6);
    for (std::size_t i = 1; i < result.states.size(); ++i) {
      EXPECT_FALSE(segmentMeetsRectangle(result.states[i - 1].location.point_W, result.states[i].location.point_W,
                                         9.5, 10.5, 0, 7))
          << "piece " << i << " crosses the lethal strip";
    }
    EXPECT_NEAR((result.states.front().location.point_W - start).norm(), 0.0, 1e-9);
    EXPECT_NEAR((result.states.back().location.point_W - goal).norm(), 0.0, 1e-9);
    // The graph optimum is no worse than any planner's, up to its discretisation (4 points per
    // 0.5 m edge: within 1%).
    EXPECT_LE(baseline.cost, result.cost * 1.01) << "graph " << baseline.cost << " planner " << result.cost;
  }
}

TEST_F(SurfacePlannerTest, BetweenFloorsOnlyOverTheRamp) {
  const FaceGraph graph(test::twoLevelMap(), walkability());
  // Directly above each other: level 0 and level 1 at (6, 7).
  const Eigen::Vector3d start(6, 7, 0), goal(6, 7, 3);
  const PlanResult baseline = planOnFaceGraph(graph, start, goal, plannerConfig("rrtstar", 1));
  ASSERT_TRUE(baseline.solved()) << baseline.reason;
  // RRT* is left out: with Euclidean nearest neighbours its tree keeps trying to join states to
  // the floor below and rarely reaches the far floor in a few seconds (docs/planning.md).
  for (const std::string& name : {std::string("bitstar"), std::string("prmstar"), std::string("aitstar")}) {
    SCOPED_TRACE(name);
    const PlanResult result = planOnSurface(graph, start, goal, plannerConfig(name, 1.0));
    ASSERT_TRUE(result.solved()) << result.reason;
    expectOnWalkableSurface(graph, result);
    bool on_ramp = false;
    for (std::size_t i = 1; i < result.states.size(); ++i) {
      const Eigen::Vector3d& a = result.states[i - 1].location.point_W;
      const Eigen::Vector3d& b = result.states[i].location.point_W;
      if (a.x() > 21 && a.x() < 39 && a.z() > 0.1 && a.z() < 2.9) on_ramp = true;
      // No jumps: a piece climbs at most as steeply as the ramp.
      const double horizontal = (b - a).head<2>().norm();
      EXPECT_LE(std::abs(b.z() - a.z()), horizontal * 3.0 / 20.0 + 1e-6) << "piece " << i << " jumps";
    }
    EXPECT_TRUE(on_ramp);
    // Out to the ramp's far end and back: at least 2 * (40 - 6) minus the ramp's width.
    EXPECT_GT(result.length_m, 60.0);
    EXPECT_LE(baseline.cost, result.cost * 1.01) << "graph " << baseline.cost << " planner " << result.cost;
  }
}

/// Between the floors on several seeds, with the roadmap planners too. LazyPRM* weighs its edges
/// before it validates them: with an infinite weight for a motion the walk does not complete (the
/// straight edge from floor to floor), it found start and goal joined and threw "Could not find
/// solution path" at once. Whatever the simplifier returns, the path walks the walkable surface
/// piece by piece (OMPL's shortcuts keep parts of a validated piece unchecked).
TEST_F(SurfacePlannerTest, RoadmapPlannersBetweenFloorsOnEverySeed) {
  const FaceGraph graph(test::twoLevelMap(), walkability());
  for (const std::string& name : {std::string("lazyprmstar"), std::string("prmstar")}) {
    for (std::uint32_t seed = 1; seed <= 6; ++seed) {
      SCOPED_TRACE(name + ", seed " + std::to_string(seed));
      PlannerConfig config = plannerConfig(name, 0.2);
      config.seed = seed;
      seedOmpl(seed);
      const PlanResult result = planOnSurface(graph, {6, 7, 0}, {6, 7, 3}, config);
      ASSERT_TRUE(result.solved()) << result.reason;
      expectOnWalkableSurface(graph, result);
      EXPECT_GT(result.length_m, 60.0);
    }
  }
}

TEST_F(SurfacePlannerTest, APlannerResumedInShortRoundsReturnsAValidPath) {
  const FaceGraph graph(test::twoLevelMap(), walkability());
  // A 10 ms budget is usually too short for a path between the floors (69 m over the ramp): the
  // planner resumes its tree or roadmap in 10 ms rounds, and the path it ends with is as valid
  // as one found in a single round.
  for (const std::string& name : {std::string("bitstar"), std::string("prmstar"), std::string("aitstar")}) {
    SCOPED_TRACE(name);
    const PlanResult resumed = planOnSurface(graph, {6, 7, 0}, {6, 7, 3}, plannerConfig(name, 0.01));
    ASSERT_TRUE(resumed.solved()) << resumed.reason;
    expectOnWalkableSurface(graph, resumed);
    EXPECT_GT(resumed.length_m, 60.0);
  }
}

TEST_F(SurfacePlannerTest, ObstacleTopAndUnknownRegionAreReportedUnreachable) {
  const FaceGraph graph(test::twoLevelMap(), walkability());
  const PlannerConfig config = plannerConfig("rrtstar", 0.5);
  const PlanResult on_box = planOnSurface(graph, {6, 7, 0}, {11, 2, 1}, config);
  EXPECT_EQ(on_box.status, PlanStatus::kUnreachable) << on_box.reason;
  EXPECT_FALSE(on_box.reason.empty());
  const PlanResult unknown = planOnSurface(graph, {6, 7, 0}, {3, 2, 0}, config);
  EXPECT_EQ(unknown.status, PlanStatus::kNoGoal) << unknown.reason;
  const PlanResult far_away = planOnSurface(graph, {6, 7, 10}, {15, 7, 0}, config);
  EXPECT_EQ(far_away.status, PlanStatus::kNoStart);
  EXPECT_EQ(planOnFaceGraph(graph, {6, 7, 0}, {11, 2, 1}, config).status, PlanStatus::kUnreachable);
}

TEST_F(SurfacePlannerTest, AllowUnknownCrossesTheUnknownStripButNeverALethalFace) {
  const Eigen::Vector3d start(3, 2, 0), goal(17, 2, 0);
  const PlannerConfig config = plannerConfig("bitstar", 0.5);
  // Without allow_unknown the strip cuts the floor in two.
  const FaceGraph closed(test::unknownGapMap(), walkability());
  EXPECT_EQ(planOnFaceGraph(closed, start, goal, config).status, PlanStatus::kUnreachable);
  EXPECT_EQ(planOnSurface(closed, start, goal, config).status, PlanStatus::kUnreachable);

  WalkabilityConfig allow = walkability();
  allow.allow_unknown = true;
  const FaceGraph open(test::unknownGapMap(), allow);
  const double free_multiplier = 1 + 4.0 * 0.2, unknown_multiplier = 1 + 4.0 * allow.unknown_cost;
  for (const std::string& name : {std::string("graph"), std::string("bitstar"), std::string("rrtstar")}) {
    SCOPED_TRACE(name);
    const PlanResult result = name == "graph" ? planOnFaceGraph(open, start, goal, config)
                                              : planOnSurface(open, start, goal, plannerConfig(name, 0.5));
    ASSERT_TRUE(result.solved()) << result.reason;
    ASSERT_GE(result.states.size(), 2u);
    for (std::size_t i = 0; i < result.states.size(); ++i) {
      const std::uint32_t face = result.states[i].location.face;
      EXPECT_TRUE(open.walkable(face)) << "state " << i;
      EXPECT_NE(open.layers(face).face_class, FaceClass::kLethal) << "state " << i;
      if (i == 0) continue;
      // The truth's obstacle is the lethal part of the strip (x 9.5..10.5, y < 6).
      EXPECT_FALSE(segmentMeetsRectangle(result.states[i - 1].location.point_W, result.states[i].location.point_W, 9.5,
                                         10.5, 0, 6))
          << "piece " << i << " crosses the lethal part of the strip";
    }
    // It crosses the 1 m strip over unknown faces, and pays the documented cost for it.
    EXPECT_GE(result.unknown_length_m, 1.0 - 1e-6);
    EXPECT_LT(result.unknown_length_m, result.length_m);
    EXPECT_NEAR(result.cost,
                free_multiplier * (result.length_m - result.unknown_length_m) + unknown_multiplier * result.unknown_length_m,
                1e-6 * result.cost);
  }
  // A lethal strip stays closed, unknown faces allowed or not.
  const FaceGraph lethal(test::unknownGapMap(true), allow);
  EXPECT_EQ(planOnFaceGraph(lethal, start, goal, config).status, PlanStatus::kUnreachable);
  EXPECT_EQ(planOnSurface(lethal, start, goal, config).status, PlanStatus::kUnreachable);
}

TEST_F(SurfacePlannerTest, StartAndGoalInTheSameFace) {
  const FaceGraph graph(test::wallWithGapMap(), walkability());
  const Eigen::Vector3d start(3.3, 2.1, 0), goal(3.4, 2.15, 0);
  ASSERT_EQ(graph.snap(start, 0.1)->face, graph.snap(goal, 0.1)->face);
  const PlanResult result = planOnSurface(graph, start, goal, plannerConfig("rrtstar", 0.3));
  ASSERT_TRUE(result.solved()) << result.reason;
  EXPECT_NEAR(result.length_m, (goal - start).norm(), 1e-9);
  EXPECT_NEAR(result.cost, (goal - start).norm() * (1 + 4.0 * 0.2), 1e-6);
}

TEST(FaceGraphTest, WalkStopsAtLethalFacesAndBoundaries) {
  const FaceGraph graph(test::wallWithGapMap(), walkability());
  const SurfaceLocation a = *graph.snap({3, 2, 0}, 0.1);
  const SurfaceLocation b = *graph.snap({17, 2, 0}, 0.1);
  EXPECT_EQ(graph.walk(a, b, true).stop, WalkStop::kBlocked);
  const SurfaceWalk free_walk = graph.walk(a, b, false);
  ASSERT_TRUE(free_walk.reached());
  EXPECT_NEAR(free_walk.length_m, 14.0, 1e-6);
  // Out of the map: the walk meets the boundary edge.
  const SurfaceWalk out = graph.walk(a, SurfaceLocation{FaceGraph::kNoFace, {3, -5, 0}}, false);
  EXPECT_EQ(out.stop, WalkStop::kBoundary);
  EXPECT_NEAR(out.points.back().point_W.y(), 0.0, 1e-9);
}

TEST(FaceGraphTest, OneComponentPerFloorAndTheBoxTop) {
  const FaceGraph graph(test::twoLevelMap(), walkability());
  // Floors + ramp + landing are one component (their area: 200 + 80 + 40 + 240 m^2 less the box
  // footprint, the unknown patch and the faces within 0.3 m of the box); the box top is apart.
  std::uint32_t largest = 0;
  for (std::uint32_t c = 0; c < graph.componentCount(); ++c) {
    if (graph.componentArea(c) > graph.componentArea(largest)) largest = c;
  }
  EXPECT_GT(graph.componentArea(largest), 540.0);
  EXPECT_LT(graph.componentArea(largest), 552.0);
  const auto ground = graph.snap({6, 7, 0}, 0.1), upper = graph.snap({6, 7, 3}, 0.1), box = graph.snap({11, 2, 1}, 0.1);
  ASSERT_TRUE(ground && upper && box);
  EXPECT_EQ(graph.component(ground->face), largest);
  EXPECT_EQ(graph.component(ground->face), graph.component(upper->face));
  EXPECT_NE(graph.component(ground->face), graph.component(box->face));
  // Snapping does not fall through to the other floor.
  EXPECT_NEAR(graph.snap({6, 7, 2.9}, 0.5)->point_W.z(), 3.0, 1e-12);
}

TEST(FaceGraphTest, HeadingFitsNeedsBothNeighbouringJudgedHeadings) {
  traversability::LayeredMesh map = test::wallWithGapMap();
  for (auto& layers : map.layers) layers.heading_fits = 0b11;  // 0 and 22.5 deg of 8 judged headings
  WalkabilityConfig config = walkability();
  config.heading_count = 8;
  const FaceGraph graph(map, config);
  const std::uint32_t f = graph.snap({3, 2, 0}, 0.1)->face;
  const auto along = [](double deg) {
    return Eigen::Vector3d(std::cos(deg * M_PI / 180), std::sin(deg * M_PI / 180), 0.5);
  };
  EXPECT_TRUE(graph.headingFits(f, along(10)));    // between 0 and 22.5: both fit
  EXPECT_TRUE(graph.headingFits(f, along(190)));   // the same heading driven the other way
  EXPECT_TRUE(graph.headingFits(f, along(22.5)));  // on a judged heading that fits
  EXPECT_FALSE(graph.headingFits(f, along(30)));   // between 22.5 (fits) and 45 (does not)
  EXPECT_FALSE(graph.headingFits(f, along(-10)));  // between 157.5 (does not) and 180
  EXPECT_TRUE(graph.headingFits(f, Eigen::Vector3d(0, 0, 1)));  // no horizontal travel
  config.heading_count = 0;                                      // a disc: no heading test
  EXPECT_TRUE(FaceGraph(map, config).headingFits(f, along(30)));
  map.layers[f].heading_fits = 0;  // no judged heading fits, free all the same (driven ground)
  config.heading_count = 8;
  EXPECT_TRUE(FaceGraph(map, config).headingFits(f, along(30)));
  config.heading_count = 33;
  EXPECT_THROW(FaceGraph(map, config), std::invalid_argument);
}

TEST(FaceGraphTest, ShortestPathCrossesABandOnlyAtHeadingsThatFit) {
  // A free 20 x 10 m floor; across x in [8, 12] a band where the footprint fits only at headings
  // within 22.5 deg of the x axis. The straight way from (2, 1) to (18, 9) runs at 26.6 deg.
  test::LayeredMeshBuilder builder;
  builder.sheet(0, 20, 0, 10, 0.5, [](double, double) { return 0.0; },
                [](const Eigen::Vector3d&) { return std::optional<FaceClass>(FaceClass::kFree); });
  traversability::LayeredMesh map = builder.finish();
  const auto in_band = [&map](std::uint32_t f) {
    const auto& t = map.mesh.faces[f];
    const double x = (map.mesh.vertices[t[0]].x() + map.mesh.vertices[t[1]].x() + map.mesh.vertices[t[2]].x()) / 3;
    return x > 8 && x < 12;
  };
  for (std::uint32_t f = 0; f < map.layers.size(); ++f) map.layers[f].heading_fits = in_band(f) ? 0b10000011 : 0xFF;
  WalkabilityConfig config = walkability();
  config.heading_count = 8;
  const FaceGraph graph(map, config);
  config.heading_count = 0;
  const FaceGraph any_heading(map, config);
  const auto path = [](const FaceGraph& g) {
    return g.shortestPath(*g.snap({2, 1, 0}, 0.1), *g.snap({18, 9, 0}, 0.1));
  };
  const GraphPath kept = path(graph), free = path(any_heading);
  ASSERT_TRUE(kept.found && free.found);
  int band_pieces = 0;
  double steepest_in_band = 0;
  for (std::size_t i = 0; i < kept.faces.size(); ++i) {
    if (!in_band(kept.faces[i])) continue;
    const Eigen::Vector3d d = kept.points_W[i + 1] - kept.points_W[i];
    steepest_in_band = std::max(steepest_in_band, std::abs(std::atan(d.y() / d.x())) * 180 / M_PI);
    ++band_pieces;
  }
  EXPECT_GT(band_pieces, 0);
  EXPECT_LE(steepest_in_band, 22.5 + 1e-6);
  EXPECT_GT(kept.length_m, free.length_m + 0.01);  // it bends to cross the band
  EXPECT_NEAR(free.length_m, std::hypot(16.0, 8.0), 0.05);
  // The OMPL planners' motions: a straight walk at 26.6 deg is blocked in the band, at 0 deg not.
  EXPECT_EQ(graph.walk(*graph.snap({2, 1, 0}, 0.1), *graph.snap({18, 9, 0}, 0.1), true).stop, WalkStop::kBlocked);
  EXPECT_TRUE(graph.walk(*graph.snap({2, 5.1, 0}, 0.1), *graph.snap({18, 5.1, 0}, 0.1), true).reached());
  EXPECT_TRUE(any_heading.walk(*any_heading.snap({2, 1, 0}, 0.1), *any_heading.snap({18, 9, 0}, 0.1), true).reached());
}

TEST(PlannerConfigTest, ValidateListsEveryProblem) {
  PlannerConfig config;
  config.planner = "dijkstra";
  config.time_budget_s = 0;
  config.seed = 0;
  config.time_cap_s = -1;
  try {
    config.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("planner"), std::string::npos);
    EXPECT_NE(text.find("time_budget_s"), std::string::npos);
    EXPECT_NE(text.find("seed"), std::string::npos);
    EXPECT_NE(text.find("time_cap_s"), std::string::npos);
  }
  WalkabilityConfig walkability_config;
  walkability_config.unknown_cost = 1.5;
  EXPECT_THROW(walkability_config.validate(), std::invalid_argument);
  config = PlannerConfig{};
  for (const char* name : {"RRT*", "informed RRT*", "PRM*", "LazyPRM*", "BIT*", "AIT*"}) {
    config.planner = name;
    EXPECT_NO_THROW(config.validate()) << name;
  }
}

}  // namespace
}  // namespace terramesh::planning
