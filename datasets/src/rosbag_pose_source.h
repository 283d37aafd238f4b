#pragma once

// Where readRosbag's cloud poses come from: a pose topic (Odometry, PoseStamped), with the static
// tf tree for clouds in a frame below the poses' child frame, or the tf tree of /tf and
// /tf_static. Includes rosbag headers: only the bag reader's sources use it.
#include <rosbag/bag.h>

#include <optional>
#include <string>
#include <vector>

#include "datasets/rosbag_reader.h"
#include "rosbag_poses.h"
#include "tf_buffer.h"

namespace terramesh::datasets::internal {

/// What a bag holds for posing its clouds.
struct PoseSource {
  explicit PoseSource(const TfBufferConfig& config) : tf(config) {}

  bool from_tf = false;  ///< poses from the tf tree, not from a pose topic
  PoseTrack track;       ///< the pose topic's (not from_tf)
  TfBuffer tf;           ///< from_tf: /tf and /tf_static; else /tf_static only (maybe empty)
  std::string source;    ///< e.g. "/odom (nav_msgs/Odometry)" or "tf on /tf (9 messages), ..."
  std::string tf_topics;  ///< the tf topics read, e.g. "/tf, /tf_static"
};

/// How every cloud of the topic is posed, decided from the first cloud's frame.
struct CloudPosing {
  bool in_world = false;     ///< registered points, used as they are
  std::string world_frame;   ///< the frame the keyframes are in
  std::string sensor_frame;  ///< whose pose is the keyframe's; empty when unnamed (PoseStamped)
  /// tf: the frame looked up for every cloud; empty: each cloud's own header.frame_id.
  std::string lookup_frame;
  /// Pose topic: the cloud frame's pose in the poses' child frame, from /tf_static.
  std::optional<TimedPose> extrinsic;
  std::string reason;  ///< why in_world is what it is
  std::string chain;   ///< the path of transforms, for the run's report; empty for a pose alone
};

/// Reads the pose topic the options name (or the bag's only one) with /tf_static, or, with
/// --tf-frames or when the bag has no pose topic but has /tf or /tf_static, the tf tree.
/// `notes` say which.
/// @throw terramesh::InputError naming the file, topic and message: as chooseTopic, a bad pose,
///        a tf tree with a frame of two parents or a cycle.
PoseSource readPoseSource(const rosbag::Bag& bag, const std::string& file,
                          const std::vector<RosbagTopic>& topics, const RosbagOptions& options,
                          std::vector<std::string>& notes);

/// Decides from the first cloud's frame (`frame`, message 0 of `topic`) how the clouds are posed.
/// @throw terramesh::InputError naming the message: the frame is not in the tf tree, in another
///        tree than the world frame, or (pose topic) neither of the poses' frames.
CloudPosing decidePosing(const PoseSource& source, const std::string& file,
                         const std::string& topic, const std::string& frame,
                         const RosbagOptions& options);

/// The sensor pose of cloud `index` (in `frame`, stamped `time_s`), or none: dropped.
/// @throw terramesh::InputError naming the message if its frame is not in the tf tree.
std::optional<TimedPose> cloudPose(const PoseSource& source, const CloudPosing& posing,
                                   const std::string& file, const std::string& topic,
                                   std::size_t index, const std::string& frame, double time_s);

/// "the poses /odom (nav_msgs/Odometry) span 10 to 12 s", for the report of dropped clouds.
std::string poseSpan(const PoseSource& source);

}  // namespace terramesh::datasets::internal
