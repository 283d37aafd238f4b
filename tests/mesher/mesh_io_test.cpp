#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "common/input_error.h"
#include "mesher/mesh_io.h"

namespace terramesh::mesher {
namespace {

namespace fs = std::filesystem;

class MeshIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("terramesh_mesh_io_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static TriangleMesh sample() {
    TriangleMesh mesh;
    mesh.vertices = {{0.1, 0.2, 0.3}, {1e6, -2.5, 3}, {0, 1, 0}, {0, 0, 1}};
    mesh.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    mesh.is_steiner = {0, 1, 0, 1};
    return mesh;
  }

  /// What readMesh(file) throws; an empty message (and a failure) if it reads the file.
  static std::string readError(const fs::path& file, std::string* where = nullptr) {
    try {
      readMesh(file);
    } catch (const InputError& error) {
      if (where) *where = error.where();
      return error.what();
    }
    ADD_FAILURE() << "expected an InputError for " << file;
    return "";
  }

  fs::path dir_;
};

TEST_F(MeshIoTest, PlyRoundTripKeepsPositionsFacesAndSteinerFlags) {
  const TriangleMesh mesh = sample();
  writePly(dir_ / "m.ply", mesh);
  const TriangleMesh read = readMesh(dir_ / "m.ply");
  ASSERT_EQ(read.vertices.size(), mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) EXPECT_EQ(read.vertices[i], mesh.vertices[i]);
  EXPECT_EQ(read.faces, mesh.faces);
  EXPECT_EQ(read.is_steiner, mesh.is_steiner);
}

TEST_F(MeshIoTest, PlyRoundTripKeepsTheFacesObservation) {
  TriangleMesh mesh = sample();
  mesh.face_rays = {7, 0, 3, 12};
  mesh.face_front_crossings = {2, 0, 3, 5};
  mesh.face_view_sides = {view_side::kFront, 0, view_side::kBehind, view_side::kFront | view_side::kBehind};
  mesh.face_back_crossings = {0, 4, 0, 1};
  mesh.face_back_depth = {0, 0.4123456789012345, 0, 1e-3};
  writePly(dir_ / "m.ply", mesh);
  const TriangleMesh read = readMesh(dir_ / "m.ply");
  EXPECT_EQ(read.face_rays, mesh.face_rays);
  EXPECT_EQ(read.face_front_crossings, mesh.face_front_crossings);
  EXPECT_EQ(read.face_view_sides, mesh.face_view_sides);
  EXPECT_EQ(read.face_back_crossings, mesh.face_back_crossings);
  EXPECT_EQ(read.face_back_depth, mesh.face_back_depth);
}

TEST_F(MeshIoTest, ABadFaceObservationNamesTheFaceAndTheProperty) {
  // Three vertices and two faces with the given face properties; the second face's values are bad.
  const auto expectNamed = [&](const std::string& properties, const std::string& faces, const std::string& property) {
    std::ofstream(dir_ / "bad.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 2\n"
                                       "property list uchar int vertex_indices\n"
                                    << properties << "end_header\n0 0 0\n1 0 0\n1 1 0\n" << faces;
    std::string where;
    const std::string message = readError(dir_ / "bad.ply", &where);
    EXPECT_EQ(where, "face 1") << property;
    EXPECT_NE(message.find(property), std::string::npos) << message;
  };
  // A view_sides value outside its bits.
  expectNamed("property uchar view_sides\n", "3 0 1 2 3\n3 0 2 1 4\n", "view_sides");
  // A negative depth behind the face.
  expectNamed("property uint back_crossings\nproperty double back_depth\n", "3 0 1 2 0 0\n3 0 2 1 3 -0.5\n",
              "back_depth");
}

TEST_F(MeshIoTest, ObjRoundTrip) {
  const TriangleMesh mesh = sample();
  writeObj(dir_ / "m.obj", mesh);
  const TriangleMesh read = readMesh(dir_ / "m.obj");
  EXPECT_EQ(read.faces, mesh.faces);
  ASSERT_EQ(read.vertices.size(), 4u);
  EXPECT_DOUBLE_EQ(read.vertices[1].x(), 1e6);
}

TEST_F(MeshIoTest, TruncatedPlyNamesFileAndElement) {
  writePly(dir_ / "m.ply", sample());
  const auto size = fs::file_size(dir_ / "m.ply");
  fs::resize_file(dir_ / "m.ply", size - 5);
  try {
    readMesh(dir_ / "m.ply");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), (dir_ / "m.ply").string());
    EXPECT_NE(error.where().find("face"), std::string::npos) << error.what();
  }
}

TEST_F(MeshIoTest, OutOfRangeIndexIsAnError) {
  std::ofstream(dir_ / "bad.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
  EXPECT_THROW(readMesh(dir_ / "bad.off"), InputError);
}

TEST_F(MeshIoTest, AnAsciiListCountTooLargeForAnyListIsAnError) {
  std::ofstream(dir_ / "count.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 1\n"
                                       "property list uchar int vertex_indices\nend_header\n"
                                       "0 0 0\n1 0 0\n1 1 0\n1.66667e+111 0 1 2\n";
  const std::string message = readError(dir_ / "count.ply");
  EXPECT_NE(message.find("count above"), std::string::npos) << message;
}

TEST_F(MeshIoTest, MissingFileIsAnError) {
  EXPECT_THROW(readMesh(dir_ / "absent.ply"), InputError);
}

TEST_F(MeshIoTest, ReadsTheAuthorsReferenceOff) {
  const fs::path reference = fs::path(TERRAMESH_SHARED_DIR) / "data/kitti00_orbslam/reference_meshes" /
                             "KITTI_200frames_D=100_Step=40_ManifoldFinal.off";
  const TriangleMesh mesh = readMesh(reference);
  EXPECT_GT(mesh.faces.size(), 1000u);
  const MeshTopology t = analyzeTopology(mesh);
  EXPECT_EQ(t.non_manifold_edges, 0u);
}

}  // namespace
}  // namespace terramesh::mesher
