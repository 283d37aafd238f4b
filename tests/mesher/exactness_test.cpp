// Moving points, removing points and correcting poses give exactly the weights a fresh run on the
// final data gives: the incremental trace/untrace/retrace bookkeeping loses nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <unordered_set>

#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

AxisAlignedBox sceneBounds() { return {Eigen::Vector3d(-11, -11, -1), Eigen::Vector3d(11, 11, 4)}; }

/// A fixed grid, so that both runs triangulate the same Steiner points.
MesherConfig fixedGridConfig(MesherMode mode) {
  MesherConfig config = MesherConfig::forMode(mode);
  config.point_policy = PointPolicy::kExactMoves;  // the baselines' default keeps points fixed
  config.steiner_step_m = 4.0;
  config.incremental_steiner_grid = false;
  config.fixed_grid_bounds_W = sceneBounds();
  return config;
}

UpdateStats runAll(Mesher& mesher, const std::vector<Keyframe>& keyframes, bool check) {
  UpdateStats totals;
  for (const Keyframe& keyframe : keyframes) {
    totals += mesher.integrateKeyframe(keyframe);
    if (check) {
      const InvariantReport report = mesher.checkInvariants();
      EXPECT_TRUE(report.ok()) << "keyframe " << keyframe.id.value << ": " << report.summary();
    }
  }
  return totals;
}

/// Same cells, same weights, same crossing counts.
void expectSameVisibility(const Mesher& a, const Mesher& b) {
  const std::vector<CellVisibility> cells_a = a.cellVisibility();
  const std::vector<CellVisibility> cells_b = b.cellVisibility();
  ASSERT_EQ(cells_a.size(), cells_b.size()) << "the triangulations differ";
  std::size_t different_cells = 0, different_weights = 0, free_cells = 0;
  for (std::size_t i = 0; i < cells_a.size(); ++i) {
    if (cells_a[i].vertices_W != cells_b[i].vertices_W) {
      ++different_cells;
      continue;
    }
    if (cells_a[i].weight != cells_b[i].weight || cells_a[i].crossings != cells_b[i].crossings) {
      ++different_weights;
    }
    free_cells += cells_a[i].crossings > 0;
  }
  EXPECT_EQ(different_cells, 0u);
  EXPECT_EQ(different_weights, 0u);
  EXPECT_GT(free_cells, 100u) << "the comparison must cover cells that rays cross";
}

class Exactness : public ::testing::TestWithParam<MesherMode> {};

TEST_P(Exactness, MovingPointsGiveTheWeightsOfAFreshRunOnTheFinalPositions) {
  test::SceneOptions options;
  const auto scene = test::boxRoomScene(options);
  const auto moving = test::withMovingEstimates(scene.keyframes, 0.08, 11);
  const auto settled = test::withFinalEstimates(moving);

  Mesher incremental(fixedGridConfig(GetParam()));
  const UpdateStats a = runAll(incremental, moving, true);
  Mesher fresh(fixedGridConfig(GetParam()));
  const UpdateStats b = runAll(fresh, settled, false);

  ASSERT_GT(a.moved_points, 500u) << "the stream must actually move points";
  ASSERT_EQ(b.moved_points, 0u);
  ASSERT_EQ(a.dropped_points + a.deferred_points + a.duplicate_points, 0u);
  ASSERT_EQ(b.dropped_points + b.deferred_points + b.duplicate_points, 0u);
  expectSameVisibility(incremental, fresh);
}

TEST_P(Exactness, RemovingPointsGivesTheWeightsOfAFreshRunWithoutThem) {
  test::SceneOptions options;
  const auto scene = test::boxRoomScene(options);
  std::unordered_set<std::uint64_t> culled;
  std::mt19937 rng(5);
  for (const auto& observation : scene.keyframes[3].observations) {
    if (rng() % 3 == 0) culled.insert(observation.point.value);
  }
  std::vector<Keyframe> without = scene.keyframes;
  for (Keyframe& keyframe : without) {
    auto& obs = keyframe.observations;
    obs.erase(std::remove_if(obs.begin(), obs.end(),
                             [&](const PointObservation& o) { return culled.count(o.point.value) != 0; }),
              obs.end());
  }

  Mesher incremental(fixedGridConfig(GetParam()));
  runAll(incremental, scene.keyframes, false);
  std::vector<PointId> ids;
  for (std::uint64_t id : culled) ids.push_back({id});
  const UpdateStats removal = incremental.removePoints(ids);
  const InvariantReport report = incremental.checkInvariants();
  ASSERT_TRUE(report.ok()) << report.summary();
  ASSERT_EQ(removal.removed_points, culled.size());
  ASSERT_EQ(removal.deferred_points, 0u);
  EXPECT_GT(removal.rays_untraced, culled.size());

  Mesher fresh(fixedGridConfig(GetParam()));
  const UpdateStats b = runAll(fresh, without, false);
  ASSERT_EQ(b.dropped_points, 0u);
  expectSameVisibility(incremental, fresh);
}

TEST_P(Exactness, CorrectingAKeyframePoseGivesTheWeightsOfAFreshRun) {
  test::SceneOptions options;
  const auto scene = test::boxRoomScene(options);
  std::vector<Keyframe> corrected = scene.keyframes;
  Keyframe& target = corrected[6];
  target.position_W_C += Eigen::Vector3d(0.31, -0.17, 0.05);

  Mesher incremental(fixedGridConfig(GetParam()));
  runAll(incremental, scene.keyframes, false);
  const UpdateStats update = incremental.integrateKeyframe(target);  // re-sent with a new pose
  const InvariantReport report = incremental.checkInvariants();
  ASSERT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(update.rays_untraced, target.observations.size());
  EXPECT_GE(update.rays_traced, target.observations.size());

  Mesher fresh(fixedGridConfig(GetParam()));
  runAll(fresh, corrected, false);
  expectSameVisibility(incremental, fresh);
}

TEST_P(Exactness, InvariantsHoldThroughMovesRemovalsCorrectionsAndKeyframeRemovals) {
  test::SceneOptions options;
  options.keyframes = 32;
  const auto scene = test::corridorScene(options);
  const auto moving = test::withMovingEstimates(scene.keyframes, 0.15, 3);
  MesherConfig config = MesherConfig::forMode(GetParam());
  config.point_policy = PointPolicy::kExactMoves;  // moves in every mode, not only the proposed
  config.steiner_step_m = 4.0;
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = sceneBounds();
  Mesher mesher(config);
  std::mt19937 rng(9);
  auto check = [&mesher](const std::string& when) {
    const InvariantReport report = mesher.checkInvariants();
    ASSERT_TRUE(report.ok()) << when << ": " << report.summary();
  };
  for (std::size_t k = 0; k < moving.size(); ++k) {
    mesher.integrateKeyframe(moving[k]);
    check("keyframe " + std::to_string(k));
    if (k % 5 == 4) {  // SLAM culls a few points
      std::vector<PointId> culled;
      for (const auto& o : moving[k].observations) {
        if (rng() % 10 == 0) culled.push_back(o.point);
      }
      mesher.removePoints(culled);
      check("removal after keyframe " + std::to_string(k));
    }
    if (k % 7 == 6) {  // a loop closure corrects an earlier keyframe
      Keyframe earlier = moving[k - 3];
      earlier.position_W_C += Eigen::Vector3d(0.2, 0.1, 0.0);
      mesher.integrateKeyframe(earlier);
      check("correction after keyframe " + std::to_string(k));
    }
    if (k % 11 == 10) {
      mesher.removeKeyframe(moving[k - 8].id);
      check("keyframe removal after keyframe " + std::to_string(k));
    }
  }
  EXPECT_TRUE(analyzeTopology(mesher.extractMesh()).isClosedManifold());
}

INSTANTIATE_TEST_SUITE_P(AllModes, Exactness,
                         ::testing::Values(MesherMode::kProposed, MesherMode::kLitvinov13,
                                           MesherMode::kRomanoni15),
                         [](const auto& param_info) { return std::string(toString(param_info.param)); });

}  // namespace
}  // namespace terramesh::mesher
