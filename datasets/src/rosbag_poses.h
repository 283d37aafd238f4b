#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace terramesh::datasets::internal {

/// The message types readRosbag knows, as a bag's connections name them.
inline constexpr std::string_view kPointCloud2Type = "sensor_msgs/PointCloud2";
inline constexpr std::string_view kOdometryType = "nav_msgs/Odometry";
inline constexpr std::string_view kPoseStampedType = "geometry_msgs/PoseStamped";
inline constexpr std::string_view kTfMessageType = "tf2_msgs/TFMessage";

/// A sensor pose at a header stamp: x_W = rotation_W_S * x_S + position_W (kept as read, so a
/// pose at a cloud's exact stamp reaches the keyframe bit for bit).
struct TimedPose {
  double time_s = 0.0;
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation_W_S = Eigen::Quaterniond::Identity();
};

/// The poses of one source, sorted by time (stable: equal stamps keep their bag order).
struct PoseTrack {
  std::vector<TimedPose> poses;
  std::string world_frame;   ///< the poses' header.frame_id (tf: the parent frame)
  std::string sensor_frame;  ///< Odometry's child_frame_id, tf's child; empty for PoseStamped
  std::string source;        ///< e.g. "/odom (nav_msgs/Odometry)", for what the run reports
};

/// A frame id without leading '/' (tf2 ignores them; ROS 1 bags have both spellings).
std::string normalizedFrame(std::string_view frame_id);

/// Where a message is, for terramesh::InputError: "topic /points: message 12".
std::string messageLocation(const std::string& topic, std::size_t index);

/// What is wrong with a pose read from a message (non-finite, quaternion off unit norm by more
/// than 1e-2), or empty.
std::string poseProblem(const Eigen::Vector3d& position, const Eigen::Vector4d& quaternion_xyzw);

/// The pose at `time_s`: a pose at exactly that stamp as it is; else the interpolation (linear
/// position, slerp rotation) of the poses just before and after when they are at most
/// `max_interval_s` apart; else the nearest pose within `tolerance_s`; else none. O(log n).
std::optional<TimedPose> poseAt(const std::vector<TimedPose>& poses, double time_s,
                                double max_interval_s, double tolerance_s);

}  // namespace terramesh::datasets::internal
