#include "datasets/slam_json.h"

#include <gtest/gtest.h>

#include <limits>
#include <nlohmann/json.hpp>

#include "datasets/stream_format.h"
#include "mesher/mesher.h"
#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kVersion01 =
    sharedData("kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json");
const fs::path kVersion02 =
    sharedData("kitti00_orbslam/non_incremental_slam_data_version0.2_KITTI00_200frames.json");

TEST(SlamJsonReader, Version01HasExactCounts) {
  const datasets::SlamStream stream = datasets::readSlamJson(kVersion01);
  EXPECT_EQ(countStream(stream), (StreamCounts{17, 15, 2536, 4616}));
  const auto keyframes = keyframesOf(stream);
  std::vector<std::uint64_t> ids;
  for (const auto& keyframe : keyframes) ids.push_back(keyframe.id.value);
  EXPECT_EQ(
      ids, (std::vector<std::uint64_t>{0, 0, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 14, 16, 17}));
}

TEST(SlamJsonReader, RepeatedViewReplacesTheFirstInTheMesher) {
  const datasets::SlamStream stream = datasets::readSlamJson(kVersion01);
  mesher::MesherConfig config;
  config.metres_per_unit = 16.589;
  mesher::Mesher mesher(config);
  for (const auto& event : stream.events) datasets::applyEvent(mesher, event);
  EXPECT_EQ(mesher.size().keyframes, 15u);
}

TEST(SlamJsonReader, Version02HasExactCounts) {
  const datasets::SlamStream stream = datasets::readSlamJson(kVersion02);
  EXPECT_EQ(countStream(stream), (StreamCounts{5, 5, 15, 21}));
  EXPECT_EQ(keyframesOf(stream).front().id.value, 1u);
}

class SlamJsonCorruptTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = json::parse(readFile(kVersion01)); }
  InputError readModified() {
    writeFile(path_, root_.dump(1));
    return expectInputError([&] { datasets::readSlamJson(path_); });
  }
  TempDir dir_;
  fs::path path_ = dir_ / "slam.json";
  json root_;
};

TEST_F(SlamJsonCorruptTest, MissingFile) {
  expectErrorAt(expectInputError([&] { datasets::readSlamJson(dir_ / "none.json"); }),
                dir_ / "none.json", "", "cannot open");
}

TEST_F(SlamJsonCorruptTest, MalformedJsonNamesLineAndColumn) {
  writeFile(path_,
            "{\n  \"slam_data_version\": \"0.1\",\n  \"views\": [\n    {\"key\": 0,,}\n  ]\n}\n");
  expectErrorAt(expectInputError([&] { datasets::readSlamJson(path_); }), path_, "line 4, column ",
                "malformed JSON");
}

TEST_F(SlamJsonCorruptTest, WrongTypeNamesTheField) {
  root_["views"][3]["extrinsic"]["center"] = {1.0, "two", 3.0};
  expectErrorAt(readModified(), path_, "views[3].extrinsic.center[1]", "expected a number");
  root_["views"][3]["extrinsic"]["center"] = "origin";
  const InputError error = readModified();
  EXPECT_EQ(error.where(), "views[3].extrinsic.center");
}

TEST_F(SlamJsonCorruptTest, UnknownVersion) {
  root_["slam_data_version"] = "0.9";
  expectErrorAt(readModified(), path_, "slam_data_version", "unsupported version \"0.9\"");
}

TEST_F(SlamJsonCorruptTest, PointListedTwiceInOneView) {
  auto& observations = root_["views"][2]["observations"];
  observations.push_back(observations[5]);
  const std::string last = "views[2].observations[" + std::to_string(observations.size() - 1) + "]";
  expectErrorAt(readModified(), path_, last + ".key",
                "is listed twice in this view (first at "
                "views[2].observations[5])");
}

TEST_F(SlamJsonCorruptTest, NonFiniteNumberAndNonRotation) {
  // JSON has no infinity: nlohmann writes it as null.
  root_["views"][4]["observations"][0]["X"][2] = std::numeric_limits<double>::infinity();
  expectErrorAt(readModified(), path_, "views[4].observations[0].X[2]", "expected a number");
  root_ = json::parse(readFile(kVersion01));
  root_["views"][6]["extrinsic"]["rotation"][0] = {2.0, 0.0, 0.0};
  expectErrorAt(readModified(), path_, "views[6].extrinsic.rotation", "expected a rotation matrix");
}

class StreamFileTest : public ::testing::Test {
 protected:
  InputError readBad(const std::string& text) {
    writeFile(path_, text);
    return expectInputError([&] { datasets::readStreamFile(path_); });
  }
  TempDir dir_;
  fs::path path_ = dir_ / "s.tmstream";
};

TEST_F(StreamFileTest, RoundTripOfTheRealStream) {
  const datasets::SlamStream stream = datasets::readSlamJson(kVersion01);
  datasets::writeStreamFile(path_, stream);
  // Positions are written exactly; re-normalising the quaternion may move its last bit.
  EXPECT_TRUE(sameStreams(datasets::readStreamFile(path_), stream, 1e-15));
}

TEST_F(StreamFileTest, PointListedTwiceInOneKeyframe) {
  expectErrorAt(
      readBad("terramesh_stream 1\nkeyframe 4 0 0 0 1 0 0 0 3\n7 1 2 3\n8 1 2 3\n7 1 2 4\n"), path_,
      "line 5", "point 7 is listed twice in the keyframe of line 2 (first on line 3)");
}

TEST_F(StreamFileTest, MalformedAndTruncated) {
  expectErrorAt(readBad("terramesh_stream 2\n"), path_, "line 1", "unsupported format version 2");
  expectErrorAt(readBad("terramesh\n"), path_, "line 1", "expected the header");
  expectErrorAt(readBad("terramesh_stream 1\nkeyframe 4 0 0 0 1 0 0 0 3\n7 1 2 3\n"), path_,
                "line 3", "file ends inside the keyframe of line 2: 1 of 3");
  expectErrorAt(readBad("terramesh_stream 1\nkeyframe 4 0 0 0 1 0 0 0 1\n7 1 nan 3\n"), path_,
                "line 3", "point position: expected a finite number");
  expectErrorAt(readBad("terramesh_stream 1\nkeyframe 4 0 0 0 1 0 0\n"), path_, "line 2",
                "10 fields, got 8");
}

}  // namespace
}  // namespace terramesh::test
