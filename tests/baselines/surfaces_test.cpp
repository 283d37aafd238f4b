// The baselines' surfaces and measures against analytic truth: voxel faces of known voxel sets,
// manifoldness of meshes of known topology, PCL reconstructions of planes with normals turned to
// each point's own camera, the eval measures and the planning pairs.
#include <gtest/gtest.h>

#include <cmath>

#include "baselines/pcl_surfaces.h"
#include "baselines/surface_measures.h"
#include "baselines/voxel_surface.h"
#include "common/input_error.h"
#include "test_support/temp_dir.h"

namespace terramesh::baselines {
namespace {

mesher::Keyframe keyframe(std::uint64_t id, const Eigen::Vector3d& centre, const std::vector<Eigen::Vector3d>& points,
                          std::uint64_t first_point = 1) {
  mesher::Keyframe k;
  k.id.value = id;
  k.position_W_C = centre;
  for (std::size_t i = 0; i < points.size(); ++i) k.observations.push_back({mesher::PointId{first_point + i}, points[i]});
  return k;
}

Eigen::Vector3d normal(const mesher::TriangleMesh& mesh, std::size_t f) {
  const auto& t = mesh.faces[f];
  return (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).normalized();
}

TEST(VoxelSurface, OneOccupiedVoxelIsAClosedCube) {
  test::TempDir dir;
  datasets::SlamStream stream;
  // One ray ending in the middle of voxel (2, 0, 0) of a 0.5 m tree: that voxel is occupied.
  stream.events.push_back(keyframe(1, {-3.1, 0.2, 0.2}, {{1.2, 0.2, 0.2}}));
  const OctomapFrame frame;  // z up, metres
  const OctomapBuild build = buildOctomap(stream, 0.5, -1, frame, dir / "one.bt");
  EXPECT_EQ(build.occupied_leaves, 1u);
  const mesher::TriangleMesh cube = voxelSurfaceFromBt(dir / "one.bt", frame);
  ASSERT_EQ(cube.faces.size(), 12u);
  ASSERT_EQ(cube.vertices.size(), 8u);
  for (const Eigen::Vector3d& v : cube.vertices) {
    EXPECT_TRUE(std::abs(v.x() - 1.0) < 1e-9 || std::abs(v.x() - 1.5) < 1e-9) << v.transpose();
    EXPECT_TRUE(std::abs(v.y()) < 1e-9 || std::abs(v.y() - 0.5) < 1e-9) << v.transpose();
  }
  const Manifoldness m = measureManifoldness(cube);
  EXPECT_EQ(m.boundary_edges, 0u);
  EXPECT_EQ(m.non_manifold_edges, 0u);
  EXPECT_EQ(m.orientation_errors, 0u);
  EXPECT_EQ(m.genus, 0);
  // Outward normals: each face's normal points away from the voxel centre.
  const Eigen::Vector3d centre(1.25, 0.25, 0.25);
  for (std::size_t f = 0; f < cube.faces.size(); ++f) {
    EXPECT_GT(normal(cube, f).dot(cube.vertices[cube.faces[f][0]] - centre), 0) << f;
  }
}

TEST(VoxelSurface, TwoVoxelsTouchingAtAnEdgeShareItAsNonManifold) {
  test::TempDir dir;
  datasets::SlamStream stream;
  stream.events.push_back(keyframe(1, {0.25, 0.25, 5.1}, {{0.25, 0.25, 0.25}, {0.75, 0.25, 0.75}}));
  const OctomapFrame frame;
  buildOctomap(stream, 0.5, -1, frame, dir / "two.bt");
  const mesher::TriangleMesh surface = voxelSurfaceFromBt(dir / "two.bt", frame);
  ASSERT_EQ(surface.faces.size(), 24u);  // two cubes: no face shared
  const Manifoldness m = measureManifoldness(surface);
  EXPECT_EQ(m.non_manifold_edges, 1u);  // the edge at x = 0.5, z = 0.5
  EXPECT_EQ(m.components, 1u);
  // In a frame where up is +y, the same octree comes back rotated: z of the tree is y of the map.
  const OctomapFrame y_up{Eigen::Vector3d::UnitY(), 2.0};
  const mesher::TriangleMesh turned = voxelSurfaceFromBt(dir / "two.bt", y_up);
  const Eigen::Matrix3d R = y_up.rotation_G_W();
  for (std::size_t v = 0; v < turned.vertices.size(); ++v) {
    EXPECT_LT((R * turned.vertices[v] * 2.0 - surface.vertices[v]).norm(), 1e-9);
  }
  EXPECT_THROW(voxelSurfaceFromBt(dir / "missing.bt", frame), InputError);
}

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

TEST(WeldVertices, SoupBecomesIndexed) {
  mesher::TriangleMesh soup;
  soup.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 1e-9}};
  soup.faces = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_EQ(weldVertices(soup).vertices.size(), 5u);
  const mesher::TriangleMesh welded = weldVertices(soup, 1e-6);
  EXPECT_EQ(welded.vertices.size(), 4u);
  EXPECT_EQ(measureManifoldness(welded).boundary_loops, 1u);
  EXPECT_THROW(weldVertices(soup, -1), std::invalid_argument);
}

/// Two parallel walls x = 0 and x = 2 (y, z in [0, 4]) on a jittered 0.2 m lattice, each point
/// seen from a camera between them, at x = 1: every normal must point into the corridor, which
/// one global viewpoint outside (or on one side) cannot give.
SlamPoints corridor() {
  SlamPoints points;
  std::uint64_t id = 1;
  for (const double wall : {0.0, 2.0}) {
    for (int i = 0; i <= 20; ++i) {
      for (int j = 0; j <= 20; ++j) {
        const double jitter = 0.013 * std::sin(7.0 * i + 3.0 * j);
        points.ids.push_back(mesher::PointId{id++});
        points.positions_W.emplace_back(wall, 0.2 * i + jitter, 0.2 * j - jitter);
        points.viewpoints_W.emplace_back(1.0, 0.2 * i, 2.0);
        points.views.push_back(2);
      }
    }
  }
  return points;
}

TEST(PclSurfaces, GreedyProjectionFacesLookAtTheirOwnCameras) {
  const SlamPoints points = corridor();
  EXPECT_NEAR(medianPointSpacing(points.positions_W), 0.2, 0.03);
  const PclSurfaceResult result = reconstructWithPcl(points, PclMethod::kGreedyProjection, {});
  const mesher::TriangleMesh& mesh = result.mesh;
  ASSERT_GT(mesh.faces.size(), 600u);  // 2 x 400 lattice cells, 2 triangles each, most of them
  std::size_t into_corridor = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const double x = mesh.vertices[mesh.faces[f][0]].x();
    const Eigen::Vector3d n = normal(mesh, f);
    EXPECT_LT(std::abs(n.x()), 1.01);
    into_corridor += (x < 1.0 ? n.x() > 0.9 : n.x() < -0.9) ? 1 : 0;
  }
  EXPECT_EQ(into_corridor, mesh.faces.size());
  for (const std::uint8_t flag : mesh.is_steiner) EXPECT_EQ(flag, 0);  // every vertex is an input point
  EXPECT_NE(result.parameters.find("search radius"), std::string::npos);
}

TEST(PclSurfaces, PoissonAndMarchingCubesStayNearAPlane) {
  // Gently rolling ground z = 0.25 sin(x) cos(y) (6 x 6 m) seen from cameras 1.5 m above it. (Not
  // a plane: marching cubes' grid spans the points' bounding box, which a plane makes flat.)
  SlamPoints points;
  for (int i = 0; i <= 30; ++i) {
    for (int j = 0; j <= 30; ++j) {
      points.ids.push_back(mesher::PointId{static_cast<std::uint64_t>(i * 31 + j + 1)});
      const double x = 0.2 * i + 0.01 * std::sin(5.0 * j), y = 0.2 * j;
      points.positions_W.emplace_back(x, y, 0.25 * std::sin(x) * std::cos(y));
      points.viewpoints_W.emplace_back(0.2 * i, 0.2 * j, 1.5);
      points.views.push_back(2);
    }
  }
  for (const PclMethod method : {PclMethod::kPoisson, PclMethod::kMarchingCubesHoppe}) {
    SCOPED_TRACE(toString(method));
    // Cells of half a spacing: the 0.5 m thin box gets 5 cells (PCL skips the grid's outer layer).
    PclSurfaceConfig config;
    config.mc_cell_spacings = 0.5;
    const PclSurfaceResult result = reconstructWithPcl(points, method, config);
    const mesher::TriangleMesh& mesh = result.mesh;
    ASSERT_FALSE(mesh.faces.empty());
    // Supported vertices (within 3 spacings of a point) lie near the ground, and faces there look up.
    std::size_t supported = 0, up = 0, near_faces = 0;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (mesh.is_steiner[v]) continue;
      ++supported;
      const Eigen::Vector3d& p = mesh.vertices[v];
      EXPECT_LT(std::abs(p.z() - 0.25 * std::sin(p.x()) * std::cos(p.y())), 0.6) << p.transpose();
    }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& t = mesh.faces[f];
      if (mesh.is_steiner[t[0]] || mesh.is_steiner[t[1]] || mesh.is_steiner[t[2]]) continue;
      const Eigen::Vector3d& p = mesh.vertices[t[0]];
      if (std::abs(p.z() - 0.25 * std::sin(p.x()) * std::cos(p.y())) > 0.1) continue;
      ++near_faces;
      up += normal(mesh, f).z() > 0.5 ? 1 : 0;
    }
    EXPECT_GT(supported, 100u);
    EXPECT_GT(near_faces, 100u);
    EXPECT_GT(static_cast<double>(up), 0.9 * static_cast<double>(near_faces));
  }
  PclSurfaceConfig bad;
  bad.poisson_depth = 1;
  bad.greedy_mu = -1;
  try {
    bad.validate();
    FAIL() << "expected invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("poisson_depth"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("greedy_mu"), std::string::npos);
  }
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
  std::vector<datasets::EvaluationView> views;
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
}  // namespace terramesh::baselines
