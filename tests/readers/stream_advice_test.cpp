// What a source advises for meshing (the data-derived camera distance of SfM models, LiDAR's
// single view, the sensor's up axis) survives writing the stream as .tmstream and reading it back,
// so that `terramesh mesh` on the saved stream makes the same choices as on the original model.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "datasets/colmap_reader.h"
#include "datasets/lidar_scan_filter.h"
#include "datasets/stream_format.h"
#include "datasets/stream_reader.h"
#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

TEST(StreamAdvice, AutoCameraDistanceOfAnSfmModelSurvivesTheTmstream) {
  TempDir dir;
  const datasets::SlamStream model =
      datasets::readAnyStream(sharedData("colmap_statue_of_liberty/txt_model_40img"));
  ASSERT_TRUE(model.recommend_auto_max_distance);
  ASSERT_FALSE(model.scale_known);
  datasets::writeStreamFile(dir / "model.tmstream", model);
  const datasets::SlamStream saved = datasets::readAnyStream(dir / "model.tmstream");
  EXPECT_TRUE(saved.recommend_auto_max_distance);
  EXPECT_FALSE(saved.scale_known);
  EXPECT_EQ(saved.recommended_min_views, model.recommended_min_views);
  EXPECT_EQ(saved.events.size(), model.events.size());
  // The auto distance is a quantile of the observations, which are written exactly.
  EXPECT_EQ(datasets::observationDistanceQuantile(saved, 0.95), datasets::observationDistanceQuantile(model, 0.95));
}

TEST(StreamAdvice, LidarAdviceAndSensorUpSurvive) {
  TempDir dir;
  datasets::SlamStream stream;
  mesher::Keyframe keyframe;
  keyframe.id.value = 3;
  keyframe.observations.push_back({{7}, Eigen::Vector3d(1, 2, 3)});
  stream.events.emplace_back(keyframe);
  stream.scale_known = true;
  stream.recommended_min_views = 1;
  stream.recommended_steiner_step_m = datasets::kLidarSteinerStepM;
  stream.sensor_up_S = Eigen::Vector3d::UnitZ();
  datasets::writeStreamFile(dir / "lidar.tmstream", stream);
  const datasets::SlamStream saved = datasets::readStreamFile(dir / "lidar.tmstream");
  EXPECT_EQ(saved.recommended_min_views, 1);
  EXPECT_EQ(saved.recommended_steiner_step_m, datasets::kLidarSteinerStepM);
  EXPECT_FALSE(saved.recommend_auto_max_distance);
  EXPECT_EQ(saved.sensor_up_S, Eigen::Vector3d::UnitZ());
}

TEST(StreamAdvice, StreamsWithoutAdviceStayAsTheyWere) {
  TempDir dir;
  writeFile(dir / "plain.tmstream", "terramesh_stream 1\nkeyframe 0 0 0 0 1 0 0 0 1\n5 1 2 3\n");
  const datasets::SlamStream stream = datasets::readStreamFile(dir / "plain.tmstream");
  EXPECT_FALSE(stream.recommend_auto_max_distance);
  EXPECT_EQ(stream.recommended_min_views, 0);
  EXPECT_EQ(stream.recommended_steiner_step_m, 0.0);
  EXPECT_EQ(stream.sensor_up_S, -Eigen::Vector3d::UnitY());
  datasets::writeStreamFile(dir / "again.tmstream", stream);
  const datasets::SlamStream again = datasets::readStreamFile(dir / "again.tmstream");
  EXPECT_FALSE(again.recommend_auto_max_distance);
  EXPECT_EQ(again.recommended_min_views, 0);
}

TEST(StreamAdvice, BadAdviceNamesTheLine) {
  TempDir dir;
  writeFile(dir / "a.tmstream", "terramesh_stream 1\nmax_camera_distance 40\n");
  expectErrorAt(expectInputError([&] { datasets::readStreamFile(dir / "a.tmstream"); }), dir / "a.tmstream",
                "line 2", "auto");
  writeFile(dir / "b.tmstream", "terramesh_stream 1\nmin_views 0\n");
  expectErrorAt(expectInputError([&] { datasets::readStreamFile(dir / "b.tmstream"); }), dir / "b.tmstream",
                "line 2", "min_views");
  writeFile(dir / "c.tmstream", "terramesh_stream 1\nsensor_up 0 0 0\n");
  expectErrorAt(expectInputError([&] { datasets::readStreamFile(dir / "c.tmstream"); }), dir / "c.tmstream",
                "line 2", "sensor_up");
  for (const char* step : {"0", "-2", "inf"}) {
    writeFile(dir / "d.tmstream", std::string("terramesh_stream 1\nsteiner_step_m ") + step + "\n");
    expectErrorAt(expectInputError([&] { datasets::readStreamFile(dir / "d.tmstream"); }), dir / "d.tmstream",
                  "line 2", "steiner_step_m");
  }
}

TEST(StreamAdvice, MeshingAdviceSetsOnlyWhatTheStreamAdvises) {
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  const mesher::MesherConfig defaults = config;
  datasets::applyMeshingAdvice(datasets::SlamStream{}, config);
  EXPECT_EQ(config.min_views, defaults.min_views);
  EXPECT_EQ(config.steiner_step_m, defaults.steiner_step_m);
  datasets::SlamStream lidar;
  lidar.recommended_min_views = 1;
  lidar.recommended_steiner_step_m = datasets::kLidarSteinerStepM;
  datasets::applyMeshingAdvice(lidar, config);
  EXPECT_EQ(config.min_views, 1);
  EXPECT_EQ(config.steiner_step_m, datasets::kLidarSteinerStepM);
  EXPECT_NE(defaults.steiner_step_m, datasets::kLidarSteinerStepM);
}

TEST(StreamAdvice, LatestPosesAndEstimatesFollowCorrectionsAndRemovals) {
  datasets::SlamStream stream;
  const auto keyframe = [](std::uint64_t id, double x, std::vector<mesher::PointObservation> observations) {
    mesher::Keyframe k;
    k.id.value = id;
    k.position_W_C = Eigen::Vector3d(x, 0, 0);
    k.observations = std::move(observations);
    return k;
  };
  stream.events.emplace_back(keyframe(5, 0.0, {{{1}, Eigen::Vector3d(1, 1, 0)}, {{2}, Eigen::Vector3d(2, 1, 0)}}));
  stream.events.emplace_back(keyframe(2, 1.0, {{{2}, Eigen::Vector3d(2, 2, 0)}}));
  stream.events.emplace_back(keyframe(9, 2.0, {{{3}, Eigen::Vector3d(3, 1, 0)}}));
  stream.events.emplace_back(keyframe(5, 0.5, {{{1}, Eigen::Vector3d(1, 3, 0)}}));  // a loop closure re-sends 5
  stream.events.emplace_back(datasets::KeyframeRemoval{{9}});
  stream.events.emplace_back(datasets::PointRemoval{{{1}}});

  const std::vector<datasets::LatestKeyframePose> poses = datasets::latestKeyframePoses(stream);
  ASSERT_EQ(poses.size(), 2u) << "keyframe 9 was removed";
  EXPECT_EQ(poses[0].id.value, 2u) << "in id order";
  EXPECT_EQ(poses[1].id.value, 5u);
  EXPECT_EQ(poses[1].position_W_C, Eigen::Vector3d(0.5, 0, 0)) << "the corrected pose";

  // Every point ever observed, at its last estimate, in id order (removed points included: their
  // positions still say where the ground was seen).
  const std::vector<Eigen::Vector3d> points = datasets::latestPointEstimates(stream);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[0], Eigen::Vector3d(1, 3, 0));
  EXPECT_EQ(points[1], Eigen::Vector3d(2, 2, 0));
  EXPECT_EQ(points[2], Eigen::Vector3d(3, 1, 0));
}

}  // namespace
}  // namespace terramesh::test
