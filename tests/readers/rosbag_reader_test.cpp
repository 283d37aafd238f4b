// The ROS bag reader's ROS-free parts (white box: datasets/src): the PointCloud2 decoder and the
// rule that poses a cloud. Whole bags are written by python3-rosbag in cli_rosbag_test.py.
#include "datasets/rosbag_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "datasets/stream_reader.h"
#include "point_cloud2.h"
#include "reader_test_util.h"
#include "rosbag_poses.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

using datasets::internal::CloudBytes;
using datasets::internal::CloudProblem;
using datasets::internal::decodeCloud;
using datasets::internal::poseAt;
using datasets::internal::TimedPose;

constexpr std::uint8_t kUint16 = 4, kInt32 = 5, kUint32 = 6, kFloat32 = 7, kFloat64 = 8;

/// A cloud of `points` records: float64 x, float32 y, float32 z, then `id` (int32), padded to 24
/// bytes a point, in `rows` rows with 8 bytes of padding at the end of each row.
struct TestCloud {
  std::vector<unsigned char> bytes;
  CloudBytes view;

  TestCloud(const std::vector<Eigen::Vector3d>& points, const std::vector<std::int32_t>& ids,
            std::uint32_t rows) {
    view.fields = {{"x", 0, kFloat64, 1},
                   {"y", 8, kFloat32, 1},
                   {"z", 12, kFloat32, 1},
                   {"id", 16, kInt32, 1}};
    view.point_step = 24;
    view.height = rows;
    view.width = static_cast<std::uint32_t>(points.size()) / rows;
    view.row_step = view.width * view.point_step + 8;
    bytes.assign(std::size_t{view.row_step} * rows, 0xAB);
    for (std::size_t i = 0; i < points.size(); ++i) {
      unsigned char* point =
          bytes.data() + (i / view.width) * view.row_step + (i % view.width) * view.point_step;
      const double x = points[i].x();
      const float y = static_cast<float>(points[i].y()), z = static_cast<float>(points[i].z());
      std::memcpy(point, &x, 8);
      std::memcpy(point + 8, &y, 4);
      std::memcpy(point + 12, &z, 4);
      std::memcpy(point + 16, &ids[i], 4);
    }
    view.data = bytes.data();
    view.size = bytes.size();
  }
};

std::string problemOf(const CloudBytes& cloud, std::string_view id_field = "id") {
  try {
    decodeCloud(cloud, id_field);
  } catch (const CloudProblem& problem) {
    return problem.what();
  }
  return "";
}

TEST(RosbagCloud, DecodesRowsPaddingMixedTypesAndIds) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const TestCloud cloud({{0.1, 1, 2}, {nan, 0, 0}, {3.25, -4, 5}, {6, 7, 8}}, {10, 11, 12, 13}, 2);
  const auto decoded = decodeCloud(cloud.view, "id");
  EXPECT_TRUE(decoded.ids_from_field);
  EXPECT_EQ(decoded.non_finite_points, 1u);
  ASSERT_EQ(decoded.positions.size(), 3u);
  EXPECT_EQ(decoded.positions[0], Eigen::Vector3d(0.1, 1, 2));  // float64 x kept exactly
  EXPECT_EQ(decoded.positions[1], Eigen::Vector3d(3.25, -4, 5));
  EXPECT_EQ(decoded.ids, (std::vector<std::uint64_t>{10, 12, 13}));
  // Without the id field (or another name), ids are the points' indices, skipped ones counted.
  const auto indexed = decodeCloud(cloud.view, "track");
  EXPECT_FALSE(indexed.ids_from_field);
  EXPECT_EQ(indexed.ids, (std::vector<std::uint64_t>{0, 2, 3}));
}

TEST(RosbagCloud, RefusesWhatItCannotRead) {
  const TestCloud twice({{0, 0, 0}, {1, 1, 1}}, {4, 4}, 1);
  EXPECT_EQ(problemOf(twice.view),
            "point 1: point id 4 is listed twice in this cloud (first at point 0)");
  EXPECT_EQ(problemOf(twice.view, ""), "");
  EXPECT_EQ(problemOf(TestCloud({{0, 0, 0}}, {-3}, 1).view),
            "point 0: field \"id\" is -3, expected a point id >= 0");
  TestCloud cloud({{0, 0, 0}, {1, 1, 1}}, {4, 5}, 1);
  EXPECT_EQ(problemOf(cloud.view), "");
  cloud.view.fields[3].datatype = kFloat32;
  EXPECT_EQ(problemOf(cloud.view),
            "PointCloud2 field \"id\" is float32, expected one integer (the point id)");
  cloud.view.fields[3].datatype = kUint16;
  EXPECT_EQ(problemOf(cloud.view), "");
  cloud.view.fields[2].name = "intensity";
  EXPECT_EQ(problemOf(cloud.view), "PointCloud2 has no field \"z\"");
  cloud.view.fields[2].name = "z";
  cloud.view.fields[1].datatype = kUint32;
  EXPECT_EQ(problemOf(cloud.view),
            "PointCloud2 field \"y\" is uint32, expected float32 or float64");
  cloud.view.fields[1].datatype = kFloat32;
  cloud.view.fields[0].offset = 20;
  EXPECT_EQ(problemOf(cloud.view),
            "PointCloud2 field \"x\" (offset 20, float64) ends beyond point_step 24");
  cloud.view.fields[0].offset = 0;
  cloud.view.size -= 1;
  EXPECT_EQ(problemOf(cloud.view),
            "PointCloud2 data has 55 bytes, expected row_step 56 x height 1");
  cloud.view.size += 1;
  cloud.view.is_bigendian = true;
  EXPECT_EQ(problemOf(cloud.view),
            "PointCloud2 is big-endian (only little-endian clouds are read)");
}

TimedPose pose(double time_s, double x, double yaw_rad) {
  TimedPose p;
  p.time_s = time_s;
  p.position_W = Eigen::Vector3d(x, 0, 0);
  p.rotation_W_S = Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()));
  return p;
}

TEST(RosbagPoses, ExactStampThenInterpolationThenNearestWithinTolerance) {
  const std::vector<TimedPose> poses = {pose(1.0, 0, 0), pose(1.1, 1, 0.2), pose(2.0, 5, 0)};
  // At a pose's stamp: that pose, bit for bit.
  const auto exact = poseAt(poses, 1.1, 0.2, 0.01);
  ASSERT_TRUE(exact);
  EXPECT_EQ(exact->position_W, poses[1].position_W);
  EXPECT_EQ(exact->rotation_W_S.coeffs(), poses[1].rotation_W_S.coeffs());
  // Between two poses 0.1 s apart: linear position, slerped rotation.
  const auto middle = poseAt(poses, 1.05, 0.2, 0.01);
  ASSERT_TRUE(middle);
  EXPECT_NEAR(middle->position_W.x(), 0.5, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(middle->rotation_W_S).angle(), 0.1, 1e-12);
  // In the 0.9 s gap: only within the tolerance of a neighbour.
  EXPECT_FALSE(poseAt(poses, 1.5, 0.2, 0.01));
  const auto near_end = poseAt(poses, 1.995, 0.2, 0.01);
  ASSERT_TRUE(near_end);
  EXPECT_EQ(near_end->position_W.x(), 5.0);
  EXPECT_TRUE(poseAt(poses, 1.5, 1.0, 0.01));
  // Before the first pose and after the last.
  EXPECT_EQ(poseAt(poses, 0.995, 0.2, 0.01)->position_W.x(), 0.0);
  EXPECT_FALSE(poseAt(poses, 0.9, 0.2, 0.01));
  EXPECT_FALSE(poseAt(poses, 2.1, 0.2, 0.01));
  EXPECT_FALSE(poseAt({}, 1.0, 0.2, 0.01));
}

TEST(RosbagReader, DetectedByExtensionAndRefusedWhenNotABag) {
  TempDir dir;
  writeFile(dir / "junk.bag", "#ROSBAG V2.0\nnot really");
  EXPECT_EQ(datasets::detectStreamFormat(dir / "junk.bag"), datasets::StreamFormat::kRosbag);
  expectErrorAt(expectInputError([&] { datasets::readAnyStream(dir / "junk.bag"); }),
                dir / "junk.bag", "", "cannot read as a ROS 1 bag");
  datasets::RosbagOptions options;
  options.tf_parent_frame = "map";
  options.max_pose_interval_s = -1;
  EXPECT_EQ(options.problems(),
            (std::vector<std::string>{"tf poses need both frames, parent and child",
                                      "max_pose_interval_s must be a finite number >= 0"}));
  EXPECT_THROW(datasets::readRosbag(dir / "junk.bag", options), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::test
