#include "datasets/colmap_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "datasets/stream_reader.h"
#include "model_writers.h"
#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

namespace fs = std::filesystem;
using datasets::ColmapFileType;
using datasets::ColmapModel;

// The shared folders hold two different reconstructions of the same 40 photos (different commits
// of the source repository: different image ids, 1,816 vs 9,066 points), so text and binary are
// compared by converting each model into the other encoding.
const fs::path kTextModel = sharedData("colmap_statue_of_liberty/txt_model_40img");
const fs::path kBinaryModel = sharedData("colmap_statue_of_liberty/bin_model_40img");

/// Fraction of observations in front of their camera (positive depth along +z).
double fractionInFront(const datasets::SlamStream& stream) {
  std::size_t in_front = 0;
  std::size_t total = 0;
  for (const mesher::Keyframe& keyframe : keyframesOf(stream)) {
    for (const auto& observation : keyframe.observations) {
      const Eigen::Vector3d p_C =
          keyframe.rotation_W_C.conjugate() * (observation.position_W - keyframe.position_W_C);
      in_front += p_C.z() > 0 ? 1 : 0;
      ++total;
    }
  }
  return static_cast<double>(in_front) / static_cast<double>(total);
}

void expectSameModels(const ColmapModel& a, const ColmapModel& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (std::size_t c = 0; c < a.cameras.size(); ++c) {
    EXPECT_EQ(a.cameras[c].id, b.cameras[c].id);
    EXPECT_EQ(a.cameras[c].model, b.cameras[c].model);
    EXPECT_EQ(a.cameras[c].width_px, b.cameras[c].width_px);
    EXPECT_EQ(a.cameras[c].height_px, b.cameras[c].height_px);
    EXPECT_EQ(a.cameras[c].params, b.cameras[c].params);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (std::size_t i = 0; i < a.images.size(); ++i) {
    const auto& x = a.images[i];
    const auto& y = b.images[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.rotation_C_W.coeffs(), y.rotation_C_W.coeffs());
    EXPECT_EQ(x.translation_C_W, y.translation_C_W);
    EXPECT_EQ(x.camera_id, y.camera_id);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.points2D_px, y.points2D_px);
    EXPECT_EQ(x.point3D_ids, y.point3D_ids);
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t p = 0; p < a.points.size(); ++p) {
    EXPECT_EQ(a.points[p].id, b.points[p].id);
    EXPECT_EQ(a.points[p].position_W, b.points[p].position_W);
    EXPECT_EQ(a.points[p].rgb, b.points[p].rgb);
    EXPECT_EQ(a.points[p].error_px, b.points[p].error_px);
    EXPECT_EQ(a.points[p].track, b.points[p].track);
  }
}

TEST(ColmapReader, TextModelHasExactCounts) {
  const ColmapModel model = datasets::readColmapModel(kTextModel, ColmapFileType::kText);
  EXPECT_EQ(model.cameras.size(), 1u);
  EXPECT_EQ(model.cameras[0].model, "SIMPLE_RADIAL");
  EXPECT_EQ(model.cameras[0].params.size(), 4u);
  EXPECT_EQ(model.images.size(), 40u);
  EXPECT_EQ(model.points.size(), 1816u);

  const datasets::SlamStream stream = datasets::readColmapStream(kTextModel);
  // 7,760 2D-3D correspondences, 23 of which repeat a point already seen by the same image.
  EXPECT_EQ(countStream(stream), (StreamCounts{40, 40, 1816, 7737}));
  EXPECT_EQ(stream.keyframe_names.size(), 40u);
  EXPECT_EQ(stream.keyframe_names.at(mesher::KeyframeId{1}), "14268549464_8c6bd2338d_o.jpg");
  EXPECT_FALSE(stream.scale_known);

  const auto keyframes = keyframesOf(stream);
  for (std::size_t k = 1; k < keyframes.size(); ++k) {
    EXPECT_LT(keyframes[k - 1].id, keyframes[k].id) << "keyframes must come in image id order";
  }
  // Image 1: q = (0.842381 0.215061 0.44459 -0.215599), t = (-2.67344 3.07749 0.697147).
  const Eigen::Quaterniond q(0.842381, 0.215061, 0.44459, -0.215599);
  const Eigen::Vector3d expected_centre = -(q.normalized().toRotationMatrix().transpose() *
                                            Eigen::Vector3d(-2.67344, 3.07749, 0.697147));
  EXPECT_LT((keyframes[0].position_W_C - expected_centre).norm(), 1e-12);
  EXPECT_GT(fractionInFront(stream), 0.999);
}

TEST(ColmapReader, BinaryModelHasExactCounts) {
  const ColmapModel model = datasets::readColmapModel(kBinaryModel, ColmapFileType::kBinary);
  EXPECT_EQ(model.cameras.size(), 1u);
  EXPECT_EQ(model.images.size(), 40u);
  EXPECT_EQ(model.points.size(), 9066u);

  const datasets::SlamStream stream = datasets::readColmapStream(kBinaryModel);
  // 37,739 2D-3D correspondences, 619 of which repeat a point already seen by the same image.
  EXPECT_EQ(countStream(stream), (StreamCounts{40, 40, 9066, 37120}));
  EXPECT_GT(fractionInFront(stream), 0.999);
}

TEST(ColmapReader, FindsTheEncodingOfADirectory) {
  EXPECT_EQ(datasets::findColmapModel(kTextModel), ColmapFileType::kText);
  EXPECT_EQ(datasets::findColmapModel(kBinaryModel), ColmapFileType::kBinary);
  TempDir dir;
  EXPECT_FALSE(datasets::findColmapModel(dir.path()));
  const InputError error = expectInputError([&] { datasets::readColmapStream(dir.path()); });
  expectErrorAt(error, dir.path(), "", "not a COLMAP model");
}

/// Reads the model `source` in encoding `from`, writes it in the other one, and checks that the
/// copy reads back as the same model and the same stream, bit for bit.
void expectOtherEncodingReadsIdentically(const fs::path& source, ColmapFileType from) {
  TempDir dir;
  const ColmapFileType to =
      from == ColmapFileType::kText ? ColmapFileType::kBinary : ColmapFileType::kText;
  const ColmapModel original = datasets::readColmapModel(source, from);
  if (to == ColmapFileType::kBinary) {
    writeColmapBinary(dir.path(), original);
  } else {
    writeColmapText(dir.path(), original);
  }
  expectSameModels(original, datasets::readColmapModel(dir.path(), to));
  EXPECT_TRUE(sameStreams(datasets::readColmapStream(source, from),
                          datasets::readColmapStream(dir.path(), to)));
}

/// Files that COLMAP 3.12+ and its GUI leave beside a model: the project, the database, rigs and
/// frames (text and binary); none of them is needed to mesh.
void addNewerColmapFiles(const fs::path& directory) {
  writeFile(directory / "project.ini", "log_to_stderr=true\n[General]\ndatabase_path=database.db\n");
  writeFile(directory / "database.db", std::string("SQLite format 3\0", 16));
  writeFile(directory / "rigs.txt", "# Rig list with one line of data per rig:\n1 1 CAMERA 1\n");
  writeFile(directory / "frames.txt", "# Frame list with one line of data per frame:\n1 1 1 0 0 0 0 0 0 1 CAMERA 1 IMAGE 1\n");
  writeFile(directory / "rigs.bin", std::string(8, '\0'));
  writeFile(directory / "frames.bin", std::string(8, '\0'));
}

TEST(ColmapReader, ExtraFilesOfNewerColmapAreIgnored) {
  for (const fs::path& source : {kTextModel, kBinaryModel}) {
    TempDir dir;
    copyFiles(source, dir.path());
    addNewerColmapFiles(dir.path());
    EXPECT_EQ(datasets::detectStreamFormat(dir.path()), datasets::StreamFormat::kColmap);
    EXPECT_TRUE(sameStreams(datasets::readAnyStream(dir.path()), datasets::readColmapStream(source)))
        << source;
  }
}

TEST(ColmapReader, WorkspaceFolderLeadsToModelZero) {
  TempDir dir;
  copyFiles(kBinaryModel, dir / "sparse" / "0");
  copyFiles(kTextModel, dir / "sparse" / "1");
  addNewerColmapFiles(dir.path());
  const datasets::SlamStream expected = datasets::readColmapStream(kBinaryModel);
  for (const fs::path& path : {dir.path(), dir / "sparse"}) {
    EXPECT_EQ(datasets::findColmapModelDirectory(path), dir / "sparse" / "0") << path;
    EXPECT_EQ(datasets::detectStreamFormat(path), datasets::StreamFormat::kColmap) << path;
    EXPECT_TRUE(sameStreams(datasets::readAnyStream(path), expected)) << path;
  }
  // Asked for text: model 1 is not among the places looked at, but can be named.
  EXPECT_EQ(datasets::findColmapModelDirectory(dir.path(), ColmapFileType::kText),
            std::nullopt);
  EXPECT_EQ(datasets::findColmapModelDirectory(dir / "sparse" / "1", ColmapFileType::kText),
            dir / "sparse" / "1");
  EXPECT_EQ(datasets::findColmapModelDirectory(dir / "sparse" / "1" / "missing"), std::nullopt);
}

TEST(ColmapReader, TextModelWrittenAsBinaryReadsIdentically) {
  expectOtherEncodingReadsIdentically(kTextModel, ColmapFileType::kText);
}

TEST(ColmapReader, BinaryModelWrittenAsTextReadsIdentically) {
  expectOtherEncodingReadsIdentically(kBinaryModel, ColmapFileType::kBinary);
}

TEST(ColmapReader, ImageWithoutPointsHasABlankPointsLine) {
  TempDir dir;
  ColmapModel model = datasets::readColmapModel(kTextModel, ColmapFileType::kText);
  model.images[3].points2D_px.clear();
  model.images[3].point3D_ids.clear();
  writeColmapText(dir.path(), model);
  const datasets::SlamStream stream = datasets::readColmapStream(dir.path());
  EXPECT_EQ(countStream(stream).keyframe_events, 40u);
}

class ColmapCorruptBinaryTest : public ::testing::Test {
 protected:
  void SetUp() override { copyFiles(kBinaryModel, dir_.path()); }
  InputError read() {
    return expectInputError(
        [&] { datasets::readColmapModel(dir_.path(), ColmapFileType::kBinary); });
  }
  TempDir dir_;
};

TEST_F(ColmapCorruptBinaryTest, TruncatedImagesNameTheByteAndImage) {
  const fs::path images = dir_ / "images.bin";
  const auto size = fs::file_size(images);
  fs::resize_file(images, size - 100);
  expectErrorAt(read(), images, "(image 40 of 40)", "truncated file");
}

TEST_F(ColmapCorruptBinaryTest, TruncatedAfterTheCountFailsAtTheCount) {
  const fs::path images = dir_ / "images.bin";
  fs::resize_file(images, 8 + 4 + 56 + 4 + 5);
  expectErrorAt(read(), images, "byte 0", "image count is 40 but only 69 bytes follow");
}

TEST_F(ColmapCorruptBinaryTest, CountTooSmallLeavesTrailingBytes) {
  const fs::path points = dir_ / "points3D.bin";
  const std::uint64_t count = 9065;
  patchFile(points, 0, &count, sizeof(count));
  expectErrorAt(read(), points, "byte", "unexpected bytes after 9065 points");
}

TEST_F(ColmapCorruptBinaryTest, HugeCountIsRejectedBeforeAllocating) {
  const fs::path points = dir_ / "points3D.bin";
  const std::uint64_t count = std::uint64_t{1} << 50;
  patchFile(points, 0, &count, sizeof(count));
  expectErrorAt(read(), points, "byte 0", "wrong count or truncated file");
}

TEST_F(ColmapCorruptBinaryTest, UnknownCameraModelId) {
  const fs::path cameras = dir_ / "cameras.bin";
  const std::int32_t model = 99;
  patchFile(cameras, 12, &model, sizeof(model));
  expectErrorAt(read(), cameras, "byte 12 (camera 1 of 1)", "unknown camera model id 99");
}

TEST_F(ColmapCorruptBinaryTest, NaNCoordinateNamesItsOffset) {
  const fs::path points = dir_ / "points3D.bin";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // The first point's y: after count (8), point3D_id (8) and x (8).
  patchFile(points, 24, &nan, sizeof(nan));
  expectErrorAt(read(), points, "byte 24 (point 1 of 9066)", "xyz: expected a finite number");
}

class ColmapCorruptTextTest : public ::testing::Test {
 protected:
  void SetUp() override { copyFiles(kTextModel, dir_.path()); }
  InputError read() {
    return expectInputError([&] { datasets::readColmapModel(dir_.path(), ColmapFileType::kText); });
  }
  TempDir dir_;
};

TEST_F(ColmapCorruptTextTest, NaNInPointsNamesTheLine) {
  replaceLine(dir_ / "points3D.txt", 5,
              "387 nan 0.69213571474978197 4.8013038684874241 146 179 160 0.81 42 975");
  expectErrorAt(read(), dir_ / "points3D.txt", "line 5", "expected a finite number");
}

TEST_F(ColmapCorruptTextTest, ImageLineWithoutNameNamesTheLine) {
  replaceLine(dir_ / "images.txt", 5,
              "1 0.842381 0.215061 0.44459 -0.215599 -2.67344 3.07749 0.697147 1");
  expectErrorAt(read(), dir_ / "images.txt", "line 5",
                "IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
}

TEST_F(ColmapCorruptTextTest, PointsLineOfTheWrongShape) {
  replaceLine(dir_ / "images.txt", 6, "213.271 57.3046 -1 213.271");
  expectErrorAt(read(), dir_ / "images.txt", "line 6", "(X Y POINT3D_ID) triples, got 4 fields");
}

TEST_F(ColmapCorruptTextTest, UnknownPointIdNamesTheImageLine) {
  replaceLine(dir_ / "images.txt", 6, "213.271 57.3046 123456789");
  expectErrorAt(read(), dir_ / "images.txt", "line 6", "point3D id 123456789 is not in points3D");
}

TEST_F(ColmapCorruptTextTest, UnknownCameraAndModel) {
  replaceLine(dir_ / "images.txt", 5,
              "1 0.842381 0.215061 0.44459 -0.215599 -2.67344 3.07749 0.697147 7 a.jpg");
  expectErrorAt(read(), dir_ / "images.txt", "line 5", "camera id 7 is not in cameras");
  replaceLine(dir_ / "cameras.txt", 4, "1 FISHEYE_9000 800 1200 2395.65 400 600");
  expectErrorAt(read(), dir_ / "cameras.txt", "line 4", "unknown camera model \"FISHEYE_9000\"");
}

TEST_F(ColmapCorruptTextTest, NonUnitQuaternion) {
  replaceLine(dir_ / "images.txt", 5,
              "1 0.5 0.215061 0.44459 -0.215599 -2.67344 3.07749 0.697147 1 a.jpg");
  expectErrorAt(read(), dir_ / "images.txt", "line 5", "qvec must have unit norm");
}

TEST_F(ColmapCorruptTextTest, FileEndingAfterAnImageHeader) {
  const std::string text = readFile(dir_ / "images.txt");
  // Cut right after the first image's header line (line 5).
  std::size_t end = 0;
  for (int line = 0; line < 5; ++line) end = text.find('\n', end) + 1;
  writeFile(dir_ / "images.txt", text.substr(0, end));
  expectErrorAt(read(), dir_ / "images.txt", "line 5", "expected its POINTS2D line");
}

TEST_F(ColmapCorruptTextTest, MissingFileIsNamed) {
  fs::remove(dir_ / "points3D.txt");
  expectErrorAt(read(), dir_ / "points3D.txt", "", "cannot open");
}

}  // namespace
}  // namespace terramesh::test
