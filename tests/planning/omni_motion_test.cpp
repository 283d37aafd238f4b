// A body that keeps its own heading (MotionModel::kOmni) against one that faces its travel, on a
// floor crossed by a band where the footprint fits only across the way through it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "planning/face_graph.h"
#include "planning/surface_planner.h"
#include "planning_fixtures.h"

namespace terramesh::planning {
namespace {

using traversability::FaceClass;

Eigen::Vector3d along(double deg) { return {std::cos(deg * M_PI / 180), std::sin(deg * M_PI / 180), 0.0}; }

double radians(double deg) { return deg * M_PI / 180; }

/// A free 20 x 10 m floor; across x in [8, 12] a band where the footprint fits only at the judged
/// headings of `band_bits` (8 headings, bit k at k x 22.5 deg), everywhere else at every heading.
traversability::LayeredMesh bandMap(std::uint32_t band_bits) {
  test::LayeredMeshBuilder builder;
  builder.sheet(0, 20, 0, 10, 0.5, [](double, double) { return 0.0; },
                [](const Eigen::Vector3d&) { return std::optional<FaceClass>(FaceClass::kFree); });
  traversability::LayeredMesh map = builder.finish();
  for (std::uint32_t f = 0; f < map.layers.size(); ++f) {
    const auto& t = map.mesh.faces[f];
    const double x = (map.mesh.vertices[t[0]].x() + map.mesh.vertices[t[1]].x() + map.mesh.vertices[t[2]].x()) / 3;
    map.layers[f].heading_fits = x > 8 && x < 12 ? band_bits : 0xFF;
  }
  return map;
}

WalkabilityConfig headings(bool omni) {
  WalkabilityConfig config;
  config.min_lethal_distance_m = 0.3;
  config.heading_count = 8;
  config.omni = omni;
  return config;
}

bool inBand(const Eigen::Vector3d& p) { return p.x() > 8 + 1e-6 && p.x() < 12 - 1e-6; }

TEST(OmniMotionTest, TurnFitsEveryJudgedHeadingTheTurnPasses) {
  const FaceGraph graph(bandMap(0b00000111), headings(true));  // 0, 22.5 and 45 deg fit in the band
  const std::uint32_t f = graph.snap({10, 5, 0}, 0.1)->face;
  EXPECT_TRUE(graph.turnFits(f, along(0), radians(45)));
  EXPECT_TRUE(graph.turnFits(f, along(180), radians(45)));   // the same rectangle, reversed
  EXPECT_FALSE(graph.turnFits(f, along(0), radians(60)));    // passes 67.5
  EXPECT_FALSE(graph.turnFits(f, along(0), radians(-10)));   // passes 157.5
  EXPECT_FALSE(graph.turnFits(f, along(10), radians(170)));  // the long way round passes them all
  EXPECT_EQ(graph.turnFits(f, along(10), 0.0), graph.headingFits(f, along(10)));
  EXPECT_EQ(graph.turnFits(f, along(30), 0.0), graph.headingFits(f, along(30)));
  EXPECT_TRUE(graph.judgedHeadingFits(f, 2));
  EXPECT_FALSE(graph.judgedHeadingFits(f, 3));
  EXPECT_NEAR(graph.judgedHeading(2).dot(along(45)), 1.0, 1e-12);
}

TEST(OmniMotionTest, GraphPathWalksSidewaysWhereOnlyAHeadingAcrossTheWayFits) {
  // In the band the footprint fits only at 90 deg, across the way from x = 2 to x = 18: a body
  // facing its travel cannot cross it, one that keeps its heading walks through sideways.
  const traversability::LayeredMesh map = bandMap(0b00010000);
  const FaceGraph facing(map, headings(false)), omni(map, headings(true));
  const auto path = [](const FaceGraph& g) {
    return g.shortestPath(*g.snap({2, 5, 0}, 0.1), *g.snap({18, 5, 0}, 0.1));
  };
  EXPECT_FALSE(path(facing).found);
  const GraphPath walked = path(omni);
  ASSERT_TRUE(walked.found);
  ASSERT_EQ(walked.body_headings_W.size(), walked.points_W.size());
  EXPECT_TRUE(path(facing).body_headings_W.empty());
  int band_pieces = 0;
  for (std::size_t i = 0; i + 1 < walked.points_W.size(); ++i) {
    const Eigen::Vector3d& a = walked.body_headings_W[i];
    const Eigen::Vector3d& b = walked.body_headings_W[i + 1];
    // Every piece's face fits the headings at both its ends, and the body turns at most one
    // judged heading (22.5 deg) from point to point.
    EXPECT_TRUE(omni.headingFits(walked.faces[i], a) && omni.headingFits(walked.faces[i], b)) << "piece " << i;
    EXPECT_GE(std::abs(a.dot(b)), std::cos(radians(22.5)) - 1e-9) << "piece " << i;
    if (inBand(0.5 * (walked.points_W[i] + walked.points_W[i + 1]))) {
      ++band_pieces;
      EXPECT_NEAR(std::abs(a.y()), 1.0, 1e-9) << "piece " << i << " in the band faces across the way";
    }
  }
  EXPECT_GT(band_pieces, 0);
  // Straight through, the start's heading being free; the cost is the length's (multiplier
  // 1 + 4 x 0.2) plus 0.1 m per radian the body turns.
  double turned_rad = 0;
  for (std::size_t i = 1; i < walked.body_headings_W.size(); ++i) {
    turned_rad += std::acos(std::min(1.0, std::abs(walked.body_headings_W[i].dot(walked.body_headings_W[i - 1]))));
  }
  EXPECT_NEAR(walked.length_m, 16.0, 0.05);
  EXPECT_NEAR(walked.cost, walked.length_m * (1 + 4 * 0.2) + 0.1 * turned_rad, 1e-6);
}

TEST(OmniMotionTest, PlannersReportTheBodysHeadingAsTheYaw) {
  // 67.5, 90 and 112.5 deg fit in the band: OMPL's states sample yaws between them.
  const traversability::LayeredMesh map = bandMap(0b00111000);
  const FaceGraph omni(map, headings(true));
  setOmplLogging(false);
  for (const char* name : {"graph", "rrtstar"}) {
    PlannerConfig config;
    config.planner = std::string(name) == "graph" ? "bitstar" : name;
    config.time_budget_s = 0.5;
    config.time_cap_s = 60;
    config.seed = 3;
    const PlanResult result = std::string(name) == "graph" ? planOnFaceGraph(omni, {2, 5, 0}, {18, 5, 0}, config)
                                                           : planOnSurface(omni, {2, 5, 0}, {18, 5, 0}, config);
    ASSERT_TRUE(result.solved()) << name << ": " << result.reason;
    int band_states = 0;
    for (std::size_t i = 0; i < result.states.size(); ++i) {
      const PathState& state = result.states[i];
      const Eigen::Vector3d body = along(state.yaw_rad * 180 / M_PI);
      EXPECT_TRUE(omni.headingFits(state.location.face, body)) << name << " state " << i;
      if (!inBand(state.location.point_W)) continue;
      ++band_states;
      // Within 22.5 deg of across the way, whichever way the body walks.
      EXPECT_GE(std::abs(body.y()), std::cos(radians(22.5)) - 1e-9) << name << " state " << i;
    }
    EXPECT_GT(band_states, 0) << name;
  }
}

TEST(OmniMotionTest, SamplingPlannersFindTheOneHeadingThatFits) {
  // Only 90 deg fits in the band: a uniformly drawn yaw fits there with probability 0, so the
  // sampler also draws the headings a face fits.
  const FaceGraph omni(bandMap(0b00010000), headings(true));
  setOmplLogging(false);
  for (const char* name : {"rrtstar", "bitstar"}) {
    PlannerConfig config;
    config.planner = name;
    config.time_budget_s = 0.5;
    config.time_cap_s = 60;
    config.seed = 5;
    const PlanResult result = planOnSurface(omni, {2, 5, 0}, {18, 5, 0}, config);
    ASSERT_TRUE(result.solved()) << name << ": " << result.reason;
    for (std::size_t i = 0; i < result.states.size(); ++i) {
      const PathState& state = result.states[i];
      EXPECT_TRUE(omni.headingFits(state.location.face, along(state.yaw_rad * 180 / M_PI))) << name << " state " << i;
    }
  }
}

}  // namespace
}  // namespace terramesh::planning
