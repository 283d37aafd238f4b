// The ball pass of manifold growing (issue 14): once growing has converged, no heavy free cell next
// to O can still be added together with its ball (itself and every free non-O cell sharing a vertex
// with it) without breaking the surface, checked against a brute-force oracle (the topology of the
// surface after the change); and the surface stays a closed 2-manifold. With and without the edge
// and ball passes.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include "manifold_growing.h"
#include "map_state.h"
#include "mesher/triangle_mesh.h"
#include "outside_boundary.h"

namespace terramesh::mesher::internal {
namespace {

using test::boundaryOf;
using test::surfaceIsManifold;

constexpr std::int32_t kHeavy = 4000;  // fixed point: 250 > edge_pass_min_weight (200)
constexpr std::int32_t kLight = 400;   // 25 > free_threshold (20): free, below the pass's floor

/// A random Delaunay triangulation whose cells are free (heavy or light) or matter at random,
/// with O started from one heavy cell, grown until nothing changes.
class BallPass : public ::testing::TestWithParam<bool> {
 protected:
  BallPass() : state_(configWithEdgePass(GetParam())) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
    state_.grid.coverPoint(Eigen::Vector3d::Zero(), 1);
    for (int i = 0; i < 500; ++i) state_.tri.insert(Point(coordinate(rng), coordinate(rng), coordinate(rng)));
    for (auto cell = state_.tri.all_cells_begin(); cell != state_.tri.all_cells_end(); ++cell) {
      for (int i = 0; i < 4; ++i) ++cell->vertex(i)->info().degree;
      state_.stampNewCell(cell);
    }
    std::uniform_real_distribution<double> draw(0.0, 1.0);
    CellHandle seed;
    for (auto cell = state_.tri.finite_cells_begin(); cell != state_.tri.finite_cells_end(); ++cell) {
      const double d = draw(rng);
      cell->info().weight = d < 0.55 ? kHeavy : d < 0.7 ? kLight : 0;
      if (seed == CellHandle() && cell->info().weight == kHeavy) seed = cell;
    }
    state_.candidates.add(seed);
  }

  static MesherConfig configWithEdgePass(bool on) {
    MesherConfig config;
    config.edge_growing_pass = on;
    return config;
  }

  /// Grows over the whole boundary until an update adds nothing; returns the cells added.
  std::size_t growToConvergence() {
    Grower grower(state_);
    std::size_t total = 0;
    for (int round = 0; round < 50; ++round) {
      UpdateStats stats;
      grower.grow(nullptr, stats);
      total += stats.cells_grown;
      if (stats.cells_grown == 0) break;
    }
    return total;
  }

  /// Heavy free cells next to O whose ball could be added keeping a closed manifold (oracle:
  /// flip the ball, look at the surface's topology, flip back).
  std::size_t acceptableBalls() {
    std::size_t count = 0;
    for (auto c = state_.tri.finite_cells_begin(); c != state_.tri.finite_cells_end(); ++c) {
      const CellHandle cell = c;
      if (cell->info().outside() || cell->info().weight != kHeavy) continue;
      bool adjacent = false;
      for (int i = 0; i < 4; ++i) adjacent = adjacent || cell->neighbor(i)->info().outside();
      if (!adjacent) continue;
      std::set<CellHandle> ball;
      for (int i = 0; i < 4; ++i) {
        std::vector<CellHandle> star;
        state_.tri.incident_cells(cell->vertex(i), std::back_inserter(star));
        for (const CellHandle& h : star) {
          if (!h->info().outside() && !state_.tri.is_infinite(h) && state_.weights.isFree(h)) ball.insert(h);
        }
      }
      for (const CellHandle& h : ball) h->info().flags ^= kCellOutside;
      count += surfaceIsManifold(state_.tri);
      for (const CellHandle& h : ball) h->info().flags ^= kCellOutside;
    }
    return count;
  }

  MapState state_;
};

TEST_P(BallPass, ConvergedGrowingLeavesNoAcceptableBallAndAManifold) {
  EXPECT_GT(growToConvergence(), 100u);
  EXPECT_TRUE(surfaceIsManifold(state_.tri));
  // With the pass on, this is its fixed point. (On these random scenes the edge and per-vertex
  // passes already leave none, seeds 1-3 and 30-70% heavy cells tried: the balls that only this
  // pass carves come from the street's geometry, docs/results/accuracy.md; here it must not break
  // the manifold nor change what the other passes reach.)
  EXPECT_EQ(acceptableBalls(), 0u);
}

INSTANTIATE_TEST_SUITE_P(EdgePass, BallPass, ::testing::Bool());

}  // namespace
}  // namespace terramesh::mesher::internal
