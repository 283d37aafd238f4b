// The baselines' surfaces against analytic truth: voxel faces of known voxel sets, welded triangle
// soups, PCL reconstructions of planes with normals turned to each point's own camera.
#include <gtest/gtest.h>

#include <cmath>

#include "baselines/pcl_surfaces.h"
#include "baselines/voxel_surface.h"
#include "baselines/weld_vertices.h"
#include "common/input_error.h"
#include "evaluation/manifoldness.h"
#include "test_support/temp_dir.h"

namespace terramesh::baselines {
namespace {

using evaluation::Manifoldness;
using evaluation::measureManifoldness;

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

}  // namespace
}  // namespace terramesh::baselines
