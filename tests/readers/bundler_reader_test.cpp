#include "datasets/bundler_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <optional>
#include <vector>

#include "datasets/colmap_reader.h"
#include "datasets/stream_reader.h"
#include "model_writers.h"
#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

namespace fs = std::filesystem;

/// Observations of a keyframe as point id -> position.
std::map<std::uint64_t, Eigen::Vector3d> observationMap(const mesher::Keyframe& keyframe) {
  std::map<std::uint64_t, Eigen::Vector3d> map;
  for (const auto& observation : keyframe.observations) {
    map[observation.point.value] = observation.position_W;
  }
  return map;
}

/// Writes the COLMAP model `colmap_dir` as Bundler, reads it back and compares it with the COLMAP
/// reader's stream: camera i is the i-th image by id, point j the j-th COLMAP point.
void expectBundlerMatchesColmap(const fs::path& colmap_dir, datasets::ColmapFileType type,
                                std::size_t observations) {
  TempDir dir;
  const datasets::ColmapModel model = datasets::readColmapModel(colmap_dir, type);
  writeBundlerFromColmap(dir / "bundle.out", dir / "list.txt", model);
  const datasets::SlamStream bundler = datasets::readBundler(dir / "bundle.out");
  const datasets::SlamStream colmap = datasets::colmapModelToStream(model, "");

  EXPECT_EQ(countStream(bundler), (StreamCounts{model.images.size(), model.images.size(),
                                                model.points.size(), observations}));

  const auto from_bundler = keyframesOf(bundler);
  const auto from_colmap = keyframesOf(colmap);
  ASSERT_EQ(from_bundler.size(), from_colmap.size());
  for (std::size_t k = 0; k < from_bundler.size(); ++k) {
    const mesher::Keyframe& b = from_bundler[k];
    const mesher::Keyframe& c = from_colmap[k];
    EXPECT_EQ(b.id.value, k);
    EXPECT_EQ(bundler.keyframe_names.at(b.id), colmap.keyframe_names.at(c.id));
    EXPECT_LT((b.position_W_C - c.position_W_C).norm(), 1e-12 * (1 + c.position_W_C.norm()));
    EXPECT_LT((b.rotation_W_C.toRotationMatrix() - c.rotation_W_C.toRotationMatrix()).norm(),
              1e-12);
    std::map<std::uint64_t, Eigen::Vector3d> expected;
    for (const auto& [id, position] : observationMap(c)) {
      const auto point = std::find_if(model.points.begin(), model.points.end(),
                                      [id = id](const auto& p) { return p.id == id; });
      expected[static_cast<std::uint64_t>(point - model.points.begin())] = position;
    }
    EXPECT_EQ(observationMap(b), expected) << "keyframe " << k;
  }
}

TEST(BundlerReader, ColmapTextModelConvertedToBundlerReadsBack) {
  expectBundlerMatchesColmap(sharedData("colmap_statue_of_liberty/txt_model_40img"),
                             datasets::ColmapFileType::kText, 7737);
}

TEST(BundlerReader, ColmapBinaryModelConvertedToBundlerReadsBack) {
  expectBundlerMatchesColmap(sharedData("colmap_statue_of_liberty/bin_model_40img"),
                             datasets::ColmapFileType::kBinary, 37120);
}

/// A small hand-written bundle: camera 1 is not reconstructed (all zeros).
constexpr const char* kSmallBundle =
    "# Bundle file v0.3\n"
    "3 2\n"
    "500 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 -5\n"
    "0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n"
    "400 0 0\n1 0 0\n0 -1 0\n0 0 -1\n1 2 3\n"
    "0 0 0\n255 0 0\n2 0 0 1.5 2.5 2 7 3.5 4.5\n"
    "1 1 1\n0 255 0\n1 0 1 0 0\n";

class BundlerSmallTest : public ::testing::Test {
 protected:
  void SetUp() override {
    writeFile(bundle_, kSmallBundle);
    writeFile(dir_ / "list.txt", "a.jpg 0 500\nb.jpg\nc.jpg 0 400\n");
  }
  InputError read() {
    return expectInputError([&] { datasets::readBundler(bundle_); });
  }
  TempDir dir_;
  fs::path bundle_ = dir_ / "bundle.out";
};

TEST_F(BundlerSmallTest, SkipsUnreconstructedCamerasAndFlipsTheCameraFrame) {
  const datasets::SlamStream stream = datasets::readBundler(bundle_);
  const auto keyframes = keyframesOf(stream);
  ASSERT_EQ(keyframes.size(), 2u);
  EXPECT_EQ(keyframes[0].id.value, 0u);
  EXPECT_EQ(keyframes[1].id.value, 2u);
  EXPECT_EQ(stream.keyframe_names.at(mesher::KeyframeId{2}), "c.jpg");
  // Camera 0: R = I, t = (0, 0, -5): centre (0, 0, 5), looking down world -z (Bundler's -z).
  EXPECT_LT((keyframes[0].position_W_C - Eigen::Vector3d(0, 0, 5)).norm(), 1e-15);
  const Eigen::Vector3d forward_W = keyframes[0].rotation_W_C * Eigen::Vector3d::UnitZ();
  EXPECT_LT((forward_W - Eigen::Vector3d(0, 0, -1)).norm(), 1e-15);
  // Camera 2: R = diag(1, -1, -1), t = (1, 2, 3): centre -R^T t = (-1, 2, 3).
  EXPECT_LT((keyframes[1].position_W_C - Eigen::Vector3d(-1, 2, 3)).norm(), 1e-15);
  ASSERT_EQ(keyframes[0].observations.size(), 2u);
  EXPECT_EQ(keyframes[0].observations[1].point.value, 1u);
  EXPECT_EQ(keyframes[0].observations[1].position_W, Eigen::Vector3d(1, 1, 1));
  ASSERT_EQ(keyframes[1].observations.size(), 1u);
}

TEST_F(BundlerSmallTest, ListInTheParentDirectoryIsFound) {
  fs::create_directories(dir_ / "bundle");
  fs::rename(bundle_, dir_ / "bundle" / "bundle.out");
  EXPECT_EQ(datasets::findBundlerList(dir_ / "bundle" / "bundle.out"), dir_ / "list.txt");
  EXPECT_EQ(countStream(datasets::readBundler(dir_ / "bundle" / "bundle.out")).keyframe_events, 2u);
}

TEST_F(BundlerSmallTest, WithoutAListTheStreamHasNoNames) {
  const datasets::SlamStream with_list = datasets::readBundler(bundle_);
  fs::remove(dir_ / "list.txt");
  EXPECT_EQ(datasets::findBundlerList(bundle_), std::nullopt);
  datasets::SlamStream without_list = datasets::readBundler(bundle_);
  EXPECT_TRUE(without_list.keyframe_names.empty());
  EXPECT_NE(without_list.description.find("no image list"), std::string::npos);
  without_list.keyframe_names = with_list.keyframe_names;
  EXPECT_TRUE(sameStreams(without_list, with_list));
  // A list named explicitly must exist.
  const fs::path explicit_list = dir_ / "images.txt";
  expectErrorAt(expectInputError([&] { datasets::readBundler(bundle_, explicit_list); }),
                explicit_list, "", "cannot open");
}

TEST(BundlerReader, ListCandidatesInOrder) {
  const fs::path bundle = fs::path("data") / "run" / "bundle_r000.out";
  const std::vector<fs::path> expected = {
      fs::path("data") / "run" / "list_r000.out", fs::path("data") / "run" / "list_r000.txt",
      fs::path("data") / "run" / "list.txt", fs::path("data") / "list.txt"};
  EXPECT_EQ(datasets::bundlerListCandidates(bundle), expected);
  // No "bundle" in the name: only list.txt, beside the file and in its parent (no duplicates).
  EXPECT_EQ(datasets::bundlerListCandidates(fs::path("model.out")),
            std::vector<fs::path>{fs::path("list.txt")});
}

/// OpenSfM's `export_bundler` writes bundle_r000.out beside list_r000.out.
class OpenSfmExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = datasets::readColmapModel(sharedData("colmap_statue_of_liberty/txt_model_40img"),
                                       datasets::ColmapFileType::kText);
    bundle_ = writeOpenSfmBundlerExport(dir_.path(), model_);
  }
  TempDir dir_;
  datasets::ColmapModel model_;
  fs::path bundle_;
};

TEST_F(OpenSfmExportTest, ListIsFoundAndNamesTheImages) {
  EXPECT_EQ(bundle_.filename(), "bundle_r000.out");
  EXPECT_EQ(datasets::findBundlerList(bundle_), dir_ / "list_r000.out");
  const datasets::SlamStream stream = datasets::readAnyStream(bundle_);
  EXPECT_EQ(countStream(stream), (StreamCounts{40, 40, 1816, 7737}));
  ASSERT_EQ(stream.keyframe_names.size(), 40u);
  EXPECT_EQ(stream.keyframe_names.begin()->second.rfind("images/", 0), 0u);
  EXPECT_TRUE(stream.recommend_auto_max_distance);
}

TEST_F(OpenSfmExportTest, ImageListGivenExplicitlyOrNone) {
  const datasets::SlamStream found = datasets::readBundler(bundle_);
  fs::rename(dir_ / "list_r000.out", dir_ / "images.lst");
  datasets::StreamReadOptions options;
  options.bundler_image_list = dir_ / "images.lst";
  EXPECT_TRUE(sameStreams(datasets::readAnyStream(bundle_, options), found));
  // With no list anywhere: the same stream without names.
  const datasets::SlamStream unnamed = datasets::readAnyStream(bundle_);
  EXPECT_TRUE(unnamed.keyframe_names.empty());
  EXPECT_EQ(countStream(unnamed), countStream(found));
  // An image list for another format is a caller's mistake.
  options.format = datasets::StreamFormat::kColmapText;
  EXPECT_THROW(datasets::readAnyStream(dir_.path(), options), std::invalid_argument);
}

TEST_F(BundlerSmallTest, ListOfTheWrongLength) {
  writeFile(dir_ / "list.txt", "a.jpg\nb.jpg\n");
  expectErrorAt(read(), dir_ / "list.txt", "", "lists 2 images but");
}

TEST_F(BundlerSmallTest, WrongHeader) {
  writeFile(bundle_, std::string("# Bundle file v0.2\n") + (kSmallBundle + 19));
  expectErrorAt(read(), bundle_, "line 1", "expected the header \"# Bundle file v0.3\"");
}

TEST_F(BundlerSmallTest, TruncatedFile) {
  const std::string text = kSmallBundle;
  writeFile(bundle_, text.substr(0, text.size() - 5));
  expectErrorAt(read(), bundle_, "line 23", "point 1: view list x: file ends");
}

TEST_F(BundlerSmallTest, MalformedLines) {
  replaceLine(bundle_, 20, "2 0 0 1.5 2.5 5 7 3.5 4.5");
  expectErrorAt(read(), bundle_, "line 20", "point 0: view list: camera 5 out of range");
  replaceLine(bundle_, 20, "2 0 0 1.5 2.5 1 7 3.5 4.5");
  expectErrorAt(read(), bundle_, "line 20", "camera 1 is not reconstructed");
  replaceLine(bundle_, 20, "2 0 0 1.5 2.5 2 7 3.5 4.5");
  replaceLine(bundle_, 18, "0 nan 0");
  expectErrorAt(read(), bundle_, "line 18", "point 0: position: expected a finite number");
  replaceLine(bundle_, 18, "0 0 0");
  replaceLine(bundle_, 4, "1 0 0.5");
  expectErrorAt(read(), bundle_, "line 7", "camera 0: R: expected a rotation matrix");
}

TEST_F(BundlerSmallTest, TrailingData) {
  writeFile(bundle_, std::string(kSmallBundle) + "1 2 3\n");
  expectErrorAt(read(), bundle_, "line 24", "unexpected data after the last of 2 points");
}

}  // namespace
}  // namespace terramesh::test
