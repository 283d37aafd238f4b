// Handle control of manifold growing (issue 14, MesherConfig::handle_min_rays): a box of free
// space split by a wall that leaves a gap at the top, so O wraps around the wall's edge; a tunnel
// of free cells through the wall would add a handle. A tunnel crossed by few rays stays closed with
// the rule on; one crossed by many opens; with the rule off (0) growing opens either. Genus and
// components from V - E + F of the surface, which stays a closed 2-manifold throughout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "manifold_growing.h"
#include "map_state.h"
#include "mesher/triangle_mesh.h"
#include "outside_boundary.h"

namespace terramesh::mesher::internal {
namespace {

using test::boundaryOf;

constexpr std::int32_t kFree = 4000;  // fixed point: 250, well above free_threshold (20)
/// Fixed-point weight of a free cell crossed by `rays` rays: 10 per crossing plus what the
/// neighbours spread, at least 21 (free). Growing carves heavier cells first, so O surrounds the
/// wall before it enters a weak tunnel from both ends.
std::int32_t tunnelWeight(std::uint32_t rays) {
  return 16 * std::max<std::int32_t>(21, 10 * static_cast<std::int32_t>(rays));
}
constexpr std::uint32_t kManyRays = 50;

enum class Tunnel { kNone, kWeak, kStrong };

struct Topology {
  std::size_t components = 0;
  long genus = 0;
  bool closed_manifold = false;
};

/// Grows O to convergence on the scene and returns the topology of its boundary.
Topology growScene(Tunnel tunnel, std::uint32_t tunnel_rays, int handle_min_rays) {
  MesherConfig config;
  config.handle_min_rays = handle_min_rays;
  MapState state(config);
  state.grid.coverPoint(Eigen::Vector3d::Zero(), 1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 10; ++j) {
      for (int k = 0; k <= 10; ++k) {
        state.tri.insert(Point(i + jitter(rng), j + jitter(rng), k + jitter(rng)));
      }
    }
  }
  for (auto cell = state.tri.all_cells_begin(); cell != state.tri.all_cells_end(); ++cell) {
    for (int i = 0; i < 4; ++i) ++cell->vertex(i)->info().degree;
    state.stampNewCell(cell);
  }
  CellHandle seed;
  for (auto cell = state.tri.finite_cells_begin(); cell != state.tri.finite_cells_end(); ++cell) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; ++i) c += toEigen(cell->vertex(i)->point()) / 4.0;
    const bool in_box = (c.array() > 1.0).all() && (c.array() < 9.0).all();
    const bool in_wall = c.x() > 4.2 && c.x() < 5.8 && c.y() < 6.5;
    const bool in_tunnel = in_wall && std::hypot(c.y() - 3.5, c.z() - 5.0) < 1.3;
    CellInfo& info = cell->info();
    if (in_box && !in_wall) {
      info.weight = kFree;
      info.crossings = kManyRays;
      if (seed == CellHandle() && c.x() < 3.0) seed = cell;
    } else if (in_box && in_tunnel && tunnel != Tunnel::kNone) {
      info.weight = tunnelWeight(tunnel_rays);
      info.crossings = tunnel_rays;
    }
  }
  state.candidates.add(seed);
  Grower grower(state);
  for (int round = 0; round < 50; ++round) {
    UpdateStats stats;
    grower.grow(nullptr, stats);
    if (stats.cells_grown == 0) break;
  }
  const MeshTopology topology = analyzeTopology(boundaryOf(state.tri));
  return {topology.components, topology.total_genus, topology.isClosedManifold()};
}

/// The grown surface is one closed 2-manifold with this many handles.
void expectOneClosedSurfaceOfGenus(const Topology& t, int genus) {
  EXPECT_TRUE(t.closed_manifold);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.genus, genus);
}

TEST(HandleControl, WithoutTunnelTheSurfaceIsASphere) {
  expectOneClosedSurfaceOfGenus(growScene(Tunnel::kNone, 0, 0), 0);
}

TEST(HandleControl, OffOpensAWeakTunnel) {
  expectOneClosedSurfaceOfGenus(growScene(Tunnel::kWeak, 2, 0), 1);
}

TEST(HandleControl, OnKeepsAWeakTunnelClosed) {
  expectOneClosedSurfaceOfGenus(growScene(Tunnel::kWeak, 2, 10), 0);
}

TEST(HandleControl, OnOpensAWellObservedTunnel) {
  expectOneClosedSurfaceOfGenus(growScene(Tunnel::kStrong, kManyRays, 10), 1);
}

TEST(HandleControl, ThresholdIsInclusive) {
  EXPECT_EQ(growScene(Tunnel::kWeak, 9, 10).genus, 0);
  EXPECT_EQ(growScene(Tunnel::kWeak, 10, 10).genus, 1);
}

}  // namespace
}  // namespace terramesh::mesher::internal
