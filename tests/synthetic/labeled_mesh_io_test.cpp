#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/input_error.h"
#include "datasets/labeled_mesh.h"
#include "test_support/temp_dir.h"

namespace terramesh::datasets {
namespace {

namespace fs = std::filesystem;

LabeledMesh sample() {
  LabeledMesh mesh;
  mesh.mesh.vertices = {{0.1, 0.2, 0.3}, {1e6, -2.5, 3}, {0, 1, 0}, {0, 0, 1}};
  mesh.mesh.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}};
  mesh.labels = {SurfaceLabel::kRoad, SurfaceLabel::kCeiling, SurfaceLabel::kRamp};
  mesh.slope_deg = {0.5f, 180.0f, 8.25f};
  return mesh;
}

/// The InputError message of reading `path`, or "" if it reads.
std::string readError(const fs::path& path) {
  try {
    readLabeledPly(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(LabeledMeshIoTest, BinaryRoundTripIsExact) {
  test::TempDir dir;
  const LabeledMesh mesh = sample();
  writeLabeledPly(dir / "gt.ply", mesh);
  const LabeledMesh read = readLabeledPly(dir / "gt.ply");
  EXPECT_EQ(read.mesh.vertices, mesh.mesh.vertices);
  EXPECT_EQ(read.mesh.faces, mesh.mesh.faces);
  EXPECT_EQ(read.labels, mesh.labels);
  EXPECT_EQ(read.slope_deg, mesh.slope_deg);
  // Written atomically: nothing but the file is left in the directory.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(LabeledMeshIoTest, ReadsAsciiWithExtraProperties) {
  test::TempDir dir;
  std::ofstream(dir / "a.ply") << "ply\nformat ascii 1.0\ncomment by hand\nelement vertex 3\nproperty float x\n"
                                  "property float y\nproperty float z\nproperty uchar red\nelement face 1\n"
                                  "property list uchar int vertex_indices\nproperty float slope_deg\n"
                                  "property int label\nend_header\n0 0 0 9\n1 0 0 9\n0 1 0 9\n3 0 1 2 12.5 5\n";
  const LabeledMesh read = readLabeledPly(dir / "a.ply");
  ASSERT_EQ(read.mesh.faces.size(), 1u);
  EXPECT_EQ(read.labels[0], SurfaceLabel::kVegetation);
  EXPECT_FLOAT_EQ(read.slope_deg[0], 12.5f);
}

TEST(LabeledMeshIoTest, ErrorsNameTheFileAndTheElement) {
  test::TempDir dir;
  writeLabeledPly(dir / "gt.ply", sample());
  fs::resize_file(dir / "gt.ply", fs::file_size(dir / "gt.ply") - 3);
  const std::string truncated = readError(dir / "gt.ply");
  EXPECT_NE(truncated.find((dir / "gt.ply").string()), std::string::npos) << truncated;
  EXPECT_NE(truncated.find("face 2"), std::string::npos) << truncated;

  auto ascii = [&](const std::string& name, const std::string& faces, const std::string& face_properties) {
    std::ofstream(dir / name) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                                 "property double z\nelement face 2\nproperty list uchar uint vertex_indices\n"
                              << face_properties << "end_header\n0 0 0\n1 0 0\n0 1 0\n" << faces;
    return readError(dir / name);
  };
  const std::string both = "property uchar label\nproperty float slope_deg\n";
  EXPECT_NE(ascii("label.ply", "3 0 1 2 0 0\n3 0 1 2 9 0\n", both).find("face 1: label 9"), std::string::npos);
  EXPECT_NE(ascii("index.ply", "3 0 1 2 0 0\n3 0 1 5 0 0\n", both).find("face 1: vertex index 5"), std::string::npos);
  EXPECT_NE(ascii("quad.ply", "4 0 1 2 0 0 0\n", both).find("face 0: expected a triangle"), std::string::npos);
  EXPECT_NE(ascii("slope.ply", "3 0 1 2 0 0\n3 0 1 2 0 200\n", both).find("face 1: slope_deg"), std::string::npos);
  EXPECT_NE(ascii("nolabel.ply", "3 0 1 2 0\n3 0 1 2 0\n", "property float slope_deg\n").find("element face"),
            std::string::npos);
  std::ofstream(dir / "header.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nbogus line\nend_header\n";
  EXPECT_NE(readError(dir / "header.ply").find("line 4"), std::string::npos);
  std::ofstream(dir / "notply.ply") << "solid\n";
  EXPECT_NE(readError(dir / "notply.ply").find("line 1"), std::string::npos);
  EXPECT_NE(readError(dir / "missing.ply").find("missing.ply"), std::string::npos);
}

TEST(LabeledMeshIoTest, WriterRejectsMismatchedLayers) {
  test::TempDir dir;
  LabeledMesh mesh = sample();
  mesh.slope_deg.pop_back();
  EXPECT_THROW(writeLabeledPly(dir / "gt.ply", mesh), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "gt.ply"));
}

TEST(LabeledMeshIoTest, LabelNamesRoundTrip) {
  for (std::size_t i = 0; i < kSurfaceLabelCount; ++i) {
    const auto label = static_cast<SurfaceLabel>(i);
    EXPECT_EQ(parseSurfaceLabel(toString(label)), label);
  }
  EXPECT_FALSE(parseSurfaceLabel("lava").has_value());
}

}  // namespace
}  // namespace terramesh::datasets
