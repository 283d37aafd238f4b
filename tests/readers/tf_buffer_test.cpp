// The ROS bag reader's tf buffer (white box: datasets/src/tf_buffer.h): chains composed through
// the common ancestor, time-varying edges interpolated by poseAt's rule, static edges at any
// time, and trees the data breaks (two parents, cycles) refused.
#include "tf_buffer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace terramesh::test {
namespace {

using datasets::internal::TfBuffer;
using datasets::internal::TfLookupStatus;
using datasets::internal::TimedPose;
using Config = datasets::internal::TfBufferConfig;

TimedPose transform(double time_s, const Eigen::Vector3d& position, double yaw_rad) {
  TimedPose pose;
  pose.time_s = time_s;
  pose.position_W = position;
  pose.rotation_W_S = Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()));
  return pose;
}

/// map -> odom (static), odom -> base_link (time-varying: x = t, yaw = 0.1 t), base_link ->
/// velodyne (static: 0.5 m ahead, 1 m up, turned by pi/2), base_link -> imu (static).
TfBuffer robot() {
  TfBuffer tf;
  tf.addStatic("/map", "odom", transform(0.0, {10, 0, 0}, 0.0));
  for (int i = 0; i <= 10; ++i) {
    tf.addDynamic("odom", "base_link", transform(i * 0.1, {i * 0.1, 0, 0}, i * 0.01));
  }
  tf.addStatic("base_link", "velodyne", transform(0.0, {0.5, 0, 1}, M_PI / 2));
  tf.addStatic("base_link", "/imu", transform(0.0, {0, 0.2, 0}, 0.0));
  return tf;
}

TEST(TfBuffer, ComposesAChainThroughTheCommonAncestor) {
  const TfBuffer tf = robot();
  // map <- velodyne at t = 0.3: map -> odom -> base_link -> velodyne.
  const auto found = tf.lookup("map", "velodyne", 0.3);
  ASSERT_EQ(found.status, TfLookupStatus::kOk);
  const Eigen::Isometry3d map_T_odom = Eigen::Translation3d(10, 0, 0) * Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d odom_T_base =
      Eigen::Translation3d(0.3, 0, 0) * Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitZ());
  const Eigen::Isometry3d base_T_velodyne =
      Eigen::Translation3d(0.5, 0, 1) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  const Eigen::Isometry3d expected = map_T_odom * odom_T_base * base_T_velodyne;
  EXPECT_LT((found.pose.position_W - expected.translation()).norm(), 1e-12);
  EXPECT_LT(found.pose.rotation_W_S.angularDistance(Eigen::Quaterniond(expected.rotation())), 1e-12);
  // Across branches: the imu seen from the velodyne, through base_link (leading '/' ignored).
  const auto across = tf.lookup("/velodyne", "imu", 5.0);
  ASSERT_EQ(across.status, TfLookupStatus::kOk);
  const Eigen::Vector3d imu_in_velodyne =
      base_T_velodyne.inverse() * Eigen::Vector3d(0, 0.2, 0);
  EXPECT_LT((across.pose.position_W - imu_in_velodyne).norm(), 1e-12);
  EXPECT_EQ(tf.describePath("map", "velodyne"),
            "map -> odom -> base_link -> velodyne (map -> odom, base_link -> velodyne static)");
  EXPECT_EQ(tf.describePath("velodyne", "imu"),
            "velodyne <- base_link -> imu (base_link -> velodyne, base_link -> imu static)");
  EXPECT_EQ(tf.root("velodyne"), "map");
  EXPECT_EQ(tf.leaves("map"), (std::vector<std::string>{"imu", "velodyne"}));
  EXPECT_EQ(tf.staticEdges(), 3u);
  EXPECT_EQ(tf.dynamicEdges(), 1u);
}

TEST(TfBuffer, OneEdgeIsTakenBitForBitAndADynamicEdgeIsInterpolated) {
  const TfBuffer tf = robot();
  // At a stored stamp (7 * 0.1, as robot() wrote it): that transform, bit for bit.
  const TimedPose stored = transform(7 * 0.1, {7 * 0.1, 0, 0}, 7 * 0.01);
  const auto exact = tf.lookup("odom", "base_link", stored.time_s);
  ASSERT_EQ(exact.status, TfLookupStatus::kOk);
  EXPECT_EQ(exact.pose.position_W, stored.position_W);
  EXPECT_EQ(exact.pose.rotation_W_S.coeffs(), stored.rotation_W_S.coeffs());
  // Halfway between 0.2 and 0.3: linear position, slerped yaw.
  const auto middle = tf.lookup("odom", "base_link", 0.25);
  ASSERT_EQ(middle.status, TfLookupStatus::kOk);
  EXPECT_NEAR(middle.pose.position_W.x(), 0.25, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(middle.pose.rotation_W_S).angle(), 0.025, 1e-12);
  // Outside the transforms by more than the tolerance: none, naming the edge.
  const auto late = tf.lookup("map", "velodyne", 1.5);
  EXPECT_EQ(late.status, TfLookupStatus::kNoTransformAtTime);
  EXPECT_EQ(late.detail, "odom -> base_link");
  EXPECT_EQ(tf.lookup("map", "velodyne", 1.005).status, TfLookupStatus::kOk);
  // The same gap with a wider interval interpolates (the config's rule, as poseAt's).
  TfBuffer sparse(Config{0.05, 0.01});
  sparse.addDynamic("odom", "base_link", transform(0.0, {0, 0, 0}, 0));
  sparse.addDynamic("odom", "base_link", transform(0.1, {1, 0, 0}, 0));
  EXPECT_EQ(sparse.lookup("odom", "base_link", 0.05).status, TfLookupStatus::kNoTransformAtTime);
  const auto ends = sparse.dynamicSpan();
  ASSERT_TRUE(ends);
  EXPECT_EQ(ends->first, 0.0);
  EXPECT_EQ(ends->second, 0.1);
}

TEST(TfBuffer, StaticEdgesHoldAtAnyTime) {
  const TfBuffer tf = robot();
  for (const double time_s : {-1e9, 0.0, 0.35, 1e9}) {
    const auto found = tf.lookup("base_link", "velodyne", time_s);
    ASSERT_EQ(found.status, TfLookupStatus::kOk);
    EXPECT_EQ(found.pose.position_W, Eigen::Vector3d(0.5, 0, 1));
  }
  // A later static transform replaces the first, as a re-latched /tf_static does.
  TfBuffer relatched;
  relatched.addStatic("base_link", "camera", transform(0, {1, 0, 0}, 0));
  relatched.addStatic("base_link", "camera", transform(5, {2, 0, 0}, 0));
  EXPECT_EQ(relatched.lookup("base_link", "camera", 0).pose.position_W.x(), 2.0);
}

TEST(TfBuffer, UnknownAndDisconnectedFrames) {
  TfBuffer tf = robot();
  tf.addStatic("world", "gps", transform(0, {0, 0, 0}, 0));
  const auto unknown = tf.lookup("map", "lidar", 0.3);
  EXPECT_EQ(unknown.status, TfLookupStatus::kUnknownFrame);
  EXPECT_EQ(unknown.detail, "lidar");
  EXPECT_EQ(tf.lookup("map", "gps", 0.3).status, TfLookupStatus::kNotConnected);
  EXPECT_EQ(tf.describePath("map", "gps"), "");
  EXPECT_THROW(tf.root("lidar"), std::out_of_range);
}

std::string problemOf(TfBuffer& tf, const std::string& parent, const std::string& child) {
  try {
    tf.addStatic(parent, child, transform(0, {0, 0, 0}, 0));
  } catch (const datasets::internal::TfProblem& problem) {
    return problem.what();
  }
  return "";
}

TEST(TfBuffer, RefusesTwoParentsACycleAndMixedEdges) {
  TfBuffer tf = robot();
  EXPECT_EQ(problemOf(tf, "odom", "velodyne"),
            "frame \"velodyne\" has two parents: \"base_link\" and \"odom\"");
  EXPECT_EQ(problemOf(tf, "velodyne", "map"),
            "the edge velodyne -> map closes a cycle: \"map\" is already an ancestor of \"velodyne\"");
  EXPECT_EQ(problemOf(tf, "imu", "imu"), "frame \"imu\" is given as its own parent");
  EXPECT_EQ(problemOf(tf, "odom", "base_link"),
            "the edge odom -> base_link is both static and time-varying");
  // The refused edges left the tree as it was.
  EXPECT_EQ(tf.lookup("base_link", "velodyne", 0).pose.position_W, Eigen::Vector3d(0.5, 0, 1));
  EXPECT_EQ(tf.root("map"), "map");
}

TEST(TfBuffer, ConfigReportsEveryProblem) {
  EXPECT_TRUE(Config{}.problems().empty());
  EXPECT_EQ(Config({-1, NAN}).problems().size(), 2u);
  EXPECT_THROW(TfBuffer(Config{0.2, -1}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::test
