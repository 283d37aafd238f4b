#include "rosbag_pose_source.h"

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <sstream>

#include "rosbag_bag.h"

namespace terramesh::datasets::internal {
namespace {

void sortByTime(PoseTrack& track) {
  std::stable_sort(track.poses.begin(), track.poses.end(),
                   [](const TimedPose& a, const TimedPose& b) { return a.time_s < b.time_s; });
}

PoseTrack readPoseTopic(const rosbag::Bag& bag, const std::string& file, const std::string& topic,
                        std::string_view type) {
  PoseTrack track;
  track.source = topic + " (" + std::string(type) + ")";
  auto frames = [&track](const std_msgs::Header& header, const std::string& child) {
    if (!track.poses.empty()) return;
    track.world_frame = normalizedFrame(header.frame_id);
    track.sensor_frame = normalizedFrame(child);
  };
  if (type == kOdometryType) {
    forEachMessage<nav_msgs::Odometry>(
        bag, file, topic, type, [&](const nav_msgs::Odometry& m, std::size_t i) {
          frames(m.header, m.child_frame_id);
          track.poses.push_back(timedPose(file, topic, i, m.header.stamp.toSec(),
                                          m.pose.pose.position, m.pose.pose.orientation));
        });
  } else {
    forEachMessage<geometry_msgs::PoseStamped>(
        bag, file, topic, type, [&](const geometry_msgs::PoseStamped& m, std::size_t i) {
          frames(m.header, "");
          track.poses.push_back(timedPose(file, topic, i, m.header.stamp.toSec(), m.pose.position,
                                          m.pose.orientation));
        });
  }
  if (track.poses.empty())
    throw InputError(file, "topic " + topic, "has no " + std::string(type) + " message");
  sortByTime(track);
  return track;
}

bool hasTopic(const std::vector<RosbagTopic>& topics, const std::string& name) {
  return std::any_of(topics.begin(), topics.end(),
                     [&name](const RosbagTopic& topic) { return topic.name == name; });
}

/// Every transform on a tf topic into `tf`, static or time-varying.
/// @throw terramesh::InputError naming the message: a bad transform, two parents, a cycle.
std::size_t readTfTopic(const rosbag::Bag& bag, const std::string& file, const std::string& topic,
                        bool is_static, TfBuffer& tf) {
  std::size_t messages = 0;
  forEachMessage<tf2_msgs::TFMessage>(
      bag, file, topic, kTfMessageType, [&](const tf2_msgs::TFMessage& m, std::size_t i) {
        ++messages;
        for (const geometry_msgs::TransformStamped& t : m.transforms) {
          geometry_msgs::Point p;
          p.x = t.transform.translation.x;
          p.y = t.transform.translation.y;
          p.z = t.transform.translation.z;
          const TimedPose pose =
              timedPose(file, topic, i, t.header.stamp.toSec(), p, t.transform.rotation);
          try {
            if (is_static) {
              tf.addStatic(t.header.frame_id, t.child_frame_id, pose);
            } else {
              tf.addDynamic(t.header.frame_id, t.child_frame_id, pose);
            }
          } catch (const TfProblem& problem) {
            throw InputError(file, messageLocation(topic, i), std::string("tf: ") + problem.what());
          }
        }
      });
  return messages;
}

/// Reads the tf topics there are into source.tf; "/tf (N messages), /tf_static (M messages)".
std::string readTfTree(const rosbag::Bag& bag, const std::string& file,
                       const std::vector<RosbagTopic>& topics, const RosbagOptions& options,
                       bool dynamic_too, PoseSource& source) {
  std::string read;
  for (const bool is_static : {false, true}) {
    const std::string& name = is_static ? options.tf_static_topic : options.tf_topic;
    if ((!is_static && !dynamic_too) || !hasTopic(topics, name)) continue;
    std::string how;
    chooseTopic(file, topics, name, {kTfMessageType}, "tf", is_static ? "--tf-static-topic" : "--tf-topic",
                how);  // checks the type
    const std::size_t messages = readTfTopic(bag, file, name, is_static, source.tf);
    read += (read.empty() ? "" : ", ") + name + " (" + std::to_string(messages) + " messages)";
    source.tf_topics += (source.tf_topics.empty() ? "" : ", ") + name;
  }
  return read;
}

std::string inQuotes(const std::string& frame) { return "\"" + frame + "\""; }

std::string frameList(const TfBuffer& tf) {
  std::string list;
  for (const std::string& frame : tf.frames()) list += (list.empty() ? "" : ", ") + frame;
  return list;
}

std::string notInTree(const PoseSource& source, const std::string& what, const std::string& frame) {
  return what + " " + inQuotes(frame) + " is not in the tf tree of " + source.tf_topics +
         " (its frames: " + frameList(source.tf) + ")";
}

/// Posing from the tf tree: the world frame is --tf-frames' parent or the root of the cloud
/// frame's tree; sensor clouds are posed by their own frame, registered ones by the sensor frame
/// (--tf-frames' child, or the only leaf under the world frame).
CloudPosing tfPosing(const PoseSource& source, const std::string& file, const std::string& topic,
                     const std::string& frame, const RosbagOptions& options) {
  const TfBuffer& tf = source.tf;
  const std::string where = messageLocation(topic, 0);
  const std::string cloud = "PointCloud2 header.frame_id";
  const bool given = !options.tf_parent_frame.empty();
  const std::string child = normalizedFrame(options.tf_child_frame);
  CloudPosing posing;
  posing.world_frame = given ? normalizedFrame(options.tf_parent_frame) : "";
  for (const std::string& named : {posing.world_frame, child}) {
    if (given && !tf.hasFrame(named)) throw InputError(file, "", notInTree(source, "--tf-frames: frame", named));
  }
  if (!given) {
    if (!tf.hasFrame(frame)) throw InputError(file, where, notInTree(source, cloud, frame));
    posing.world_frame = tf.root(frame);
  }
  const std::string world_why = given ? "the world frame --tf-frames names" : "the tf tree's root";
  if (options.cloud_frame != CloudFrame::kAuto) {
    posing.in_world = options.cloud_frame == CloudFrame::kWorld;
    posing.reason = "as --cloud-frame says";
  } else {
    posing.in_world = frame == posing.world_frame;
    posing.reason = "its header.frame_id " + inQuotes(frame) + " is " +
                    (posing.in_world ? world_why : "in the tf tree under " + inQuotes(posing.world_frame));
  }
  if (!posing.in_world) {
    posing.sensor_frame = frame;
    if (!tf.hasFrame(frame)) {
      if (!given) throw InputError(file, where, notInTree(source, cloud, frame));
      posing.sensor_frame = posing.lookup_frame = child;  // --cloud-frame sensor: the child's frame
    }
  } else if (given) {
    posing.sensor_frame = posing.lookup_frame = child;
  } else {
    const std::vector<std::string> leaves = tf.leaves(posing.world_frame);
    if (leaves.size() != 1) {
      throw InputError(file, where,
                       cloud + " " + inQuotes(frame) + " is the world frame (registered points) and the tf tree under it has " +
                           std::to_string(leaves.size()) + " leaf frames: name the sensor with --tf-frames " +
                           posing.world_frame + " SENSOR");
    }
    posing.sensor_frame = posing.lookup_frame = leaves.front();
  }
  posing.chain = tf.describePath(posing.world_frame, posing.sensor_frame);
  if (posing.chain.empty()) {
    throw InputError(file, where,
                     "frame " + inQuotes(posing.sensor_frame) + " is in another tf tree than the world frame " +
                         inQuotes(posing.world_frame) + " (its root is " + inQuotes(tf.root(posing.sensor_frame)) + ")");
  }
  const std::string sensor_why =
      posing.in_world && !given ? " (the only leaf frame under " + inQuotes(posing.world_frame) + ")" : "";
  posing.chain = "poses: tf " + posing.chain + "; world frame " + inQuotes(posing.world_frame) + " (" +
                 world_why + "), sensor frame " + inQuotes(posing.sensor_frame) + sensor_why;
  return posing;
}

/// Posing from a pose topic: registered clouds in its frame, sensor clouds in its child frame or in a
/// frame below it on /tf_static (the static extrinsic is applied).
CloudPosing topicPosing(const PoseSource& source, const std::string& file, const std::string& topic,
                        const std::string& frame, const RosbagOptions& options) {
  const PoseTrack& track = source.track;
  CloudPosing posing;
  posing.world_frame = track.world_frame;
  posing.sensor_frame = track.sensor_frame;
  const std::string header = "its header.frame_id " + inQuotes(frame);
  const bool forced = options.cloud_frame != CloudFrame::kAuto;
  if (options.cloud_frame == CloudFrame::kWorld || (!forced && !frame.empty() && frame == track.world_frame)) {
    posing.in_world = true;
    posing.reason = forced ? "as --cloud-frame says" : header + " is the poses' frame";
    return posing;
  }
  if (!frame.empty() && frame == track.sensor_frame) {
    posing.reason = forced ? "as --cloud-frame says" : header + " is the poses' child frame";
    return posing;
  }
  const TfLookup extrinsic =
      track.sensor_frame.empty() ? TfLookup{TfLookupStatus::kUnknownFrame, {}, ""}
                                 : source.tf.lookup(track.sensor_frame, frame, 0.0);
  if (extrinsic.status == TfLookupStatus::kOk) {
    posing.extrinsic = extrinsic.pose;
    posing.sensor_frame = frame;
    posing.reason = forced ? "as --cloud-frame says" : header + " is below the poses' child frame on " + options.tf_static_topic;
    posing.chain = "poses: " + track.source + " " + track.world_frame + " -> " + track.sensor_frame + ", then " +
                   options.tf_static_topic + " " + source.tf.describePath(track.sensor_frame, frame) +
                   "; world frame " + inQuotes(track.world_frame) + ", sensor frame " + inQuotes(frame);
    return posing;
  }
  if (forced) {
    posing.reason = "as --cloud-frame says";
    return posing;
  }
  throw InputError(file, messageLocation(topic, 0),
                   "PointCloud2 header.frame_id " + inQuotes(frame) + " is neither the poses' frame " +
                       inQuotes(track.world_frame) + " nor their child frame " + inQuotes(track.sensor_frame) +
                       ", nor below it on " + options.tf_static_topic +
                       ": say which with --cloud-frame sensor|world");
}

}  // namespace

PoseSource readPoseSource(const rosbag::Bag& bag, const std::string& file,
                          const std::vector<RosbagTopic>& topics, const RosbagOptions& options,
                          std::vector<std::string>& notes) {
  PoseSource source(TfBufferConfig{options.max_pose_interval_s, options.pose_time_tolerance_s});
  const std::vector<std::string_view> pose_types{kOdometryType, kPoseStampedType};
  const bool any_tf = hasTopic(topics, options.tf_topic) || hasTopic(topics, options.tf_static_topic);
  std::string how;
  if (!options.tf_parent_frame.empty()) {
    source.from_tf = true;
    how = "as --tf-frames says";
  } else if (options.pose_topic.empty() && topicsOfType(topics, pose_types).empty() && any_tf) {
    source.from_tf = true;
    how = "the bag has no pose topic (" + std::string(kOdometryType) + " or " + std::string(kPoseStampedType) + ")";
  }
  if (!source.from_tf) {
    const RosbagTopic& topic = chooseTopic(file, topics, options.pose_topic, pose_types, "pose", "--pose-topic", how);
    source.track = readPoseTopic(bag, file, topic.name, topic.type);
    source.source = source.track.source;
    readTfTree(bag, file, topics, options, false, source);
    const PoseTrack& track = source.track;
    notes.push_back("poses from " + track.source + ", " + std::to_string(track.poses.size()) + " poses, " + how +
                    "; frame " + inQuotes(track.world_frame) +
                    (track.sensor_frame.empty() ? std::string() : ", child frame " + inQuotes(track.sensor_frame)));
    return source;
  }
  if (!any_tf) {
    chooseTopic(file, topics, options.tf_topic, {kTfMessageType}, "tf", "--tf-topic", how);  // throws
  }
  const std::string read = readTfTree(bag, file, topics, options, true, source);
  source.source = "tf on " + read;
  notes.push_back("poses from " + source.source + ", " + how + ": " + std::to_string(source.tf.dynamicEdges()) +
                  " time-varying and " + std::to_string(source.tf.staticEdges()) + " static edges");
  return source;
}

CloudPosing decidePosing(const PoseSource& source, const std::string& file, const std::string& topic,
                         const std::string& frame, const RosbagOptions& options) {
  return source.from_tf ? tfPosing(source, file, topic, frame, options)
                        : topicPosing(source, file, topic, frame, options);
}

std::optional<TimedPose> cloudPose(const PoseSource& source, const CloudPosing& posing, const std::string& file,
                                   const std::string& topic, std::size_t index, const std::string& frame,
                                   double time_s) {
  if (!source.from_tf) {
    const std::optional<TimedPose> pose =
        poseAt(source.track.poses, time_s, source.tf.config().max_interval_s, source.tf.config().tolerance_s);
    if (!pose || !posing.extrinsic) return pose;
    return composePoses(*pose, *posing.extrinsic);
  }
  const std::string& looked_up = posing.lookup_frame.empty() ? frame : posing.lookup_frame;
  const TfLookup found = source.tf.lookup(posing.world_frame, looked_up, time_s);
  switch (found.status) {
    case TfLookupStatus::kOk:
      return found.pose;
    case TfLookupStatus::kNoTransformAtTime:
      return std::nullopt;
    case TfLookupStatus::kUnknownFrame:
      throw InputError(file, messageLocation(topic, index),
                       notInTree(source, "PointCloud2 header.frame_id", looked_up));
    case TfLookupStatus::kNotConnected:
      break;
  }
  throw InputError(file, messageLocation(topic, index),
                   "PointCloud2 header.frame_id " + inQuotes(looked_up) + " is in another tf tree than the world frame " +
                       inQuotes(posing.world_frame));
}

std::string poseSpan(const PoseSource& source) {
  std::ostringstream span;
  span.precision(15);
  if (!source.from_tf) {
    span << "the poses " << source.source << " span " << source.track.poses.front().time_s << " to "
         << source.track.poses.back().time_s << " s";
  } else if (const auto times = source.tf.dynamicSpan()) {
    span << "the time-varying transforms of " << source.source << " span " << times->first << " to "
         << times->second << " s";
  } else {
    span << source.source << " has static transforms only";
  }
  return span.str();
}

}  // namespace terramesh::datasets::internal
