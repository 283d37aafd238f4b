// Closest points on segments and triangles: each Voronoi region of a triangle (vertices, edges,
// interior), both windings, a brute-force oracle, and degenerate triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "common/closest_point.h"

namespace terramesh::geometry {
namespace {

const Eigen::Vector3d kA(0, 0, 0), kB(2, 0, 0), kC(0, 1, 0);

void expectPoint(const Eigen::Vector3d& got, const Eigen::Vector3d& want) {
  EXPECT_NEAR((got - want).norm(), 0.0, 1e-12) << got.transpose() << " vs " << want.transpose();
}

TEST(ClosestPointTest, SegmentClampsToItsEnds) {
  expectPoint(closestPointOnSegment({-1, 1, 0}, kA, kB), kA);
  expectPoint(closestPointOnSegment({3, -1, 0}, kA, kB), kB);
  expectPoint(closestPointOnSegment({0.5, 2, 7}, kA, kB), {0.5, 0, 0});
  expectPoint(closestPointOnSegment({4, 4, 4}, kC, kC), kC);
}

TEST(ClosestPointTest, EachRegionOfTheTriangle) {
  for (const DegenerateTriangles mode : {DegenerateTriangles::kAsEdges, DegenerateTriangles::kUnchecked}) {
    // Vertex regions.
    expectPoint(closestPointOnTriangle({-1, -1, 0.5}, kA, kB, kC, mode), kA);
    expectPoint(closestPointOnTriangle({3, -0.5, -1}, kA, kB, kC, mode), kB);
    expectPoint(closestPointOnTriangle({-0.5, 2, 0}, kA, kB, kC, mode), kC);
    // Edge regions: ab, ac and bc.
    expectPoint(closestPointOnTriangle({1, -3, 2}, kA, kB, kC, mode), {1, 0, 0});
    expectPoint(closestPointOnTriangle({-2, 0.5, 0}, kA, kB, kC, mode), {0, 0.5, 0});
    expectPoint(closestPointOnTriangle(Eigen::Vector3d(1, 0.5, 0) + Eigen::Vector3d(1, 2, 0), kA, kB, kC, mode),
                {1, 0.5, 0});
    // Interior: straight below and above the face.
    expectPoint(closestPointOnTriangle({0.5, 0.25, 3}, kA, kB, kC, mode), {0.5, 0.25, 0});
    expectPoint(closestPointOnTriangle({0.5, 0.25, -3}, kA, kB, kC, mode), {0.5, 0.25, 0});
    // The other winding gives the same points.
    expectPoint(closestPointOnTriangle({0.5, 0.25, 3}, kA, kC, kB, mode), {0.5, 0.25, 0});
    expectPoint(closestPointOnTriangle({3, -0.5, -1}, kC, kB, kA, mode), kB);
  }
}

TEST(ClosestPointTest, MatchesDenseSampling) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 3.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(unit(rng), unit(rng), unit(rng));
    const double distance = (closestPointOnTriangle(p, kA, kB, kC) - p).norm();
    double best = 1e300;
    for (int s = 0; s <= 200; ++s) {
      for (int t = 0; s + t <= 200; ++t) {
        best = std::min(best, (kA + s / 200.0 * (kB - kA) + t / 200.0 * (kC - kA) - p).norm());
      }
    }
    EXPECT_LE(distance, best + 1e-12);
    EXPECT_GE(distance, best - 0.02);  // the sampling grid is 1/100 m
    // Without the degenerate test, a well-shaped triangle gives the same bits.
    EXPECT_EQ(closestPointOnTriangle(p, kA, kB, kC),
              closestPointOnTriangle(p, kA, kB, kC, DegenerateTriangles::kUnchecked));
  }
}

TEST(ClosestPointTest, DegenerateTrianglesAreTheirEdges) {
  // Collinear: the nearest point of the three segments.
  expectPoint(closestPointOnTriangle({1, 1, 0}, kA, kB, Eigen::Vector3d(1, 0, 0)), {1, 0, 0});
  expectPoint(closestPointOnTriangle({3, 1, 0}, kA, kB, Eigen::Vector3d(1, 0, 0)), kB);
  // Two vertices coincide: the segment between the distinct ones.
  expectPoint(closestPointOnTriangle({0.5, 0.5, 0.5}, kA, kA, kB), {0.5, 0, 0});
  // One point: itself.
  expectPoint(closestPointOnTriangle({5, 5, 5}, kC, kC, kC), kC);
  // A sliver far below the threshold: still an edge point, and finite.
  const Eigen::Vector3d sliver(1, 1e-14, 0);
  const Eigen::Vector3d q = closestPointOnTriangle({1, 1, 0}, kA, kB, sliver);
  EXPECT_TRUE(q.allFinite());
  EXPECT_NEAR(q.x(), 1.0, 1e-12);
  EXPECT_NEAR(q.y(), 0.0, 1e-12);
}

}  // namespace
}  // namespace terramesh::geometry
