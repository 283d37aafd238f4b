// Depth comparison, surface distances and the nearest-point index on scenes with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "datasets/point_cloud_index.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/mesh_evaluation.h"

namespace terramesh::evaluation {
namespace {

using datasets::PointCloudIndex;
using datasets::TriangleBvh;

/// A square grid of `n` x `n` quads over [-half, half]^2 at height z, two triangles per quad.
/// Quads whose centre has x > 0 are left out when `left_half_only`.
mesher::TriangleMesh planeGrid(double z, double half = 50.0, int n = 20, bool left_half_only = false) {
  mesher::TriangleMesh mesh;
  const double step = 2.0 * half / n;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.vertices.emplace_back(-half + i * step, -half + j * step, z);
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (left_half_only && -half + (i + 0.5) * step > 0) continue;
      const auto a = static_cast<std::uint32_t>(j * (n + 1) + i);
      mesh.faces.push_back({a, a + 1, a + static_cast<std::uint32_t>(n) + 2});
      mesh.faces.push_back({a, a + static_cast<std::uint32_t>(n) + 2, a + static_cast<std::uint32_t>(n) + 1});
    }
  }
  return mesh;
}

/// A camera 10 m above the origin looking straight down (camera z = world -z).
std::vector<EvaluationView> downwardView() {
  EvaluationView view;
  view.centre_W = Eigen::Vector3d(0, 0, 10);
  view.rotation_W_C = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  return {view};
}

DepthComparisonConfig config() {
  DepthComparisonConfig c;
  c.stride_px = 16;
  return c;
}

TEST(DepthComparison, IdenticalMeshHasNoErrorAndFullCoverage) {
  const mesher::TriangleMesh truth = planeGrid(0.0);
  const TriangleBvh bvh(truth);
  const auto rays = renderTruthRays(bvh, downwardView(), PinholeCamera{}, config());
  ASSERT_GT(rays.size(), 1000u);
  const DepthErrors errors = compareDepths(bvh, truth, rays, config());
  EXPECT_EQ(errors.compared, rays.size());
  EXPECT_NEAR(errors.mean_abs_m, 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(errors.coverage(), 1.0);
}

TEST(DepthComparison, RaisedPlaneErrorIsTheOffsetOverTheCosineAndSigned) {
  const TriangleBvh truth(planeGrid(0.0));
  const auto rays = renderTruthRays(truth, downwardView(), PinholeCamera{}, config());
  // Every ray meets the raised plane 0.2 / cos(angle to the vertical) early; the widest angle of
  // KITTI's camera is about 42.5 degrees.
  const mesher::TriangleMesh raised = planeGrid(0.2);
  const DepthErrors errors = compareDepths(TriangleBvh(raised), raised, rays, config());
  EXPECT_EQ(errors.compared, rays.size());
  EXPECT_GE(errors.mean_abs_m, 0.2 - 1e-9);
  EXPECT_LE(errors.mean_abs_m, 0.2 / std::cos(42.6 * M_PI / 180.0));
  EXPECT_NEAR(errors.mean_signed_m, -errors.mean_abs_m, 1e-9);
  EXPECT_DOUBLE_EQ(errors.coverage(), 1.0);
  // 0.6 m away, no ray is within the 0.5 m coverage threshold.
  const mesher::TriangleMesh far = planeGrid(-0.6);
  const DepthErrors far_errors = compareDepths(TriangleBvh(far), far, rays, config());
  EXPECT_EQ(far_errors.covered, 0u);
  EXPECT_GT(far_errors.mean_signed_m, 0.6 - 1e-9);
}

TEST(DepthComparison, AHoleLowersCoverageAndSteinerHitsAreCounted) {
  const TriangleBvh truth(planeGrid(0.0));
  const auto rays = renderTruthRays(truth, downwardView(), PinholeCamera{}, config());
  mesher::TriangleMesh half = planeGrid(0.0, 50.0, 20, true);
  const DepthErrors errors = compareDepths(TriangleBvh(half), half, rays, config());
  EXPECT_LT(errors.compared, rays.size());
  EXPECT_EQ(errors.covered, errors.compared);
  EXPECT_GT(errors.coverage(), 0.3);
  EXPECT_LT(errors.coverage(), 0.7);
  EXPECT_EQ(errors.steiner_hits, 0u);
  half.is_steiner.assign(half.vertices.size(), 1);
  EXPECT_EQ(compareDepths(TriangleBvh(half), half, rays, config()).steiner_hits, errors.compared);
}

TEST(DepthComparison, RaysToPointsKeepThoseWithinTheMaximumDepth) {
  const std::vector<Eigen::Vector3d> points = {{3, 4, 0}, {0, 0, 50}, {0, 0, 0}};
  const auto rays = raysToPoints(Eigen::Vector3d::Zero(), points, DepthComparisonConfig{});
  ASSERT_EQ(rays.size(), 1u);  // 50 m is beyond 40 m; the origin itself has no direction
  EXPECT_DOUBLE_EQ(rays[0].truth_depth_m, 5.0);
  EXPECT_NEAR((rays[0].direction_W - Eigen::Vector3d(0.6, 0.8, 0)).norm(), 0.0, 1e-12);
}

TEST(SurfaceDistances, OffsetPlaneSamplesAreAtTheOffset) {
  const mesher::TriangleMesh raised = planeGrid(0.2, 10.0, 4);
  const auto samples = sampleSurface(raised, 2000, 7, false);
  ASSERT_EQ(samples.size(), 2000u);
  const DistanceStats stats = distancesToSurface(samples, TriangleBvh(planeGrid(0.0, 20.0, 4)));
  EXPECT_EQ(stats.matched, 2000u);
  EXPECT_NEAR(stats.mean_m, 0.2, 1e-9);
  EXPECT_NEAR(stats.p90_m, 0.2, 1e-9);
  EXPECT_DOUBLE_EQ(stats.within[DistanceStats::kWithin10cm], 0.0);  // 0.1 m
  EXPECT_DOUBLE_EQ(stats.within[DistanceStats::kWithin25cm], 1.0);  // 0.25 m
}

TEST(SurfaceDistances, SamplingIsByAreaDeterministicAndSkipsSteinerFaces) {
  mesher::TriangleMesh mesh = planeGrid(0.0, 10.0, 4);
  const auto a = sampleSurface(mesh, 4000, 3, false);
  const auto b = sampleSurface(mesh, 4000, 3, false);
  EXPECT_EQ(a, b);
  const auto left = std::count_if(a.begin(), a.end(), [](const Eigen::Vector3d& p) { return p.x() < 0; });
  EXPECT_NEAR(static_cast<double>(left) / 4000.0, 0.5, 0.05);
  // Flag the vertices right of x = 5: faces touching them are never sampled.
  mesh.is_steiner.assign(mesh.vertices.size(), 0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) mesh.is_steiner[v] = mesh.vertices[v].x() > 5.0 - 1e-9;
  for (const Eigen::Vector3d& p : sampleSurface(mesh, 4000, 3, true)) EXPECT_LE(p.x(), 0.0 + 1e-9);
}

TEST(SurfaceDistances, DistancesToPointsCountUnmatchedSamples) {
  std::vector<Eigen::Vector3d> cloud;
  for (int i = -20; i <= 20; ++i) {
    for (int j = -20; j <= 20; ++j) cloud.emplace_back(0.1 * i, 0.1 * j, 0.0);
  }
  const PointCloudIndex index(cloud);
  const std::vector<Eigen::Vector3d> samples = {{0, 0, 0.3}, {0.05, 0.05, 0.0}, {10, 10, 10}};
  const DistanceStats stats = distancesToPoints(samples, index, 1.0);
  EXPECT_EQ(stats.samples, 3u);
  EXPECT_EQ(stats.matched, 2u);
  // Within 0.5 m: the far sample counts as beyond; within 0.2 m and 0.1 m only the in-plane one.
  EXPECT_NEAR(stats.within[DistanceStats::kWithin50cm], 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(stats.within[DistanceStats::kWithin20cm], 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(stats.within[DistanceStats::kWithin10cm], 1.0 / 3.0, 1e-12);
}

TEST(PointCloudIndex, NearestMatchesBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::vector<Eigen::Vector3d> points(3000);
  for (auto& p : points) p = Eigen::Vector3d(u(rng), u(rng), u(rng));
  const PointCloudIndex index(points);
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3d query(u(rng) * 1.3, u(rng) * 1.3, u(rng) * 1.3);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : points) best = std::min(best, (p - query).norm());
    const auto found = index.nearest(query, 2.0);
    if (best > 2.0) {
      EXPECT_FALSE(found.has_value());
    } else {
      ASSERT_TRUE(found.has_value());
      EXPECT_DOUBLE_EQ(found->distance, best);
    }
  }
  std::vector<Eigen::Vector3d> with_nan = points;
  with_nan.push_back(Eigen::Vector3d(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0));
  EXPECT_THROW(PointCloudIndex{with_nan}, std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::evaluation
