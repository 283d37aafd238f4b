#include <gtest/gtest.h>

#include <fstream>

#include "common/input_error.h"
#include "datasets/kitti_odometry_reader.h"
#include "datasets/kitti_trajectory.h"
#include "test_support/temp_dir.h"

namespace terramesh::datasets {
namespace {

const std::string kKitti00 = std::string(TERRAMESH_SHARED_DIR) + "/data/kitti_poses/00.txt";

TEST(KittiPosesTest, RealSequence00) {
  const PoseList poses = readKittiPoses(kKitti00);
  ASSERT_EQ(poses.size(), 4541u);
  EXPECT_TRUE(poses.front().isApprox(Eigen::Isometry3d::Identity(), 1e-6));
  double travelled = 0.0;
  for (std::size_t i = 1; i < poses.size(); ++i) travelled += (poses[i].translation() - poses[i - 1].translation()).norm();
  EXPECT_NEAR(travelled, 3724.0, 20.0) << "KITTI 00 is 3.7 km";
  // The car drives forward: camera z (forward) along the motion.
  const Eigen::Vector3d motion = poses[20].translation() - poses[10].translation();
  EXPECT_GT(motion.normalized().dot(poses[15].linear().col(2)), 0.95);
}

TEST(KittiPosesTest, WrittenPosesReadBackAndFramesSelect) {
  test::TempDir dir;
  const PoseList poses = selectFrames(readKittiPoses(kKitti00), 100, 130);
  ASSERT_EQ(poses.size(), 30u);
  writeKittiPoses(dir / "t.txt", poses);
  const PoseList read = readKittiPoses(dir / "t.txt");
  ASSERT_EQ(read.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) EXPECT_TRUE(read[i].isApprox(poses[i], 1e-15));
  EXPECT_EQ(selectFrames(poses, 25, 1000).size(), 5u) << "the end is clamped";
  EXPECT_THROW(selectFrames(poses, 30, 40), std::invalid_argument);
}

TEST(KittiPosesTest, BadFilesNameFileAndLine) {
  test::TempDir dir;
  try {
    readKittiPoses(dir / "missing.txt");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("missing.txt"), std::string::npos);
  }
  std::ofstream(dir / "bad.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n";
  try {
    readKittiPoses(dir / "bad.txt");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bad.txt"), std::string::npos);
    EXPECT_EQ(error.where(), "line 3");
  }
}

}  // namespace
}  // namespace terramesh::datasets
