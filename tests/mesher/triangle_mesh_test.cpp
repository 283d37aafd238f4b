#include <gtest/gtest.h>

#include "mesher/triangle_mesh.h"

namespace terramesh::mesher {
namespace {

TriangleMesh tetrahedron() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  mesh.is_steiner = {0, 0, 0, 1};
  return mesh;
}

TEST(TriangleMeshTopology, TetrahedronIsClosedSphere) {
  const MeshTopology t = analyzeTopology(tetrahedron());
  EXPECT_TRUE(t.isClosedManifold());
  EXPECT_EQ(t.vertices, 4u);
  EXPECT_EQ(t.edges, 6u);
  EXPECT_EQ(t.euler_characteristic, 2);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.total_genus, 0);
}

TEST(TriangleMeshTopology, FlippedFaceIsAnOrientationError) {
  TriangleMesh mesh = tetrahedron();
  std::swap(mesh.faces[0][1], mesh.faces[0][2]);
  const MeshTopology t = analyzeTopology(mesh);
  EXPECT_GT(t.orientation_errors, 0u);
  EXPECT_FALSE(t.isClosedManifold());
}

TEST(TriangleMeshTopology, TwoTetrahedraTouchingAtAVertexAreNotManifold) {
  TriangleMesh mesh = tetrahedron();
  const TriangleMesh second = tetrahedron();
  // Second copy shares vertex 0 only.
  const std::uint32_t base = static_cast<std::uint32_t>(mesh.vertices.size());
  for (std::size_t i = 1; i < 4; ++i) mesh.vertices.push_back(-second.vertices[i]);
  auto map = [base](std::uint32_t v) { return v == 0 ? 0u : base + v - 1; };
  for (const auto& f : second.faces) mesh.faces.push_back({map(f[0]), map(f[2]), map(f[1])});
  const MeshTopology t = analyzeTopology(mesh);
  EXPECT_EQ(t.non_manifold_vertices, 1u);
  EXPECT_EQ(t.components, 1u);
}

TEST(TriangleMeshTopology, TorusHasGenusOne) {
  // A 4x4 quad torus, triangulated.
  TriangleMesh mesh;
  const int n = 4;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) mesh.vertices.emplace_back(i, j, 0);
  }
  auto id = [n](int i, int j) { return static_cast<std::uint32_t>(((i + n) % n) * n + (j + n) % n); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      mesh.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  const MeshTopology t = analyzeTopology(mesh);
  EXPECT_TRUE(t.isClosedManifold());
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_EQ(t.total_genus, 1);
}

TEST(DropSteinerFaces, KeepsOnlyFacesWithoutSteinerVertices) {
  const TriangleMesh open = dropSteinerFaces(tetrahedron());
  ASSERT_EQ(open.faces.size(), 1u);  // only {0, 2, 1} avoids vertex 3
  EXPECT_EQ(open.vertices.size(), 3u);
  const MeshTopology t = analyzeTopology(open);
  EXPECT_EQ(t.boundary_edges, 3u);
}

TEST(DropSteinerFaces, RejectsMissingFlags) {
  TriangleMesh mesh = tetrahedron();
  mesh.is_steiner.clear();
  EXPECT_THROW(dropSteinerFaces(mesh), std::invalid_argument);
}

TEST(SelectFaces, KeepsFlaggedFacesWithTheirArraysAndRenumbersVertices) {
  TriangleMesh mesh = tetrahedron();
  mesh.face_rays = {10, 11, 12, 13};
  mesh.face_front_crossings = {1, 2, 3, 4};
  mesh.face_back_crossings = {0, 5, 6, 0};
  mesh.face_back_depth = {0, 0.5, 0.6, 0};
  const TriangleMesh selected = selectFaces(mesh, {0, 1, 0, 1});
  ASSERT_EQ(selected.faces.size(), 2u);
  EXPECT_EQ(selected.face_rays, (std::vector<std::uint32_t>{11, 13}));
  EXPECT_EQ(selected.face_front_crossings, (std::vector<std::uint32_t>{2, 4}));
  EXPECT_EQ(selected.face_back_crossings, (std::vector<std::uint32_t>{5, 0}));
  EXPECT_EQ(selected.face_back_depth, (std::vector<double>{0.5, 0}));
  // Faces {0, 1, 3} and {0, 3, 2} use all four vertices, numbered by first use: 0, 1, 3, 2.
  ASSERT_EQ(selected.vertices.size(), 4u);
  EXPECT_EQ(selected.vertices[2], mesh.vertices[3]);
  EXPECT_EQ(selected.is_steiner, (std::vector<std::uint8_t>{0, 0, 1, 0}));
  for (std::size_t f = 0; f < selected.faces.size(); ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(selected.vertices[selected.faces[f][k]], mesh.vertices[mesh.faces[2 * f + 1][k]]);
    }
  }
  EXPECT_TRUE(selectFaces(mesh, {0, 0, 0, 0}).vertices.empty());
  EXPECT_THROW(selectFaces(mesh, {1, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::mesher
