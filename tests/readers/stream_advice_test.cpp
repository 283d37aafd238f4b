// What a source advises for meshing (the data-derived camera distance of SfM models, LiDAR's
// single view, the sensor's up axis) survives writing the stream as .tmstream and reading it back,
// so that `terramesh mesh` on the saved stream makes the same choices as on the original model.
#include <gtest/gtest.h>

#include "datasets/colmap_reader.h"
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
  stream.sensor_up_S = Eigen::Vector3d::UnitZ();
  datasets::writeStreamFile(dir / "lidar.tmstream", stream);
  const datasets::SlamStream saved = datasets::readStreamFile(dir / "lidar.tmstream");
  EXPECT_EQ(saved.recommended_min_views, 1);
  EXPECT_FALSE(saved.recommend_auto_max_distance);
  EXPECT_EQ(saved.sensor_up_S, Eigen::Vector3d::UnitZ());
}

TEST(StreamAdvice, StreamsWithoutAdviceStayAsTheyWere) {
  TempDir dir;
  writeFile(dir / "plain.tmstream", "terramesh_stream 1\nkeyframe 0 0 0 0 1 0 0 0 1\n5 1 2 3\n");
  const datasets::SlamStream stream = datasets::readStreamFile(dir / "plain.tmstream");
  EXPECT_FALSE(stream.recommend_auto_max_distance);
  EXPECT_EQ(stream.recommended_min_views, 0);
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
}

}  // namespace
}  // namespace terramesh::test
