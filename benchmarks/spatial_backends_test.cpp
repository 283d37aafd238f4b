// The libraries compared in spatial_queries_benchmark.cpp answer the same questions as the
// project's own structures: on random rays and points around a synthetic street, every backend
// finds the same first hits (distances), the same closest surface distances and the same nearest
// cloud points. Exact agreement in double precision (CGAL, nanoflann); Embree works in single
// precision, so its ray distances agree to 1e-3 m and a few grazing rays may differ.
#include <gtest/gtest.h>

#include <random>

#include "datasets/synthetic_scene.h"
#include "spatial_backends.h"

namespace terramesh::bench {
namespace {

struct Scene {
  mesher::TriangleMesh mesh;
  Eigen::AlignedBox3d box;
};

const Scene& scene() {
  static const Scene data = [] {
    datasets::StreetSceneConfig config;
    config.length_m = 60;
    Scene s;
    s.mesh = datasets::buildStreetScene(config).ground_truth.mesh;
    for (const Eigen::Vector3d& v : s.mesh.vertices) s.box.extend(v);
    return s;
  }();
  return data;
}

Eigen::Vector3d randomPoint(const Eigen::AlignedBox3d& box, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return box.min() + Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(box.sizes());
}

Eigen::Vector3d randomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
}

/// Compares first hits of `other` with the project's BVH on `count` random rays (max 40 m):
/// returns how many rays disagree on hit/miss, and checks the distances of rays both hit.
template <class Tree>
std::size_t compareRays(const Tree& other, double tolerance_m, std::size_t count, std::size_t& both_hit) {
  const datasets::TriangleBvh ours(scene().mesh);
  std::mt19937_64 rng(11);
  std::size_t disagreements = 0;
  both_hit = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d origin = randomPoint(scene().box, rng), direction = randomDirection(rng);
    const auto a = ours.firstHit(origin, direction, 40.0);
    const auto b = other.firstHit(origin, direction, 40.0);
    if (a.has_value() != b.has_value()) {
      // A miss on one side is only acceptable at the very end of the range (rounding of 40 m).
      const double d = a ? a->distance : b->distance;
      if (std::abs(d - 40.0) > tolerance_m) ++disagreements;
      continue;
    }
    if (!a) continue;
    ++both_hit;
    EXPECT_NEAR(a->distance, b->distance, tolerance_m) << "ray " << i;
  }
  return disagreements;
}

template <class Tree>
void compareClosest(const Tree& other, double tolerance_m) {
  const datasets::TriangleBvh ours(scene().mesh);
  std::mt19937_64 rng(12);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d q = randomPoint(scene().box, rng);
    EXPECT_NEAR(ours.closestPoint(q).distance, other.closestPoint(q).distance, tolerance_m) << "query " << i;
  }
}

TEST(SpatialBackendsTest, ClosestPointOnTriangleMatchesBruteForceSampling) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 1, 0);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 3.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(unit(rng), unit(rng), unit(rng));
    const double distance = (closestPointOnTriangle(p, a, b, c) - p).norm();
    double best = 1e300;
    for (int s = 0; s <= 200; ++s) {
      for (int t = 0; s + t <= 200; ++t) best = std::min(best, (a + s / 200.0 * (b - a) + t / 200.0 * (c - a) - p).norm());
    }
    EXPECT_LE(distance, best + 1e-12);
    EXPECT_GE(distance, best - 0.02);  // the sampling grid is 1/100 m
  }
}

TEST(SpatialBackendsTest, CgalAabbTreeAgreesWithOurBvh) {
  const CgalTriangleTree cgal(scene().mesh);
  std::size_t both_hit = 0;
  EXPECT_EQ(compareRays(cgal, 1e-7, 3000, both_hit), 0u);
  EXPECT_GT(both_hit, 300u);
  compareClosest(cgal, 1e-9);
}

#ifdef TERRAMESH_HAVE_EMBREE
TEST(SpatialBackendsTest, EmbreeAgreesWithOurBvh) {
  const EmbreeTriangleScene embree(scene().mesh);
  std::size_t both_hit = 0;
  EXPECT_LE(compareRays(embree, 1e-3, 3000, both_hit), 3u);
  EXPECT_GT(both_hit, 300u);
  compareClosest(embree, 1e-9);
}
#endif

TEST(SpatialBackendsTest, NanoflannFindsTheSameNearestPoints) {
  std::mt19937_64 rng(13);
  const Eigen::AlignedBox3d box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(20, 20, 5));
  std::vector<Eigen::Vector3d> cloud;
  for (int i = 0; i < 20000; ++i) cloud.push_back(randomPoint(box, rng));
  const datasets::PointCloudIndex ours(cloud, 0.5);
  const NanoflannCloud flann(cloud);
  std::size_t found = 0;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector3d q = randomPoint(Eigen::AlignedBox3d(Eigen::Vector3d(-2, -2, -2), Eigen::Vector3d(22, 22, 7)), rng);
    const auto a = ours.nearest(q, 1.0);
    const auto b = flann.nearest(q, 1.0);
    ASSERT_EQ(a.has_value(), b.has_value()) << "query " << i;
    if (!a) continue;
    ++found;
    EXPECT_EQ(a->distance, b->distance) << "query " << i;
  }
  EXPECT_GT(found, 1000u);
}

}  // namespace
}  // namespace terramesh::bench
