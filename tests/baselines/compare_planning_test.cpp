// terramesh compare's planning column: start-goal pairs on the observed, connected part of a
// labelled truth, and per-map outcomes with their reasons (apps/terramesh/compare_planning.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "compare_planning.h"

namespace terramesh::cli {
namespace {

/// A horizontal rectangle [x0, x1] x [y0, y1] at height z, split into a grid of `n` x `n` cells
/// (two triangles each, facing up), appended to `mesh` with `label` per face.
void addQuad(datasets::LabeledMesh& mesh, double x0, double x1, double y0, double y1, double z, int n,
             datasets::SurfaceLabel label) {
  const auto base = static_cast<std::uint32_t>(mesh.mesh.vertices.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.mesh.vertices.emplace_back(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n, z);
  }
  auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.mesh.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.mesh.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      for (int k = 0; k < 2; ++k) {
        mesh.labels.push_back(label);
        mesh.slope_deg.push_back(label == datasets::SurfaceLabel::kWall ? 90.0f : 0.0f);
      }
    }
  }
}

/// A vertical wall x = x, y in [y0, y1], z in [0, height].
void addWall(datasets::LabeledMesh& mesh, double x, double y0, double y1, double height) {
  const auto base = static_cast<std::uint32_t>(mesh.mesh.vertices.size());
  mesh.mesh.vertices.insert(mesh.mesh.vertices.end(), {{x, y0, 0}, {x, y1, 0}, {x, y1, height}, {x, y0, height}});
  mesh.mesh.faces.push_back({base, base + 1, base + 2});
  mesh.mesh.faces.push_back({base, base + 2, base + 3});
  for (int k = 0; k < 2; ++k) {
    mesh.labels.push_back(datasets::SurfaceLabel::kWall);
    mesh.slope_deg.push_back(90.0f);
  }
}

/// Road A [0, 20] x [0, 4] seen by two cameras; road B [30, 40] x [-10, 14], three times A's area,
/// hidden from them by a wall at x = 25: without the observation filter the pairs would be on B.
struct Scene {
  datasets::LabeledMesh truth;
  std::vector<Eigen::Vector3d> cameras{{4, 2, 1.5}, {8, 2, 1.5}};
  Scene() {
    addQuad(truth, 0, 20, 0, 4, 0, 20, datasets::SurfaceLabel::kRoad);
    addQuad(truth, 30, 40, -10, 14, 0, 20, datasets::SurfaceLabel::kRoad);
    addWall(truth, 25, -20, 20, 6);
  }
};

evaluation::GroundTruthTraversability labelled(const Scene& scene) {
  evaluation::RobotLimits robot;
  robot.footprint_radius_m = 0.2;
  return evaluation::labelTraversability(scene.truth, robot, Eigen::Vector3d::UnitZ(), {});
}

TEST(ComparePlanningTest, PairsLieOnTheObservedConnectedPartOnly) {
  const Scene scene;
  const auto labels = labelled(scene);
  const datasets::TriangleBvh bvh(scene.truth.mesh);
  TruthPairsConfig config;
  config.count = 8;
  config.min_distance_m = 6;
  const TruthPairs drawn = pairsOnObservedTruth(labels, bvh, scene.cameras, config);
  ASSERT_EQ(drawn.pairs.size(), 8u);
  EXPECT_LT(drawn.observed, drawn.samples) << "road B is hidden behind the wall";
  EXPECT_EQ(drawn.component_samples, drawn.observed) << "road A is one piece";
  for (const ComparePair& pair : drawn.pairs) {
    for (const Eigen::Vector3d& p : {pair.start_W, pair.goal_W}) {
      EXPECT_LE(p.x(), 20.0) << "an end on the unobserved road B: " << p.transpose();
      EXPECT_NEAR(p.z(), 0.0, 1e-9);
    }
    const double straight = (pair.goal_W - pair.start_W).norm();
    EXPECT_GE(straight, config.min_distance_m);
    // On an open flat road the shortest way is the straight line; the sample graph zig-zags a bit.
    EXPECT_GE(pair.truth_length_m, straight - 1e-9);
    EXPECT_LE(pair.truth_length_m, 1.1 * straight);
  }
  const TruthPairs again = pairsOnObservedTruth(labels, bvh, scene.cameras, config);
  ASSERT_EQ(again.pairs.size(), drawn.pairs.size());
  for (std::size_t i = 0; i < drawn.pairs.size(); ++i) EXPECT_EQ(again.pairs[i].start_W, drawn.pairs[i].start_W);
}

/// A map of road A alone: every face free, except a lethal strip across x in [lethal_x0, lethal_x1].
traversability::LayeredMesh roadMap(double lethal_x0, double lethal_x1) {
  datasets::LabeledMesh road;
  addQuad(road, 0, 20, 0, 4, 0, 40, datasets::SurfaceLabel::kRoad);
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
  const Scene scene;
  const datasets::TriangleBvh bvh(scene.truth.mesh);
  PathTruth truth{&scene.truth, &bvh, Eigen::Vector3d::UnitZ(), 20};
  planning::WalkabilityConfig walkability;
  walkability.min_lethal_distance_m = 0;
  const std::vector<ComparePair> pairs = {{{2, 2, 0}, {18, 2, 0}, 16.0},     // across the road
                                          {{2, 2, 0}, {35, 2, 0}, NAN}};     // goal on road B
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
