// terramesh compare's planning column: per-map outcomes on start-goal pairs and their reasons
// (apps/terramesh/compare_planning.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "compare_planning.h"
#include "pair_scene.h"

namespace terramesh::cli {
namespace {

/// A map of road A alone: every face free, except a lethal strip across x in [lethal_x0, lethal_x1].
traversability::LayeredMesh roadMap(double lethal_x0, double lethal_x1) {
  datasets::LabeledMesh road;
  test::addGrid(road, 0, 20, 0, 4, 0, 40, datasets::SurfaceLabel::kRoad);
  traversability::LayeredMesh map;
  map.mesh = road.mesh;
  map.layers.resize(map.mesh.faces.size());
  for (std::size_t f = 0; f < map.layers.size(); ++f) {
    const auto& t = map.mesh.faces[f];
    const double x = (map.mesh.vertices[t[0]].x() + map.mesh.vertices[t[1]].x() + map.mesh.vertices[t[2]].x()) / 3;
    const bool lethal = x > lethal_x0 && x < lethal_x1;
    map.layers[f].face_class = lethal ? traversability::FaceClass::kLethal : traversability::FaceClass::kFree;
    map.layers[f].cost = lethal ? 1.0f : 0.0f;
    map.layers[f].rays = 3;
  }
  return map;
}

TEST(ComparePlanningTest, OutcomesAndTheirReasons) {
  const test::PairScene scene;
  const datasets::TriangleBvh bvh(scene.truth.mesh);
  PathTruth truth{&scene.truth, &bvh, Eigen::Vector3d::UnitZ(), {}};
  truth.config.max_slope_deg = 20;
  planning::WalkabilityConfig walkability;
  walkability.min_lethal_distance_m = 0;
  const std::vector<evaluation::ComparePair> pairs = {{{2, 2, 0}, {18, 2, 0}, 16.0},  // across the road
                                                      {{2, 2, 0}, {35, 2, 0}, NAN}};  // goal on road B
  const PlanningOutcome open = planComparePairs(roadMap(100, 100), pairs, walkability, 0.5, truth);
  EXPECT_EQ(open.solved, 1u);
  EXPECT_EQ(open.no_start_or_goal, 1u);
  EXPECT_EQ(open.truth_checked, 1u);
  EXPECT_EQ(open.truth_valid, 1u);
  EXPECT_NEAR(open.mean_length_m, 16.0, 1e-3);
  EXPECT_NEAR(open.mean_length_ratio, 1.0, 1e-4);
  EXPECT_NEAR(open.walkable_area_m2, 80.0, 1e-6);
  EXPECT_EQ(open.walkable_components, 1u);
  EXPECT_EQ(open.statuses[1], "no_goal");

  const PlanningOutcome cut = planComparePairs(roadMap(9, 11), pairs, walkability, 0.5, truth);
  EXPECT_EQ(cut.solved, 0u);
  EXPECT_EQ(cut.unreachable, 1u);
  EXPECT_EQ(cut.walkable_components, 2u);
  EXPECT_NE(cut.summary().find("different walkable components"), std::string::npos) << cut.summary();
}

}  // namespace
}  // namespace terramesh::cli
