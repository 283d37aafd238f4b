// The surface measures against analytic truth: manifoldness of meshes of known topology, and the
// geometry scores of a surface against itself and a shifted copy.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "evaluation/geometry_truth.h"
#include "evaluation/manifoldness.h"

namespace terramesh::evaluation {
namespace {

mesher::TriangleMesh tetrahedron(const Eigen::Vector3d& offset, std::uint32_t first) {
  mesher::TriangleMesh mesh;
  mesh.vertices = {offset, offset + Eigen::Vector3d::UnitX(), offset + Eigen::Vector3d::UnitY(),
                   offset + Eigen::Vector3d::UnitZ()};
  mesh.faces = {{first + 0, first + 2, first + 1}, {first + 0, first + 1, first + 3}, {first + 0, first + 3, first + 2},
                {first + 1, first + 2, first + 3}};
  return mesh;
}

/// An n x m grid on a torus (wrapping in both directions): genus 1.
mesher::TriangleMesh torus(int n, int m) {
  mesher::TriangleMesh mesh;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      mesh.vertices.emplace_back((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      mesh.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return mesh;
}

TEST(Manifoldness, KnownTopologies) {
  const Manifoldness closed = measureManifoldness(tetrahedron({0, 0, 0}, 0));
  EXPECT_EQ(closed.boundary_loops, 0u);
  EXPECT_EQ(closed.genus, 0);
  EXPECT_EQ(closed.components, 1u);

  const Manifoldness ring = measureManifoldness(torus(8, 6));
  EXPECT_EQ(ring.genus, 1);
  EXPECT_EQ(ring.boundary_loops, 0u);

  // A tetrahedron with one face removed: a disc, one boundary loop, genus 0.
  mesher::TriangleMesh open = tetrahedron({0, 0, 0}, 0);
  open.faces.pop_back();
  const Manifoldness disc = measureManifoldness(open);
  EXPECT_EQ(disc.boundary_loops, 1u);
  EXPECT_EQ(disc.boundary_edges, 3u);
  EXPECT_EQ(disc.genus, 0);

  // A torus with two faces cut at opposite places: two holes, still genus 1.
  mesher::TriangleMesh holed = torus(8, 6);
  holed.faces.erase(holed.faces.begin() + 40);
  holed.faces.erase(holed.faces.begin() + 2);
  const Manifoldness two_holes = measureManifoldness(holed);
  EXPECT_EQ(two_holes.boundary_loops, 2u);
  EXPECT_EQ(two_holes.genus, 1);

  // Two tetrahedra sharing one vertex (0): one non-manifold vertex, two fans.
  mesher::TriangleMesh pinched = tetrahedron({0, 0, 0}, 0);
  pinched.vertices.push_back({-1, 0, 0});
  pinched.vertices.push_back({0, -1, 0});
  pinched.vertices.push_back({0, 0, -1});
  pinched.faces.push_back({0, 4, 5});
  pinched.faces.push_back({0, 5, 6});
  pinched.faces.push_back({0, 6, 4});
  pinched.faces.push_back({4, 6, 5});
  const Manifoldness bow = measureManifoldness(pinched);
  EXPECT_EQ(bow.non_manifold_vertices, 1u);
  EXPECT_EQ(bow.components, 1u);
  EXPECT_EQ(bow.boundary_loops, 0u);
}

mesher::TriangleMesh flatSquare(double size, int cells) {
  mesher::TriangleMesh mesh;
  for (int i = 0; i <= cells; ++i) {
    for (int j = 0; j <= cells; ++j) mesh.vertices.emplace_back(size * i / cells, size * j / cells, 0);
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i * (cells + 1) + j); };
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      mesh.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return mesh;
}

TEST(GeometryTruth, ASurfaceAgainstItselfAndAgainstAShiftedCopy) {
  const mesher::TriangleMesh floor = flatSquare(20, 10);
  // Two views 1.6 m above the floor looking along +x and slightly down (camera y down, z forward).
  std::vector<EvaluationView> views;
  Eigen::Matrix3d R_W_C;
  R_W_C.col(0) = Eigen::Vector3d(0, -1, 0);
  R_W_C.col(2) = Eigen::Vector3d(1, 0, -0.3).normalized();
  R_W_C.col(1) = R_W_C.col(2).cross(R_W_C.col(0));
  views.push_back({{1, 10, 1.6}, Eigen::Quaterniond(R_W_C)});
  GeometryTruthConfig config;
  config.samples = 5000;
  config.depth.stride_px = 16;
  const GeometryTruth truth = GeometryTruth::fromMesh(floor, views, config);
  ASSERT_GT(truth.truthRays(), 100u);
  const GeometryScores same = truth.score(floor);
  EXPECT_NEAR(same.accuracy.median_m, 0, 1e-9);
  EXPECT_NEAR(same.completeness.median_m, 0, 1e-9);
  EXPECT_NEAR(same.depth.coverage(), 1.0, 1e-9);
  mesher::TriangleMesh raised = floor;
  for (Eigen::Vector3d& v : raised.vertices) v.z() += 0.2;
  const GeometryScores shifted = truth.score(raised);
  EXPECT_NEAR(shifted.accuracy.median_m, 0.2, 1e-6);
  EXPECT_NEAR(shifted.completeness.median_m, 0.2, 1e-6);
  // Steiner-flagged vertices take their faces out of the accuracy samples.
  raised.is_steiner.assign(raised.vertices.size(), 1);
  EXPECT_EQ(truth.score(raised).measured_faces, 0u);
}

}  // namespace
}  // namespace terramesh::evaluation
