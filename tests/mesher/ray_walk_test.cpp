// The straight walk with next-tetrahedron caching against CGAL's segment traverser.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "cgal_types.h"
#include "ray_walk.h"

namespace terramesh::mesher::internal {
namespace {

class RayWalkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> coordinate(-10.0, 10.0);
    for (int i = 0; i < 3000; ++i) {
      vertices_.push_back(tri_.insert(Point(coordinate(rng), coordinate(rng), coordinate(rng))));
    }
    // A bounding lattice so cameras are inside the hull.
    for (int i = -1; i <= 1; ++i) {
      for (int j = -1; j <= 1; ++j) {
        for (int k = -1; k <= 1; ++k) tri_.insert(Point(15.0 * i, 15.0 * j, 15.0 * k));
      }
    }
  }

  CameraLocation locate(const Point& p) const {
    CameraLocation camera;
    camera.position = p;
    camera.cell = tri_.locate(p, camera.type, camera.li, camera.lj);
    return camera;
  }

  std::vector<CellHandle> reference(const CameraLocation& camera, VertexHandle target) const {
    std::vector<CellHandle> path;
    for (CellHandle cell : tri_.segment_traverser_cell_handles(camera.position, target->point())) {
      path.push_back(cell);
      if (cell->has_vertex(target)) break;
    }
    return path;
  }

  Delaunay tri_;
  std::vector<VertexHandle> vertices_;
};

TEST_F(RayWalkTest, MatchesCgalsSegmentTraverserWithAndWithoutCache) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-9.0, 9.0);
  RayWalker cached(tri_, true);
  RayWalker plain(tri_, false);
  WalkCounters cached_counters;
  WalkCounters plain_counters;
  std::vector<CellHandle> a, b;
  std::size_t rays = 0;
  // Several cameras, each seeing many points: the cache is exercised by similar directions.
  for (int c = 0; c < 20; ++c) {
    const CameraLocation camera = locate(Point(coordinate(rng), coordinate(rng), coordinate(rng)));
    ASSERT_EQ(camera.type, Delaunay::CELL);
    for (int r = 0; r < 150; ++r) {
      const VertexHandle target = vertices_[rng() % vertices_.size()];
      cached.walk(camera, target, a, cached_counters);
      plain.walk(camera, target, b, plain_counters);
      const std::vector<CellHandle> expected = reference(camera, target);
      ASSERT_EQ(a, expected) << "camera " << c << " ray " << r;
      ASSERT_EQ(b, expected);
      ASSERT_TRUE(a.back()->has_vertex(target));
      ++rays;
    }
  }
  EXPECT_EQ(cached_counters.fallbacks, 0u);
  EXPECT_EQ(cached_counters.steps, plain_counters.steps);
  EXPECT_GT(cached_counters.cache_lookups, cached_counters.steps / 2);
  EXPECT_GT(cached_counters.cache_hits, 0u);
  EXPECT_EQ(plain_counters.cache_lookups, 0u);
  EXPECT_EQ(rays, 3000u);
}

TEST_F(RayWalkTest, BridgingACutStretchGivesTheFreshWalk) {
  // A point inserted near the middle of a stored path destroys a stretch of it. Walking from the
  // prefix's last cell until the walk enters the tail's first must give, with the prefix and the
  // tail kept, the path a fresh walk finds, in fewer steps.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-9.0, 9.0);
  std::uniform_real_distribution<double> along(0.35, 0.65);
  RayWalker walker(tri_, true);
  std::vector<CellHandle> path, between, fresh;
  std::size_t bridged = 0, bridge_steps = 0, fresh_steps = 0;
  for (int r = 0; r < 400 && bridged < 60; ++r) {
    const CameraLocation camera = locate(Point(coordinate(rng), coordinate(rng), coordinate(rng)));
    const VertexHandle target = vertices_[rng() % vertices_.size()];
    WalkCounters counters;
    if (walker.walk(camera, target, path, counters) != kWalkedStraight || path.size() < 12) continue;
    // A new point just off the segment, within its middle third.
    const Eigen::Vector3d q = toEigen(camera.position), p = toEigen(target->point());
    const Eigen::Vector3d offset(0.013, -0.007, 0.011);
    const Point inserted = toPoint(q + along(rng) * (p - q) + offset);
    std::vector<CellHandle> doomed;
    tri_.find_conflicts(inserted, tri_.locate(inserted), CGAL::Emptyset_iterator(),
                        std::back_inserter(doomed));
    const auto isDoomed = [&](const CellHandle& c) {
      return std::find(doomed.begin(), doomed.end(), c) != doomed.end();
    };
    std::size_t first = path.size(), last = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
      if (!isDoomed(path[i])) continue;
      first = std::min(first, i);
      last = i;
    }
    if (first == path.size() || first == 0 || last + 1 >= path.size()) continue;
    std::vector<CellHandle> kept(path.begin(), path.begin() + static_cast<std::ptrdiff_t>(first));
    kept.insert(kept.end(), path.begin() + static_cast<std::ptrdiff_t>(last + 1), path.end());
    vertices_.push_back(tri_.insert(inserted));
    WalkCounters bridge_counters;
    ASSERT_TRUE(walker.bridge(camera.position, target, kept, first, between, bridge_counters))
        << "ray " << r;
    kept.insert(kept.begin() + static_cast<std::ptrdiff_t>(first), between.begin(), between.end());
    WalkCounters fresh_counters;
    ASSERT_EQ(walker.walk(locate(camera.position), target, fresh, fresh_counters), kWalkedStraight);
    ASSERT_EQ(kept, fresh) << "ray " << r;
    bridge_steps += bridge_counters.steps;
    fresh_steps += fresh_counters.steps;
    ++bridged;
    // A tail cell the segment never enters: the walk reaches the target and says so.
    const std::vector<CellHandle> wrong{fresh.front(), vertices_.front()->cell()};
    if (std::find(fresh.begin(), fresh.end(), wrong.back()) == fresh.end()) {
      EXPECT_FALSE(walker.bridge(camera.position, target, wrong, 1, between, bridge_counters));
    }
  }
  ASSERT_GE(bridged, 30u);
  EXPECT_LT(2 * bridge_steps, fresh_steps) << "the bridge walks the cut stretch, not the tail";
}

/// A path is a chain of face-adjacent cells from one containing the camera to one at the target.
void expectConnectedPath(const Delaunay& tri, const std::vector<CellHandle>& path, const Point& camera,
                         VertexHandle target) {
  ASSERT_FALSE(path.empty());
  Delaunay::Locate_type type;
  int li = 0, lj = 0;
  EXPECT_NE(tri.side_of_cell(camera, path.front(), type, li, lj), CGAL::ON_UNBOUNDED_SIDE);
  EXPECT_TRUE(path.back()->has_vertex(target));
  for (std::size_t i = 1; i < path.size(); ++i) EXPECT_TRUE(path[i - 1]->has_neighbor(path[i]));
}

TEST_F(RayWalkTest, CameraOnAVertexWalksFromADisplacedCamera) {
  const VertexHandle on = vertices_[10];
  const CameraLocation camera = locate(on->point());
  ASSERT_EQ(camera.type, Delaunay::VERTEX);
  RayWalker walker(tri_, true);
  WalkCounters counters;
  std::vector<CellHandle> path, again;
  walker.walk(camera, vertices_[20], path, counters);
  EXPECT_EQ(counters.fallbacks, 1u);
  EXPECT_EQ(counters.failures, 0u);
  expectConnectedPath(tri_, path, on->point(), vertices_[20]);
  walker.walk(camera, vertices_[20], again, counters);
  EXPECT_EQ(path, again) << "the displaced walk is deterministic";
}

TEST(RayWalkDegenerate, RaysAlongLatticeEdgesStillReachTheTarget) {
  Delaunay tri;
  std::vector<VertexHandle> lattice;
  for (int i = 0; i <= 4; ++i) {
    for (int j = 0; j <= 4; ++j) {
      for (int k = 0; k <= 4; ++k) lattice.push_back(tri.insert(Point(i, j, k)));
    }
  }
  // A camera on the segment between two lattice points along an axis: the ray runs along edges.
  CameraLocation camera;
  camera.position = Point(0.5 + 1e-9, 2.0, 2.0);
  camera.cell = tri.locate(camera.position, camera.type, camera.li, camera.lj);
  RayWalker walker(tri, true);
  WalkCounters counters;
  std::vector<CellHandle> path;
  for (const VertexHandle& target : lattice) {
    if (target->point() == Point(0, 0, 0)) continue;
    walker.walk(camera, target, path, counters);
    expectConnectedPath(tri, path, camera.position, target);
  }
  EXPECT_GT(counters.fallbacks, 0u);
  EXPECT_EQ(counters.failures, 0u);
}

TEST(OutwardFacets, AreWoundWithTheNormalOutOfTheCell) {
  Delaunay tri;
  tri.insert(Point(0, 0, 0));
  tri.insert(Point(1, 0, 0));
  tri.insert(Point(0, 1, 0));
  tri.insert(Point(0, 0, 1));
  const CellHandle cell = tri.finite_cells_begin();
  for (int i = 0; i < 4; ++i) {
    const Point& a = cell->vertex(outwardFacetVertex(i, 0))->point();
    const Point& b = cell->vertex(outwardFacetVertex(i, 1))->point();
    const Point& c = cell->vertex(outwardFacetVertex(i, 2))->point();
    // The opposite vertex is inside, so on the negative side of an outward-wound facet.
    EXPECT_EQ(CGAL::orientation(a, b, c, cell->vertex(i)->point()), CGAL::NEGATIVE);
  }
}

}  // namespace
}  // namespace terramesh::mesher::internal
