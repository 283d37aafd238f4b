// The mode as the single source of the mode-dependent settings, the baselines' point policy, and
// each ablation switch (`--disable`) having the effect it names.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>

#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

std::vector<Keyframe> movingRoom() {
  test::SceneOptions options;
  return test::withMovingEstimates(test::boxRoomScene(options).keyframes, 0.08, 11);
}

struct ModeRun {
  std::vector<UpdateStats> updates;
  UpdateStats totals;
  std::vector<std::size_t> outside_before;  ///< |O| before each update
  TriangleMesh mesh;
  std::vector<CellVisibility> cells;
};

ModeRun runStream(MesherConfig config, const std::vector<Keyframe>& keyframes) {
  config.steiner_step_m = 4.0;
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = test::keyframeBounds(keyframes);
  Mesher mesher(config);
  ModeRun result;
  for (const Keyframe& keyframe : keyframes) {
    result.outside_before.push_back(mesher.size().outside_cells);
    result.updates.push_back(mesher.integrateKeyframe(keyframe));
    result.totals += result.updates.back();
  }
  const InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
  result.mesh = mesher.extractMesh();
  result.cells = mesher.cellVisibility();
  return result;
}

void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_GT(a.faces.size(), 100u);
}

/// Same triangulation, same weights and crossing counts.
void expectSameCells(const std::vector<CellVisibility>& a, const std::vector<CellVisibility>& b) {
  ASSERT_EQ(a.size(), b.size());
  std::size_t different = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    different += a[i].vertices_W != b[i].vertices_W || a[i].weight != b[i].weight ||
                 a[i].crossings != b[i].crossings;
  }
  EXPECT_EQ(different, 0u);
}

// ---- The mode ------------------------------------------------------------------------------

auto modeSettings(const MesherConfig& c) {
  return std::make_tuple(c.weight_crossed, c.weight_neighbour, c.weight_second_neighbour, c.spread_cap,
                         c.free_threshold, c.point_policy, c.incremental_steiner_grid,
                         c.local_enclosing_set, c.boundary_hash, c.next_cell_cache, c.ray_scheduler,
                         c.edge_growing_pass);
}

TEST(MesherMode, SetModeSetsEverySettingOfTheModeOverridingEarlierAssignments) {
  EXPECT_EQ(MesherConfig().mode(), MesherMode::kProposed);
  EXPECT_EQ(modeSettings(MesherConfig()), modeSettings(MesherConfig::forMode(MesherMode::kProposed)));
  for (MesherMode mode : {MesherMode::kProposed, MesherMode::kLitvinov13, MesherMode::kRomanoni15}) {
    MesherConfig config;
    config.weight_crossed = 77;
    config.spread_cap = 5;
    config.edge_growing_pass = !config.edge_growing_pass;
    config.point_policy = PointPolicy::kFixedPosition;
    config.min_views = 3;  // not mode-dependent: kept
    config.setMode(mode);
    EXPECT_EQ(config.mode(), mode);
    EXPECT_EQ(modeSettings(config), modeSettings(MesherConfig::forMode(mode))) << toString(mode);
    EXPECT_EQ(config.min_views, 3);
  }
  // What each mode stands for (docs/algorithms.md).
  const MesherConfig litvinov = MesherConfig::forMode(MesherMode::kLitvinov13);
  EXPECT_EQ(std::make_tuple(litvinov.weight_crossed, litvinov.weight_neighbour,
                            litvinov.weight_second_neighbour, litvinov.free_threshold),
            std::make_tuple(1.0, 0.0, 0.0, 0.0));
  const MesherConfig romanoni = MesherConfig::forMode(MesherMode::kRomanoni15);
  EXPECT_EQ(romanoni.spread_cap, 0);
  EXPECT_EQ(romanoni.point_policy, PointPolicy::kFixedPosition);
  EXPECT_EQ(MesherConfig().point_policy, PointPolicy::kExactMoves);
  EXPECT_EQ(MesherConfig().spread_cap, 1);
}

TEST(MesherMode, SettingTheModeAloneChangesWhatTheMesherRuns) {
  const std::vector<Keyframe> keyframes = movingRoom();
  MesherConfig litvinov;
  litvinov.setMode(MesherMode::kLitvinov13);
  const ModeRun baseline = runStream(litvinov, keyframes);
  const ModeRun proposed = runStream(MesherConfig(), keyframes);

  // litvinov13: a cell's weight is the number of rays crossing it; points never move.
  std::size_t counts = 0, not_counts = 0, multiple = 0;
  for (const CellVisibility& cell : baseline.cells) {
    (cell.weight == cell.crossings ? counts : not_counts) += 1;
    multiple += cell.crossings > 1;
  }
  EXPECT_EQ(not_counts, 0u);
  EXPECT_GT(multiple, 100u);
  EXPECT_EQ(baseline.totals.moved_points, 0u);
  EXPECT_EQ(baseline.totals.cache_lookups, 0u) << "no next-cell cache in the baselines";
  // The proposed mode: inverse-cone weights and exact moves.
  not_counts = 0;
  for (const CellVisibility& cell : proposed.cells) not_counts += cell.weight != cell.crossings;
  EXPECT_GT(not_counts, 100u);
  EXPECT_GT(proposed.totals.moved_points, 500u);
  EXPECT_GT(proposed.totals.cache_lookups, 0u);
}

// ---- The point policy ----------------------------------------------------------------------

/// Vertex positions of the triangulation.
std::set<std::array<double, 3>> vertexPositions(const std::vector<CellVisibility>& cells) {
  std::set<std::array<double, 3>> positions;
  for (const CellVisibility& cell : cells) {
    for (const Eigen::Vector3d& p : cell.vertices_W) positions.insert({p.x(), p.y(), p.z()});
  }
  return positions;
}

/// Runs keyframe by keyframe; returns (positions that were ever vertices, final vertices).
std::pair<std::set<std::array<double, 3>>, std::set<std::array<double, 3>>> vertexHistory(
    MesherConfig config, const std::vector<Keyframe>& keyframes, UpdateStats& totals) {
  config.steiner_step_m = 4.0;
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = test::keyframeBounds(keyframes);
  Mesher mesher(config);
  std::set<std::array<double, 3>> ever;
  for (const Keyframe& keyframe : keyframes) {
    totals += mesher.integrateKeyframe(keyframe);
    const auto now = vertexPositions(mesher.cellVisibility());
    ever.insert(now.begin(), now.end());
  }
  return {ever, vertexPositions(mesher.cellVisibility())};
}

TEST(PointPolicy, FixedPositionKeepsEveryVertexWhereItWasFirstInserted) {
  const std::vector<Keyframe> keyframes = movingRoom();
  for (MesherMode mode : {MesherMode::kLitvinov13, MesherMode::kRomanoni15}) {
    UpdateStats fixed_totals;
    const auto [ever, final_vertices] =
        vertexHistory(MesherConfig::forMode(mode), keyframes, fixed_totals);
    EXPECT_EQ(fixed_totals.moved_points, 0u) << toString(mode);
    EXPECT_EQ(ever, final_vertices) << toString(mode) << ": a vertex left its first position";
    EXPECT_GT(fixed_totals.new_points, 500u);

    MesherConfig exact = MesherConfig::forMode(mode);
    exact.point_policy = PointPolicy::kExactMoves;
    UpdateStats exact_totals;
    const auto [ever_exact, final_exact] = vertexHistory(exact, keyframes, exact_totals);
    EXPECT_GT(exact_totals.moved_points, 500u) << toString(mode);
    EXPECT_GT(ever_exact.size(), final_exact.size() + 500) << "moved vertices leave old positions";
  }
}

// ---- Each --disable switch does what it names ----------------------------------------------

TEST(Ablation, BoundaryHashChangesOnlyTheWorkOfFindingTheEnclosedVertices) {
  const std::vector<Keyframe> keyframes = movingRoom();
  const ModeRun with = runStream(MesherConfig(), keyframes);
  MesherConfig config;
  config.boundary_hash = false;
  const ModeRun without = runStream(config, keyframes);
  expectSameMesh(with.mesh, without.mesh);
  expectSameCells(with.cells, without.cells);
  EXPECT_EQ(with.totals.enclosing_cells, without.totals.enclosing_cells);
  EXPECT_EQ(with.totals.cells_shrunk, without.totals.cells_shrunk);
  EXPECT_EQ(with.totals.cells_grown, without.totals.cells_grown);
  EXPECT_GT(with.totals.boundary_vertices_examined, 0u);
  EXPECT_GT(without.totals.boundary_vertices_examined, with.totals.boundary_vertices_examined);
}

TEST(Ablation, NextCellCacheChangesOnlyTheOrderOfTests) {
  const std::vector<Keyframe> keyframes = movingRoom();
  const ModeRun with = runStream(MesherConfig(), keyframes);
  MesherConfig config;
  config.next_cell_cache = false;
  const ModeRun without = runStream(config, keyframes);
  expectSameMesh(with.mesh, without.mesh);
  EXPECT_EQ(with.totals.walk_steps, without.totals.walk_steps);
  EXPECT_GT(with.totals.cache_hits, 0u);
  EXPECT_EQ(without.totals.cache_lookups, 0u);
  EXPECT_EQ(without.totals.cache_hits, 0u);
}

TEST(Ablation, RaySchedulerWalksEachRayOnceAndChangesNoWeight) {
  const std::vector<Keyframe> keyframes = movingRoom();
  const ModeRun with = runStream(MesherConfig(), keyframes);
  MesherConfig config;
  config.ray_scheduler = false;
  const ModeRun without = runStream(config, keyframes);
  expectSameCells(with.cells, without.cells);
  EXPECT_EQ(with.totals.rays_traced, without.totals.rays_traced);
  EXPECT_GT(without.totals.rays_retraced, with.totals.rays_retraced + with.totals.rays_retraced / 2)
      << "without the scheduler a ray is walked again after each change that cuts it";
}

TEST(Ablation, FixedSteinerGridIsBuiltOnceAndNeverGrows) {
  test::SceneOptions options;
  const std::vector<Keyframe> keyframes = test::planeScene(options).keyframes;
  MesherConfig config;
  config.incremental_steiner_grid = false;
  const ModeRun fixed = runStream(config, keyframes);
  const ModeRun incremental = runStream(MesherConfig(), keyframes);
  ASSERT_GT(fixed.updates.front().steiner_points, 0u);
  std::size_t later_fixed = 0, later_incremental = 0;
  for (std::size_t i = 1; i < keyframes.size(); ++i) {
    later_fixed += fixed.updates[i].steiner_points;
    later_incremental += incremental.updates[i].steiner_points;
  }
  EXPECT_EQ(later_fixed, 0u);
  EXPECT_GT(later_incremental, 0u) << "the incremental grid grows with the map";
  EXPECT_LT(incremental.updates.front().steiner_points, fixed.updates.front().steiner_points);
}

TEST(Ablation, WithoutTheLocalEnclosingSetEveryUpdateEnclosesAllOfONearTheCamera) {
  const std::vector<Keyframe> keyframes = movingRoom();
  MesherConfig config;
  config.local_enclosing_set = false;
  const ModeRun spheres = runStream(config, keyframes);
  MesherConfig local;
  local.enclosing_radius_cells = 1;
  const ModeRun keyed = runStream(local, keyframes);
  // The room (12 x 9 x 3.5 m) lies within max_camera_distance_m (40 m) of every camera: the
  // camera spheres enclose all of O, and no region is looked up in the hash.
  std::size_t updates_with_o = 0, smaller = 0;
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    if (spheres.outside_before[i] == 0) continue;
    ++updates_with_o;
    EXPECT_EQ(spheres.updates[i].enclosing_cells, spheres.outside_before[i]) << "update " << i;
    smaller += keyed.updates[i].enclosing_cells < keyed.outside_before[i];
  }
  EXPECT_GT(updates_with_o, 10u);
  EXPECT_EQ(spheres.totals.boundary_vertices_examined, 0u);
  EXPECT_GT(smaller, 0u) << "the local set encloses less than all of O";
}

TEST(Ablation, EdgePassAddsRingsAroundEdgesOnlyWhenOn) {
  const std::vector<Keyframe> keyframes = movingRoom();
  MesherConfig low;
  low.edge_pass_min_weight = 0;  // try every refused cell, so the small scene exercises the pass
  const ModeRun with = runStream(low, keyframes);
  MesherConfig off = low;
  off.edge_growing_pass = false;
  const ModeRun without = runStream(off, keyframes);
  EXPECT_GT(with.totals.edge_pass_cells, 0u);
  EXPECT_EQ(without.totals.edge_pass_cells, 0u);
  MesherConfig unreachable = low;
  unreachable.edge_pass_min_weight = 1e6;  // no cell is that heavy
  EXPECT_EQ(runStream(unreachable, keyframes).totals.edge_pass_cells, 0u);
}

}  // namespace
}  // namespace terramesh::mesher
