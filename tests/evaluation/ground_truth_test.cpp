// Similarity files and the KITTI LiDAR ground truth, on the real files in ../shared/data.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "common/input_error.h"
#include "datasets/similarity_transform.h"
#include "evaluation/lidar_truth.h"
#include "test_support/temp_dir.h"

namespace terramesh::evaluation {
namespace {

using datasets::SimilarityTransform;
using datasets::readSimilarityTransform;

const std::filesystem::path kShared = TERRAMESH_SHARED_DIR;
const std::filesystem::path kLidar = kShared / "data" / "kitti00_lidar";
const std::filesystem::path kPoses = kShared / "data" / "kitti_poses" / "00.txt";

std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(SimilarityTransform, ReadsTheIcpSimilarityOfKitti00) {
  const SimilarityTransform sim = readSimilarityTransform(kLidar / "piazza_sim3_to_gt_icp.txt");
  EXPECT_DOUBLE_EQ(sim.scale, 16.5891119);
  EXPECT_DOUBLE_EQ(sim.rotation(0, 2), 0.0175062179);
  EXPECT_DOUBLE_EQ(sim.translation.z(), 0.378288792);
  // x' = s R x + t.
  const Eigen::Vector3d x(1, 2, 3);
  EXPECT_NEAR((sim.apply(x) - (sim.scale * sim.rotation * x + sim.translation)).norm(), 0.0, 1e-12);
  // The other file's extra `matched_frames` line is ignored.
  EXPECT_DOUBLE_EQ(readSimilarityTransform(kLidar / "piazza_sim3_to_gt.txt").scale, 18.5968202);
}

TEST(SimilarityTransform, MappedMeshKeepsFacesAndFlags) {
  SimilarityTransform sim;
  sim.scale = 2.0;
  sim.translation = Eigen::Vector3d(1, 0, 0);
  mesher::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.faces = {{0, 1, 2}};
  mesh.is_steiner = {0, 1, 0};
  const mesher::TriangleMesh mapped = sim.apply(mesh);
  EXPECT_EQ(mapped.faces, mesh.faces);
  EXPECT_EQ(mapped.is_steiner, mesh.is_steiner);
  EXPECT_EQ(mapped.vertices[1], Eigen::Vector3d(3, 0, 0));
}

TEST(SimilarityTransform, BadFilesNameFileLineAndField) {
  test::TempDir dir;
  auto write = [&](const std::string& text) {
    const auto path = dir / "sim3.txt";
    std::ofstream(path) << text;
    return path;
  };
  const std::string identity = "R 1 0 0 0 1 0 0 0 1\n";
  EXPECT_THAT(errorOf([&] { readSimilarityTransform(write("s 2\n" + identity)); }), ::testing::HasSubstr("missing t"));
  EXPECT_THAT(errorOf([&] { readSimilarityTransform(write("s -1\n" + identity + "t 0 0 0\n")); }),
              ::testing::AllOf(::testing::HasSubstr("line 1"), ::testing::HasSubstr("positive")));
  EXPECT_THAT(errorOf([&] { readSimilarityTransform(write("s 1\nR 1 0 0 0 1 0 0 0 2\nt 0 0 0\n")); }),
              ::testing::AllOf(::testing::HasSubstr("line 2"), ::testing::HasSubstr("rotation")));
  EXPECT_THAT(errorOf([&] { readSimilarityTransform(write("s 1\n" + identity + "t 0 0\n")); }),
              ::testing::AllOf(::testing::HasSubstr("line 3"), ::testing::HasSubstr("expected 3 numbers")));
  EXPECT_THAT(errorOf([&] { readSimilarityTransform(write("s 1\n" + identity + "t 0 nan 0\n")); }),
              ::testing::HasSubstr("finite"));
  EXPECT_THAT(errorOf([&] { readSimilarityTransform(dir / "missing.txt"); }), ::testing::HasSubstr("missing.txt"));
}

TEST(LidarTruth, RaysRunFromTheSensorToReturnsTheCameraSees) {
  LidarTruthOptions options;
  options.poses_path = kPoses;
  options.first_frame = 1;
  options.last_frame = 2;
  const PinholeCamera camera;
  const DepthComparisonConfig config;
  const LidarTruth truth = readLidarTruth(kLidar, options, camera, config);
  ASSERT_EQ(truth.world_from_sensor.size(), 2u);
  ASSERT_GT(truth.rays.size(), 10000u);
  // Returns the camera cannot see (behind, beside) are kept for accuracy but give no depth ray.
  EXPECT_LT(truth.rays.size(), truth.returns_W.size() / 2);
  EXPECT_LE(truth.returns_W.size(), truth.returns_read);
  for (const DepthRay& ray : truth.rays) {
    ASSERT_LE(ray.truth_depth_m, config.max_depth_m);
    ASSERT_NEAR(ray.direction_W.norm(), 1.0, 1e-9);
    const bool from_a_sensor = (ray.origin_W - truth.world_from_sensor[0].translation()).norm() < 1e-9 ||
                               (ray.origin_W - truth.world_from_sensor[1].translation()).norm() < 1e-9;
    ASSERT_TRUE(from_a_sensor);
  }
  // The scanner covers a return's end, but not a point 10 m straight above it (beyond +2 degrees).
  const DepthRay& ray = truth.rays[truth.rays.size() / 2];
  const Eigen::Vector3d end = ray.origin_W + ray.truth_depth_m * ray.direction_W;
  EXPECT_TRUE(truth.covers(end, config.max_depth_m, &camera));
  const Eigen::Vector3d above = truth.world_from_sensor[0] * Eigen::Vector3d(10.0, 0.0, 10.0);
  EXPECT_FALSE(truth.covers(above, config.max_depth_m, nullptr));
  // KITTI's world is cam0 of frame 0 (y down): the ground below the car has y of about +1.7 m.
  std::vector<double> heights;
  for (const DepthRay& r : truth.rays) heights.push_back((r.origin_W + r.truth_depth_m * r.direction_W).y());
  std::nth_element(heights.begin(), heights.begin() + static_cast<long>(heights.size() * 9 / 10), heights.end());
  EXPECT_NEAR(heights[heights.size() * 9 / 10], 1.7, 0.4);
}

TEST(LidarTruth, NoScanInTheRangeIsAnError) {
  LidarTruthOptions options;
  options.poses_path = kPoses;
  options.first_frame = 100;
  options.last_frame = 120;
  EXPECT_THAT(errorOf([&] { readLidarTruth(kLidar, options, PinholeCamera{}, DepthComparisonConfig{}); }),
              ::testing::HasSubstr("no scan for frames 100 to 120"));
}

}  // namespace
}  // namespace terramesh::evaluation
