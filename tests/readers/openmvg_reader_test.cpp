#include "datasets/openmvg_reader.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kSfmData = sharedData("openmvg_dinoring/sfm_data.json");

TEST(OpenMvgReader, DinoRingHasExactCounts) {
  const datasets::SlamStream stream = datasets::readOpenMvgSfmData(kSfmData);
  EXPECT_EQ(countStream(stream), (StreamCounts{48, 48, 1230, 8662}));
  EXPECT_EQ(stream.keyframe_names.at(mesher::KeyframeId{0}), "dinoR0001.png");
  EXPECT_EQ(stream.keyframe_names.at(mesher::KeyframeId{47}), "dinoR0048.png");

  const auto keyframes = keyframesOf(stream);
  // extrinsics[0]: center (0.149964, 0.204702, -0.611028), first rotation row
  // (-0.086617, 0.972031, 0.218295) = the camera's x axis in the world.
  EXPECT_EQ(keyframes[0].position_W_C, Eigen::Vector3d(0.149964, 0.204702, -0.611028));
  const Eigen::Vector3d x_axis_W = keyframes[0].rotation_W_C * Eigen::Vector3d::UnitX();
  EXPECT_LT((x_axis_W - Eigen::Vector3d(-0.086617, 0.972031, 0.218295)).norm(), 1e-5);
  // World-to-camera read the right way round: every observed point lies in front of its camera.
  for (const mesher::Keyframe& keyframe : keyframes) {
    for (const auto& observation : keyframe.observations) {
      const Eigen::Vector3d p_C =
          keyframe.rotation_W_C.conjugate() * (observation.position_W - keyframe.position_W_C);
      ASSERT_GT(p_C.z(), 0) << "keyframe " << keyframe.id.value;
    }
  }
}

class OpenMvgCorruptTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = json::parse(readFile(kSfmData)); }
  InputError readModified() {
    writeFile(path_, root_.dump());
    return expectInputError([&] { datasets::readOpenMvgSfmData(path_); });
  }
  TempDir dir_;
  fs::path path_ = dir_ / "sfm_data.json";
  json root_;
};

TEST_F(OpenMvgCorruptTest, RelativeOrMissingRootPathAndViewVariantsReadTheSame) {
  const datasets::SlamStream original = datasets::readOpenMvgSfmData(kSfmData);
  // Converted exports say where the images are relative to the file, or not at all; views of
  // newer OpenMVG are polymorphic (view_priors) with extra fields; control points may be present.
  for (const json& root_path : {json("images"), json("."), json("../dinoRing"), json("")}) {
    root_["root_path"] = root_path;
    for (auto& view : root_["views"]) {
      view["value"]["polymorphic_id"] = 1073741824;
      view["value"]["polymorphic_name"] = "view_priors";
      view["value"]["ptr_wrapper"]["data"]["local_path"] = "sub/";
      view["value"]["ptr_wrapper"]["data"]["use_pose_center_prior"] = false;
    }
    root_["control_points"] = json::array();
    writeFile(path_, root_.dump(2));
    EXPECT_TRUE(sameStreams(datasets::readOpenMvgSfmData(path_), original)) << root_path;
  }
  root_.erase("root_path");
  writeFile(path_, root_.dump());
  EXPECT_TRUE(sameStreams(datasets::readOpenMvgSfmData(path_), original));
}

TEST_F(OpenMvgCorruptTest, WrongTypeNamesTheField) {
  root_["extrinsics"][2]["value"]["center"] = "here";
  expectErrorAt(readModified(), path_, "extrinsics[2].value.center",
                "expected an array of 3 numbers");
}

TEST_F(OpenMvgCorruptTest, NonRotationNamesTheField) {
  root_["extrinsics"][5]["value"]["rotation"][1][1] = 3.0;
  expectErrorAt(readModified(), path_, "extrinsics[5].value.rotation", "expected a rotation");
}

TEST_F(OpenMvgCorruptTest, ObservationOfAnUnknownView) {
  root_["structure"][7]["value"]["observations"][1]["key"] = 4800;
  expectErrorAt(readModified(), path_, "structure[7].value.observations[1].key",
                "view 4800 is not in views");
}

TEST_F(OpenMvgCorruptTest, ObservationOfAViewWithoutPose) {
  root_["extrinsics"].erase(0);
  expectErrorAt(readModified(), path_, "structure[0].value.observations[0].key",
                "view 0 has no pose");
}

TEST_F(OpenMvgCorruptTest, ViewTwiceInOnePointsObservations) {
  auto& observations = root_["structure"][3]["value"]["observations"];
  observations.push_back(observations[0]);
  expectErrorAt(readModified(), path_, "structure[3].value.observations[",
                "observes this point twice");
}

TEST_F(OpenMvgCorruptTest, MissingVersion) {
  root_.erase("sfm_data_version");
  expectErrorAt(readModified(), path_, "sfm_data_version", "missing field");
}

TEST_F(OpenMvgCorruptTest, MalformedJsonNamesLineAndColumn) {
  writeFile(path_, "{\n  \"sfm_data_version\": \"0.3\",\n  \"views\": [,]\n}\n");
  expectErrorAt(expectInputError([&] { datasets::readOpenMvgSfmData(path_); }), path_,
                "line 3, column", "malformed JSON");
}

TEST_F(OpenMvgCorruptTest, ViewsWithoutPoseAreSkipped) {
  // A view with no pose and no observation is an unregistered image, not an error.
  root_["views"][10]["value"]["ptr_wrapper"]["data"]["id_pose"] = 4242;
  auto& structure = root_["structure"];
  for (auto& point : structure) {
    auto& observations = point["value"]["observations"];
    for (auto it = observations.begin(); it != observations.end();) {
      it = (*it)["key"] == 10 ? observations.erase(it) : it + 1;
    }
  }
  writeFile(path_, root_.dump());
  const datasets::SlamStream stream = datasets::readOpenMvgSfmData(path_);
  EXPECT_EQ(countStream(stream).keyframe_events, 47u);
  EXPECT_EQ(stream.keyframe_names.count(mesher::KeyframeId{10}), 0u);
}

}  // namespace
}  // namespace terramesh::test
