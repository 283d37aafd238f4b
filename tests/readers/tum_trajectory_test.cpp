#include "datasets/tum_trajectory.h"

#include <gtest/gtest.h>

#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

class TumTrajectoryTest : public ::testing::Test {
 protected:
  std::vector<datasets::StampedPose> read(const std::string& text) {
    writeFile(path_, text);
    return datasets::readTumTrajectory(path_);
  }
  InputError readBad(const std::string& text) {
    writeFile(path_, text);
    return expectInputError([&] { datasets::readTumTrajectory(path_); });
  }
  TempDir dir_;
  std::filesystem::path path_ = dir_ / "trajectory.txt";
};

TEST_F(TumTrajectoryTest, ReadsPosesWithCommentsAndBlankLines) {
  // The second pose turns 90 degrees about z: q = (x y z w) = (0 0 sin45 cos45).
  const auto poses = read(
      "# ground truth trajectory\n"
      "# timestamp tx ty tz qx qy qz qw\n"
      "1305031102.175304 1.3405 0.6266 1.6575 0 0 0 1\n"
      "\n"
      "1305031102.211214 1.3 0.6 1.6 0 0 0.70710678118654757 0.70710678118654757\n");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_DOUBLE_EQ(poses[0].time_s, 1305031102.175304);
  EXPECT_EQ(poses[0].pose_W_C.translation(), Eigen::Vector3d(1.3405, 0.6266, 1.6575));
  EXPECT_TRUE(poses[0].pose_W_C.linear().isIdentity(1e-15));
  const Eigen::Vector3d x_axis_W = poses[1].pose_W_C.linear() * Eigen::Vector3d::UnitX();
  EXPECT_LT((x_axis_W - Eigen::Vector3d::UnitY()).norm(), 1e-15);
}

TEST_F(TumTrajectoryTest, NearestPoseWithinTolerance) {
  const auto poses = read("0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n");
  EXPECT_EQ(datasets::nearestPose(poses, 1.004, 0.01), &poses[1]);
  EXPECT_EQ(datasets::nearestPose(poses, 0.996, 0.01), &poses[1]);
  EXPECT_EQ(datasets::nearestPose(poses, -0.005, 0.01), &poses[0]);
  EXPECT_EQ(datasets::nearestPose(poses, 2.009, 0.01), &poses[2]);
  EXPECT_EQ(datasets::nearestPose(poses, 1.5, 0.01), nullptr);
  EXPECT_EQ(datasets::nearestPose(poses, 3.0, 0.01), nullptr);
}

TEST_F(TumTrajectoryTest, BadLinesNameTheLine) {
  expectErrorAt(readBad("# c\n0 0 0 0 0 0 1\n"), path_, "line 2", "8 fields, got 7");
  expectErrorAt(readBad("0 0 0 0 0 0 0 1\n1 0 nan 0 0 0 0 1\n"), path_, "line 2",
                "ty: expected a finite number");
  expectErrorAt(readBad("0 0 0 0 0 0 0 2\n"), path_, "line 1", "unit norm");
  expectErrorAt(readBad("5 0 0 0 0 0 0 1\n4 0 0 0 0 0 0 1\n"), path_, "line 2", "earlier");
  expectErrorAt(readBad("0 0 0 0 0 0 0 one\n"), path_, "line 1", "qw: expected a number");
  expectErrorAt(readBad("# only a comment\n"), path_, "", "no poses");
}

}  // namespace
}  // namespace terramesh::test
