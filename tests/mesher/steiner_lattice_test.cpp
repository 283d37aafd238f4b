// The Steiner lattice's placement: the origin offset (an experiment option) moves the lattice and
// only it; the clearance keeps lattice nodes away from the points, as a function of the final
// points alone (moves and removals restore the nodes a fresh run would have).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "mesher/checkpoint.h"
#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

using Position = std::array<double, 3>;

Position key(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

/// Every vertex of the triangulation, split into inserted points (those at an observed position)
/// and Steiner nodes (the others).
struct Vertices {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> steiner;
};

Vertices verticesOf(const Mesher& mesher, const std::vector<Keyframe>& keyframes) {
  std::set<Position> observed;
  for (const Keyframe& keyframe : keyframes) {
    for (const PointObservation& o : keyframe.observations) observed.insert(key(o.position_W));
  }
  std::set<Position> seen;
  Vertices vertices;
  for (const CellVisibility& cell : mesher.cellVisibility()) {
    for (const Eigen::Vector3d& v : cell.vertices_W) {
      if (!seen.insert(key(v)).second) continue;
      (observed.count(key(v)) ? vertices.points : vertices.steiner).push_back(v);
    }
  }
  return vertices;
}

double nearestPointDistance(const Vertices& vertices) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& s : vertices.steiner) {
    for (const Eigen::Vector3d& p : vertices.points) nearest = std::min(nearest, (s - p).norm());
  }
  return nearest;
}

MesherConfig proposed(double clearance_steps) {
  MesherConfig config = MesherConfig::forMode(MesherMode::kProposed);
  config.steiner_step_m = 4.0;
  config.steiner_clearance_steps = clearance_steps;
  return config;
}

void runAll(Mesher& mesher, const std::vector<Keyframe>& keyframes, bool check) {
  for (const Keyframe& keyframe : keyframes) {
    mesher.integrateKeyframe(keyframe);
    if (check) {
      const InvariantReport report = mesher.checkInvariants();
      ASSERT_TRUE(report.ok()) << "keyframe " << keyframe.id.value << ": " << report.summary();
    }
  }
}

TEST(SteinerLattice, OffsetAndClearanceAreValidated) {
  MesherConfig config;
  EXPECT_TRUE(config.problems().empty());
  config.steiner_origin_offset_m = Eigen::Vector3d(0, std::numeric_limits<double>::quiet_NaN(), 0);
  config.steiner_clearance_steps = 0.5;
  const std::vector<std::string> problems = config.problems();
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_NE(problems[0].find("steiner_clearance_steps"), std::string::npos);
  EXPECT_NE(problems[1].find("steiner_origin_offset_m"), std::string::npos);
  config.steiner_origin_offset_m = Eigen::Vector3d(2e4, 0, 0);
  config.steiner_clearance_steps = -0.1;
  EXPECT_EQ(config.problems().size(), 2u);
}

TEST(SteinerLattice, BaselinesKeepEveryNode) {
  EXPECT_EQ(MesherConfig::forMode(MesherMode::kRomanoni15).steiner_clearance_steps, 0.0);
  EXPECT_EQ(MesherConfig::forMode(MesherMode::kLitvinov13).steiner_clearance_steps, 0.0);
  MesherConfig config = proposed(0.3);
  config.setMode(MesherMode::kProposed);
  EXPECT_EQ(config.steiner_clearance_steps, MesherConfig().steiner_clearance_steps);
}

TEST(SteinerLattice, TheOffsetMovesTheLatticeByExactlyThatMuch) {
  const auto scene = test::planeScene(test::SceneOptions());
  const Eigen::Vector3d offset(1.3, -0.7, 0.45);
  MesherConfig shifted = proposed(0.0);
  shifted.steiner_origin_offset_m = offset;
  Mesher a(proposed(0.0));
  Mesher b(shifted);
  runAll(a, scene.keyframes, false);
  runAll(b, scene.keyframes, false);
  const Vertices va = verticesOf(a, scene.keyframes);
  const Vertices vb = verticesOf(b, scene.keyframes);
  ASSERT_FALSE(va.steiner.empty());
  ASSERT_FALSE(vb.steiner.empty());
  // Every node of b, moved back by the offset, is a node of a's lattice (same step, same origin).
  const Eigen::Vector3d origin = va.steiner.front();
  double worst = 0;
  for (const Eigen::Vector3d& s : vb.steiner) {
    const Eigen::Vector3d cells = (s - offset - origin) / 4.0;
    worst = std::max(worst, (cells - cells.array().round().matrix()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9);
  // ... and not of a's lattice without moving back: the lattice did move.
  const Eigen::Vector3d cells = (vb.steiner.front() - origin) / 4.0;
  EXPECT_GT((cells - cells.array().round().matrix()).cwiseAbs().maxCoeff(), 0.1);
}

/// Largest distance, in cells, of a node of `b` from the lattice of `a` (step 4 m).
double offLattice(const Vertices& a, const Vertices& b) {
  double worst = 0;
  for (const Eigen::Vector3d& s : b.steiner) {
    const Eigen::Vector3d cells = (s - a.steiner.front()) / 4.0;
    worst = std::max(worst, (cells - cells.array().round().matrix()).cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(SteinerLattice, AGlobalPhaseGivesRunsOfDifferentDataOneLattice) {
  // Two runs that start on different keyframes (as two tiles of a plan do): with the global
  // phase every node of one lies on the other's lattice; without it the lattices differ.
  const auto scene = test::planeScene(test::SceneOptions());
  ASSERT_GE(scene.keyframes.size(), 6u);
  const std::vector<Keyframe> first(scene.keyframes.begin(), scene.keyframes.begin() + 3);
  const std::vector<Keyframe> later(scene.keyframes.begin() + 3, scene.keyframes.end());
  MesherConfig global = proposed(0.0);
  global.steiner_global_phase = true;
  Mesher a(global), b(global), c(proposed(0.0)), d(proposed(0.0));
  runAll(a, first, false);
  runAll(b, later, true);
  runAll(c, first, false);
  runAll(d, later, false);
  const Vertices va = verticesOf(a, first), vb = verticesOf(b, later);
  ASSERT_FALSE(va.steiner.empty());
  ASSERT_FALSE(vb.steiner.empty());
  EXPECT_LT(offLattice(va, vb), 1e-9);
  EXPECT_GT(offLattice(verticesOf(c, first), verticesOf(d, later)), 0.01);
  // The checkpoint keeps the setting.
  std::stringstream bytes;
  saveCheckpoint(b, bytes);
  EXPECT_TRUE(loadCheckpoint(bytes, "memory").mesher.config().steiner_global_phase);
}

TEST(SteinerLattice, CheckpointKeepsOffsetAndClearance) {
  const auto scene = test::planeScene(test::SceneOptions());
  MesherConfig config = proposed(0.3);
  config.steiner_origin_offset_m = Eigen::Vector3d(0.5, 1.5, -2.5);
  Mesher mesher(config);
  runAll(mesher, {scene.keyframes.begin(), scene.keyframes.begin() + 4}, false);
  std::stringstream bytes;
  saveCheckpoint(mesher, bytes);
  const LoadedCheckpoint loaded = loadCheckpoint(bytes, "memory");
  EXPECT_EQ(loaded.mesher.config().steiner_origin_offset_m, config.steiner_origin_offset_m);
  EXPECT_EQ(loaded.mesher.config().steiner_clearance_steps, 0.3);
}

TEST(SteinerClearance, NoNodeLiesWithinTheClearanceOfAPoint) {
  const auto scene = test::boxRoomScene(test::SceneOptions());
  Mesher kept(proposed(0.0));
  Mesher cleared(proposed(0.3));
  runAll(kept, scene.keyframes, false);
  runAll(cleared, scene.keyframes, true);
  const Vertices vk = verticesOf(kept, scene.keyframes);
  const Vertices vc = verticesOf(cleared, scene.keyframes);
  ASSERT_GT(vc.points.size(), 500u);
  EXPECT_EQ(vc.points.size(), vk.points.size());
  // Without the clearance some node is that close (the test can fail), with it none is.
  EXPECT_LT(nearestPointDistance(vk), 0.3 * 4.0);
  EXPECT_GE(nearestPointDistance(vc), 0.3 * 4.0);
  EXPECT_LT(vc.steiner.size(), vk.steiner.size());
  const TriangleMesh mesh = cleared.extractMesh();
  EXPECT_GT(mesh.faces.size(), 100u);
}

TEST(SteinerClearance, MovesAndRemovalsGiveTheTriangulationOfAFreshRun) {
  const auto scene = test::boxRoomScene(test::SceneOptions());
  // Moves of up to 0.6 m carry points in and out of the nodes' clearance (1.2 m). A fixed grid,
  // so that both runs have the same lattice.
  const auto moving = test::withMovingEstimates(scene.keyframes, 0.6, 11);
  const auto settled = test::withFinalEstimates(moving);
  MesherConfig config = proposed(0.3);
  config.incremental_steiner_grid = false;
  config.fixed_grid_bounds_W = AxisAlignedBox{Eigen::Vector3d(-5, -5, -5), Eigen::Vector3d(17, 14, 9)};
  Mesher incremental(config);
  UpdateStats totals;
  for (const Keyframe& keyframe : moving) {
    totals += incremental.integrateKeyframe(keyframe);
    const InvariantReport report = incremental.checkInvariants();
    ASSERT_TRUE(report.ok()) << "keyframe " << keyframe.id.value << ": " << report.summary();
  }
  ASSERT_GT(totals.moved_points, 500u);
  ASSERT_EQ(totals.deferred_points + totals.dropped_points, 0u) << "a deferred move keeps its old position";
  Mesher fresh(config);
  runAll(fresh, settled, false);

  std::vector<CellVisibility> a = incremental.cellVisibility();
  std::vector<CellVisibility> b = fresh.cellVisibility();
  ASSERT_EQ(a.size(), b.size());
  std::size_t different = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    different += a[i].vertices_W != b[i].vertices_W || a[i].weight != b[i].weight;
  }
  EXPECT_EQ(different, 0u);
  EXPECT_GE(nearestPointDistance(verticesOf(incremental, settled)), 0.3 * 4.0);
}

}  // namespace
}  // namespace terramesh::mesher
