// Conversions to and from PCL: mesh -> pcl::PolygonMesh -> mesh is the identity (on coordinates a
// float represents exactly), and the PCDs we write are read back by PCL's own reader.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "baselines/pcl_io.h"
#include "common/input_error.h"
#include "baselines/slam_points.h"
#include "mesher/mesh_io.h"
#include "test_support/temp_dir.h"

namespace terramesh::baselines {
namespace {

/// An irregular closed mesh (octahedron with a refined face) on coordinates exactly
/// representable as float, with Steiner flags.
mesher::TriangleMesh floatExactMesh() {
  mesher::TriangleMesh mesh;
  mesh.vertices = {{1.5, 0, 0}, {-1.25, 0, 0}, {0, 2.0, 0}, {0, -0.75, 0}, {0, 0, 3.5}, {0, 0, -1.125}, {0.5, 0.5, 0.5}};
  mesh.faces = {{0, 2, 6}, {2, 4, 6}, {4, 0, 6}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  mesh.is_steiner = {0, 0, 1, 0, 0, 1, 0};
  return mesh;
}

void expectSameGeometry(const mesher::TriangleMesh& a, const mesher::TriangleMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t v = 0; v < a.vertices.size(); ++v) EXPECT_EQ(a.vertices[v], b.vertices[v]) << "vertex " << v;
  for (std::size_t f = 0; f < a.faces.size(); ++f) EXPECT_EQ(a.faces[f], b.faces[f]) << "face " << f;
}

TEST(PclMeshRoundTrip, PlyAndObjGiveTheSameMeshBack) {
  test::TempDir dir;
  const mesher::TriangleMesh mesh = floatExactMesh();
  for (const char* name : {"mesh.ply", "mesh.obj"}) {
    writeMeshWithPcl(dir / name, mesh);
    const mesher::TriangleMesh back = readMeshWithPcl(dir / name);
    SCOPED_TRACE(name);
    expectSameGeometry(mesh, back);
    EXPECT_TRUE(back.is_steiner.empty());  // PCL's writers carry positions and faces only
  }
}

TEST(PclMeshRoundTrip, OurReaderReadsWhatPclWrote) {
  test::TempDir dir;
  const mesher::TriangleMesh mesh = floatExactMesh();
  writeMeshWithPcl(dir / "pcl.ply", mesh);
  expectSameGeometry(mesh, mesher::readMesh(dir / "pcl.ply"));
  // And PCL reads what we wrote (float64 vertices, a steiner property).
  mesher::writePly(dir / "ours.ply", mesh);
  expectSameGeometry(mesh, readMeshWithPcl(dir / "ours.ply"));
}

TEST(PclMeshRoundTrip, DoubleCoordinatesComeBackAsTheirFloatValues) {
  test::TempDir dir;
  mesher::TriangleMesh mesh = floatExactMesh();
  mesh.vertices[0] = {0.1, 1.0 / 3.0, 1234.5678901};
  writeMeshWithPcl(dir / "mesh.ply", mesh);
  const mesher::TriangleMesh back = readMeshWithPcl(dir / "mesh.ply");
  ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(back.vertices[0][a], static_cast<double>(static_cast<float>(mesh.vertices[0][a])));
  }
}

TEST(PclMeshRoundTrip, VtkFileListsEveryPointAndPolygon) {
  test::TempDir dir;
  const mesher::TriangleMesh mesh = floatExactMesh();
  writeMeshWithPcl(dir / "mesh.vtk", mesh);
  std::ifstream in(dir / "mesh.vtk");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("POINTS 7 float"), std::string::npos) << text.substr(0, 200);
  EXPECT_NE(text.find("POLYGONS 10 40"), std::string::npos);
  EXPECT_THROW(readMeshWithPcl(dir / "mesh.vtk"), std::invalid_argument);
  EXPECT_THROW(writeMeshWithPcl(dir / "mesh.stl", mesh), std::invalid_argument);
}

TEST(PclMeshRoundTrip, UnreadableFileIsAnInputError) {
  test::TempDir dir;
  std::ofstream(dir / "bad.ply") << "this is not a ply\n";
  EXPECT_THROW(readMeshWithPcl(dir / "bad.ply"), InputError);
  EXPECT_THROW(readMeshWithPcl(dir / "missing.ply"), InputError);
}

mesher::Keyframe keyframe(std::uint64_t id, const Eigen::Vector3d& centre,
                          const std::vector<std::pair<std::uint64_t, Eigen::Vector3d>>& points) {
  mesher::Keyframe k;
  k.id.value = id;
  k.position_W_C = centre;
  for (const auto& [point, position] : points) k.observations.push_back({mesher::PointId{point}, position});
  return k;
}

/// Three keyframes; point 1 seen by all, point 2 by two, point 3 by one, point 4 removed; keyframe
/// 2 re-sent with point 1 moved.
datasets::SlamStream smallStream() {
  datasets::SlamStream stream;
  stream.events.push_back(keyframe(1, {0, 0, 0}, {{1, {0, 0, 10}}, {2, {1, 0, 10}}, {4, {2, 0, 10}}}));
  stream.events.push_back(keyframe(2, {0, 0, 4}, {{1, {0, 0, 10}}, {2, {1, 0, 10}}, {3, {3, 0, 10}}, {4, {2, 0, 10}}}));
  stream.events.push_back(keyframe(3, {0, 0, 8}, {{1, {0, 0, 10}}}));
  stream.events.push_back(datasets::PointRemoval{{mesher::PointId{4}}});
  stream.events.push_back(keyframe(2, {0, 0, 5}, {{1, {0, 0.5, 10}}, {2, {1, 0, 10}}, {3, {3, 0, 10}}}));
  return stream;
}

TEST(SlamPoints, FinalStateWithOwnViewpoints) {
  SlamPointsConfig config;
  config.min_views = 2;
  const SlamPoints points = collectSlamPoints(smallStream(), config);
  ASSERT_EQ(points.size(), 2u);  // 3 is seen once, 4 was removed
  EXPECT_EQ(points.ids[0].value, 1u);
  EXPECT_EQ(points.positions_W[0], Eigen::Vector3d(0, 0.5, 10));  // the last position sent
  EXPECT_EQ(points.views[0], 3u);
  EXPECT_EQ(points.viewpoints_W[0], Eigen::Vector3d(0, 0, 8));  // the nearest observing camera
  EXPECT_EQ(points.ids[1].value, 2u);
  EXPECT_EQ(points.viewpoints_W[1], Eigen::Vector3d(0, 0, 5));  // keyframe 2's corrected pose
  config.min_views = 1;
  config.max_camera_distance_units = 6;  // keyframe 1 (10 away) no longer counts
  const SlamPoints near = collectSlamPoints(smallStream(), config);
  ASSERT_EQ(near.size(), 3u);
  EXPECT_EQ(near.views[0], 2u);
  config.min_views = 0;
  EXPECT_THROW(collectSlamPoints(smallStream(), config), std::invalid_argument);
}

TEST(SlamPointsPcd, PclReadsPointsAndTheirViewpoints) {
  test::TempDir dir;
  SlamPointsConfig config;
  config.min_views = 1;
  const SlamPoints points = collectSlamPoints(smallStream(), config);
  writeSlamPointsPcd(dir / "points.pcd", points, 2.0);
  const PcdContents pcd = readPcdWithPcl(dir / "points.pcd");
  ASSERT_EQ(pcd.values.size(), points.size());
  for (const char* name : {"x", "y", "z", "vp_x", "vp_y", "vp_z"}) ASSERT_GE(pcd.field(name), 0) << name;
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_FLOAT_EQ(pcd.values[i][static_cast<std::size_t>(pcd.field(std::string(1, "xyz"[a])))],
                      2.0 * points.positions_W[i][a]);
      EXPECT_FLOAT_EQ(pcd.values[i][static_cast<std::size_t>(pcd.field(std::string("vp_") + "xyz"[a]))],
                      2.0 * points.viewpoints_W[i][a]);
    }
  }
}

TEST(TraversabilityPcd, FaceCentroidsWithEveryLayer) {
  test::TempDir dir;
  traversability::LayeredMesh map;
  map.mesh.vertices = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {3, 3, 3}};
  map.mesh.faces = {{0, 1, 2}, {1, 3, 2}};
  map.layers.resize(2);
  map.layers[0].face_class = traversability::FaceClass::kFree;
  map.layers[0].cost = 0.25f;
  map.layers[0].slope_deg = 0;
  map.layers[0].rays = 7;
  map.layers[1].face_class = traversability::FaceClass::kLethal;
  map.layers[1].cost = 1;
  map.layers[1].slope_deg = 35.26f;
  map.layers[1].steiner = true;
  writeTraversabilityPcd(dir / "map.pcd", map);
  const PcdContents pcd = readPcdWithPcl(dir / "map.pcd");
  ASSERT_EQ(pcd.values.size(), 2u);
  for (const char* name : {"cost", "class", "slope_deg", "step_m", "roughness_m", "contact", "contact_best",
                           "clearance_m", "lethal_distance_m", "rays", "steiner"}) {
    ASSERT_GE(pcd.field(name), 0) << name;
  }
  auto at = [&](std::size_t i, const char* name) { return pcd.values[i][static_cast<std::size_t>(pcd.field(name))]; };
  EXPECT_FLOAT_EQ(at(0, "x"), 1);
  EXPECT_FLOAT_EQ(at(0, "y"), 1);
  EXPECT_FLOAT_EQ(at(1, "z"), 1);
  EXPECT_FLOAT_EQ(at(0, "cost"), 0.25);
  EXPECT_EQ(at(0, "class"), 0);
  EXPECT_EQ(at(1, "class"), 1);
  EXPECT_FLOAT_EQ(at(1, "slope_deg"), 35.26f);
  EXPECT_EQ(at(0, "rays"), 7);
  EXPECT_EQ(at(1, "steiner"), 1);
  EXPECT_TRUE(std::isinf(at(0, "clearance_m")));
  map.layers.pop_back();
  EXPECT_THROW(writeTraversabilityPcd(dir / "bad.pcd", map), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::baselines
