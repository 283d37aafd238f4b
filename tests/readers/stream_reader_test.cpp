#include "datasets/stream_reader.h"

#include <gtest/gtest.h>

#include "datasets/colmap_reader.h"
#include "datasets/stream_format.h"
#include "model_writers.h"
#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

namespace fs = std::filesystem;
using datasets::StreamFormat;

TEST(StreamReader, FormatNamesRoundTrip) {
  for (StreamFormat format :
       {StreamFormat::kAuto, StreamFormat::kSlamJson, StreamFormat::kTmStream,
        StreamFormat::kOpenMvg, StreamFormat::kColmap, StreamFormat::kColmapText,
        StreamFormat::kColmapBinary, StreamFormat::kBundler, StreamFormat::kKittiOdometry,
        StreamFormat::kRosbag}) {
    EXPECT_EQ(datasets::parseStreamFormat(datasets::toString(format)), format);
  }
  EXPECT_FALSE(datasets::parseStreamFormat("ply"));
  EXPECT_EQ(datasets::streamFormatNames(),
            "auto, slam-json, tmstream, openmvg, colmap, colmap-text, colmap-bin, bundler, kitti, "
            "rosbag");
}

TEST(StreamReader, DetectsEveryRealInput) {
  EXPECT_EQ(datasets::detectStreamFormat(
                sharedData("kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json")),
            StreamFormat::kSlamJson);
  EXPECT_EQ(datasets::detectStreamFormat(sharedData("openmvg_dinoring/sfm_data.json")),
            StreamFormat::kOpenMvg);
  EXPECT_EQ(datasets::detectStreamFormat(sharedData("colmap_statue_of_liberty/txt_model_40img")),
            StreamFormat::kColmap);
  EXPECT_EQ(datasets::detectStreamFormat(sharedData("colmap_statue_of_liberty/bin_model_40img")),
            StreamFormat::kColmap);
  EXPECT_EQ(datasets::detectStreamFormat(sharedData("kitti00_lidar")),
            StreamFormat::kKittiOdometry);
}

TEST(StreamReader, ReadsEachRealInputThroughOneEntryPoint) {
  EXPECT_EQ(countStream(datasets::readAnyStream(sharedData("openmvg_dinoring/sfm_data.json")))
                .observations,
            8662u);
  EXPECT_EQ(
      countStream(datasets::readAnyStream(sharedData("colmap_statue_of_liberty/txt_model_40img")))
          .distinct_points,
      1816u);
  EXPECT_EQ(countStream(datasets::readAnyStream(sharedData(
                            "kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json")))
                .observations,
            4616u);
  datasets::StreamReadOptions options;
  options.kitti.poses_path = sharedData("kitti_poses/00.txt");
  options.kitti.last_frame = 2;
  EXPECT_EQ(countStream(datasets::readAnyStream(sharedData("kitti00_lidar"), options)).observations,
            124605u + 124478u);
  // The shared LiDAR folder has no poses of its own.
  expectErrorAt(expectInputError([] { datasets::readAnyStream(sharedData("kitti00_lidar")); }),
                sharedData("kitti00_lidar"), "", "no poses");
}

TEST(StreamReader, FormatOverrideChoosesTheColmapEncoding) {
  // A folder with both encodings of different models: binary wins unless text is asked for.
  TempDir dir;
  copyFiles(sharedData("colmap_statue_of_liberty/txt_model_40img"), dir.path());
  copyFiles(sharedData("colmap_statue_of_liberty/bin_model_40img"), dir.path());
  EXPECT_EQ(countStream(datasets::readAnyStream(dir.path())).distinct_points, 9066u);
  EXPECT_EQ(countStream(datasets::readAnyStream(dir.path(), {StreamFormat::kColmapText, {}, {}, {}}))
                .distinct_points,
            1816u);
  EXPECT_EQ(countStream(datasets::readAnyStream(dir.path(), {StreamFormat::kColmapBinary, {}, {}, {}}))
                .distinct_points,
            9066u);
}

TEST(StreamReader, DetectsFilesByExtensionAndJsonByVersionKey) {
  TempDir dir;
  const datasets::SlamStream stream = datasets::readAnyStream(
      sharedData("kitti00_orbslam/non_incremental_slam_data_version0.2_KITTI00_200frames.json"));
  datasets::writeStreamFile(dir / "s.tmstream", stream);
  EXPECT_EQ(datasets::detectStreamFormat(dir / "s.tmstream"), StreamFormat::kTmStream);
  EXPECT_TRUE(sameStreams(datasets::readAnyStream(dir / "s.tmstream"), stream));

  const auto model = datasets::readColmapModel(
      sharedData("colmap_statue_of_liberty/txt_model_40img"), datasets::ColmapFileType::kText);
  writeBundlerFromColmap(dir / "bundle.out", dir / "list.txt", model);
  EXPECT_EQ(datasets::detectStreamFormat(dir / "bundle.out"), StreamFormat::kBundler);
  EXPECT_EQ(countStream(datasets::readAnyStream(dir / "bundle.out")).keyframe_events, 40u);

  // The version key may come late in a large file; the first one found decides.
  writeFile(dir / "late.json", "{\"views\": [], \"pad\": \"" + std::string(200000, 'x') +
                                   "\", \"sfm_data_version\": \"0.3\"}");
  EXPECT_EQ(datasets::detectStreamFormat(dir / "late.json"), StreamFormat::kOpenMvg);
}

TEST(StreamReader, UnknownInputsAreNamed) {
  TempDir dir;
  expectErrorAt(expectInputError([&] { datasets::readAnyStream(dir / "missing.json"); }),
                dir / "missing.json", "", "no such file or directory");
  writeFile(dir / "mesh.ply", "ply\n");
  expectErrorAt(expectInputError([&] { datasets::readAnyStream(dir / "mesh.ply"); }),
                dir / "mesh.ply", "", "unknown stream format \".ply\"");
  writeFile(dir / "other.json", "{\"version\": 1}");
  expectErrorAt(expectInputError([&] { datasets::readAnyStream(dir / "other.json"); }),
                dir / "other.json", "", "slam_data_version");
  expectErrorAt(expectInputError([&] { datasets::readAnyStream(dir.path()); }), dir.path(), "",
                "unknown input directory");
  // An explicit format is obeyed even when detection would choose another.
  expectErrorAt(expectInputError([&] {
                  datasets::readAnyStream(dir / "other.json", {StreamFormat::kOpenMvg, {}, {}, {}});
                }),
                dir / "other.json", "sfm_data_version", "missing field");
}

}  // namespace
}  // namespace terramesh::test
