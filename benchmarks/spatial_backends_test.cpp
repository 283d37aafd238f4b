// CGAL's AABB_tree, compared in spatial_queries_benchmark.cpp, answers the same questions as the
// project's datasets::TriangleBvh (Embree with double-precision refinement): on random rays and
// points around a synthetic street both find the same first hits and the same closest surface
// distances, to double-precision rounding; a ray grazing an edge within float rounding may
// differ in hit/miss (TriangleBvh's documented tolerance).
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

TEST(SpatialBackendsTest, CgalAabbTreeAgreesWithTriangleBvh) {
  const datasets::TriangleBvh ours(scene().mesh);
  const CgalTriangleTree cgal(scene().mesh);
  std::mt19937_64 rng(11);
  std::size_t disagreements = 0, both_hit = 0;
  for (std::size_t i = 0; i < 3000; ++i) {
    const Eigen::Vector3d origin = randomPoint(scene().box, rng), direction = randomDirection(rng);
    const auto a = ours.firstHit(origin, direction, 40.0);
    const auto b = cgal.firstHit(origin, direction, 40.0);
    if (a.has_value() != b.has_value()) {
      // A miss on one side is only acceptable at the very end of the range (rounding of 40 m).
      const double d = a ? a->distance : b->distance;
      if (std::abs(d - 40.0) > 1e-7) ++disagreements;
      continue;
    }
    if (!a) continue;
    ++both_hit;
    EXPECT_NEAR(a->distance, b->distance, 1e-7) << "ray " << i;
  }
  EXPECT_EQ(disagreements, 0u);
  EXPECT_GT(both_hit, 300u);
  std::mt19937_64 points(12);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d q = randomPoint(scene().box, points);
    EXPECT_NEAR(ours.closestPoint(q).distance, cgal.closestPoint(q).distance, 1e-9) << "query " << i;
  }
}

}  // namespace
}  // namespace terramesh::bench
