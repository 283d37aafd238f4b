#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/lidar_scan_filter.h"
#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// Which frame the points of a bag's clouds are in.
enum class CloudFrame {
  kAuto,    ///< decided from the first cloud's header.frame_id against the poses' frame ids
  kSensor,  ///< the sensor's frame: moved into the world by the sensor's pose
  kWorld,   ///< already registered in the poses' world frame: used as they are
};

/// The name of a cloud frame as `--cloud-frame` spells it: auto, sensor, world.
std::string_view toString(CloudFrame frame);

/// How readRosbag picks its topics and matches clouds to poses. Times in seconds.
struct RosbagOptions {
  /// The sensor_msgs/PointCloud2 topic; empty: the bag's only PointCloud2 topic.
  std::string cloud_topic;
  /// The nav_msgs/Odometry or geometry_msgs/PoseStamped topic; empty: the bag's only topic of
  /// either type (unless tf frames are given). A cloud in a frame below the poses' child frame
  /// on tf_static_topic is moved by that static extrinsic too.
  std::string pose_topic;
  /// Both set: the poses come from the tf tree of tf_topic and tf_static_topic (also used, with
  /// the world frame the root of the cloud frame's tree, when the bag has no pose topic):
  /// tf_parent_frame is the world frame, tf_child_frame the sensor frame; chains are composed.
  /// Leading '/' are ignored.
  std::string tf_parent_frame;
  std::string tf_child_frame;
  std::string tf_topic = "/tf";                ///< time-varying transforms (tf2_msgs/TFMessage)
  std::string tf_static_topic = "/tf_static";  ///< static transforms (tf2_msgs/TFMessage)
  CloudFrame cloud_frame = CloudFrame::kAuto;
  /// A cloud between two poses at most this far apart takes their interpolation (linear
  /// position, slerp rotation); a pose at the cloud's exact stamp is taken as it is.
  double max_pose_interval_s = 0.2;
  /// Otherwise (before the first pose, after the last, in a wider gap) the nearest pose within
  /// this; a cloud with none is dropped and counted.
  double pose_time_tolerance_s = 0.01;
  /// An integer field of this name gives the point ids (tracked points keep their identity
  /// across keyframes); without it, every return is its own point.
  std::string point_id_field = "id";
  /// Clouds without the point-id field (LiDAR returns): range limits, voxels and merging across
  /// clouds (LidarScanFilter). The reader's default keeps every return; `LidarScanOptions()`
  /// holds the LiDAR defaults that `terramesh` uses. Clouds with ids are used as they are.
  LidarScanOptions lidar = LidarScanOptions::everyReturn();

  /// Every problem with these options (empty when valid).
  std::vector<std::string> problems() const;
};

/// One topic of a bag: its name, message type (e.g. "sensor_msgs/PointCloud2") and count.
struct RosbagTopic {
  std::string name;
  std::string type;
  std::size_t messages = 0;
};

/// The topics of a ROS 1 bag, by name (no ROS master needed).
/// @throw terramesh::InputError naming the file if it cannot be read as a bag.
std::vector<RosbagTopic> listRosbagTopics(const std::filesystem::path& path);

/// Reads a ROS 1 bag of LiDAR (or visual) SLAM output as a stream: each PointCloud2 of the cloud
/// topic becomes one keyframe event (id = its index on the topic, in bag order), posed by the
/// pose topic (or the tf tree: the transform from the world frame to the cloud's frame, as tf2's
/// lookupTransform) at the cloud's header stamp as RosbagOptions says. Points are the finite
/// x y z (float32 or float64) of the cloud; with the point-id field their ids come from it, else
/// point id = keyframe id << 32 | index of the point in the cloud, the stream advises
/// min_views 1 and `options.lidar` filters the clouds as the KITTI reader does its scans. Units are metres (REP 103): metres_per_unit = 1, known. The sensor's up axis is
/// +z (REP 103 body frames), -y for an optical frame (a child frame named "*optical*").
/// `SlamStream::reader_notes` says which topics, frame and id field were used and what was
/// dropped; `reader_warnings` when most clouds were dropped.
/// @throw std::invalid_argument if `options` are invalid (see problems()).
/// @throw terramesh::InputError naming the file, and the topic, message type and message index
///        where one is at fault: not a bag, a missing topic or one of the wrong type, several
///        candidates and no choice (naming them), a cloud without x, y or z, a malformed cloud,
///        no pose at all, a cloud frame not in the tf tree, a tf frame with two parents or a
///        cycle, no cloud kept.
SlamStream readRosbag(const std::filesystem::path& path, const RosbagOptions& options = {});

}  // namespace terramesh::datasets
