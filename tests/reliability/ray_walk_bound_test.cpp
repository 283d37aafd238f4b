// Every ray walk terminates: degenerate rays (through a vertex, along an edge, inside a face, of
// zero length, from a camera on a vertex) in the most degenerate triangulation there is, a cubic
// lattice (eight cospherical points per cube, coplanar faces everywhere). The walk is bounded by
// the number of cells (a straight walk enters each cell at most once); the bound is a counter
// that must stay at zero.
#include <gtest/gtest.h>

#include <random>

#include "cgal_types.h"
#include "ray_walk.h"

namespace terramesh::mesher::internal {
namespace {

class DegenerateRayWalk : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int i = 0; i <= 5; ++i) {
      for (int j = 0; j <= 5; ++j) {
        for (int k = 0; k <= 5; ++k) lattice_.push_back(tri_.insert(Point(i, j, k)));
      }
    }
  }

  VertexHandle at(int i, int j, int k) const { return lattice_[static_cast<std::size_t>((i * 6 + j) * 6 + k)]; }

  CameraLocation locate(const Point& p) const {
    CameraLocation camera;
    camera.position = p;
    camera.cell = tri_.locate(p, camera.type, camera.li, camera.lj);
    return camera;
  }

  /// Walks one ray; it must end, with a connected path to the target or a counted failure.
  void expectTerminates(const Point& camera_W, VertexHandle target) {
    const CameraLocation camera = locate(camera_W);
    const std::size_t failures = counters_.failures;
    std::vector<CellHandle> path;
    walker_.walk(camera, target, path, counters_);
    EXPECT_EQ(counters_.step_limit_hits, 0u);
    if (path.empty()) {
      EXPECT_EQ(counters_.failures, failures + 1) << "an empty path is a counted failure";
      return;
    }
    EXPECT_TRUE(path.back()->has_vertex(target));
    for (std::size_t i = 1; i < path.size(); ++i) EXPECT_TRUE(path[i - 1]->has_neighbor(path[i]));
    EXPECT_LE(path.size(), tri_.number_of_cells() + 1);
    ++walked_;
  }

  Delaunay tri_;
  std::vector<VertexHandle> lattice_;
  RayWalker walker_{tri_, true};
  WalkCounters counters_;
  std::size_t walked_ = 0;
};

TEST_F(DegenerateRayWalk, ThroughAVertex) {
  expectTerminates(Point(0.5, 0.5, 0.5), at(2, 2, 2));  // passes exactly through (1,1,1)
  expectTerminates(Point(0.5, 1, 1.5), at(2, 4, 3));    // passes exactly through (1,2,2)
  EXPECT_EQ(walked_, 2u);
}

TEST_F(DegenerateRayWalk, AlongAnEdge) {
  expectTerminates(Point(0.5, 2, 2), at(5, 2, 2));  // along the lattice line y = z = 2
  expectTerminates(Point(2, 2, 0.25), at(2, 2, 5));
  EXPECT_EQ(walked_, 2u);
}

TEST_F(DegenerateRayWalk, InsideAFace) {
  expectTerminates(Point(0.5, 0.25, 2), at(3, 2, 2));  // in the lattice plane z = 2
  expectTerminates(Point(2, 0.3, 0.7), at(2, 4, 3));   // in the plane x = 2
  EXPECT_EQ(walked_, 2u);
}

TEST_F(DegenerateRayWalk, ZeroLengthAndCameraOnAVertex) {
  expectTerminates(at(2, 3, 2)->point(), at(2, 3, 2));  // zero length: the camera is the target
  expectTerminates(at(1, 1, 1)->point(), at(4, 4, 4));  // camera on a vertex, along a diagonal
  expectTerminates(at(1, 1, 1)->point(), at(1, 4, 1));  // camera on a vertex, along an edge
  EXPECT_GE(counters_.fallbacks, 3u);
}

TEST_F(DegenerateRayWalk, EveryPairOfLatticeVerticesAndHalfPoints) {
  // Cameras on vertices, edge midpoints, face centres and cube centres; targets every vertex.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> half(1, 9);
  std::size_t rays = 0;
  for (int c = 0; c < 60; ++c) {
    const Point camera(0.5 * half(rng), 0.5 * half(rng), 0.5 * half(rng));
    for (std::size_t t = 0; t < lattice_.size(); t += 7) {
      expectTerminates(camera, lattice_[t]);
      ++rays;
    }
  }
  EXPECT_EQ(counters_.step_limit_hits, 0u);
  EXPECT_GT(counters_.fallbacks, 0u);
  EXPECT_GT(walked_, rays * 9 / 10) << "almost every degenerate ray finds a path";
}

}  // namespace
}  // namespace terramesh::mesher::internal
