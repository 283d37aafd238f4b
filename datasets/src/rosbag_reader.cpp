#include "datasets/rosbag_reader.h"

#include <console_bridge/console.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/input_error.h"
#include "point_cloud2.h"
#include "rosbag_poses.h"

namespace terramesh::datasets {
namespace {

using internal::messageLocation;
using internal::normalizedFrame;
using internal::PoseTrack;
using internal::TimedPose;

/// Silences console_bridge, through which rosbag and cpp_common log what they then throw (libraries
/// do not print; the exception becomes the InputError), and restores its level on leaving. The
/// level is process-wide: another console_bridge user's messages are silenced meanwhile too.
class QuietRosLogging {
 public:
  QuietRosLogging() : level_(console_bridge::getLogLevel()) {
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  }
  ~QuietRosLogging() { console_bridge::setLogLevel(level_); }
  QuietRosLogging(const QuietRosLogging&) = delete;
  QuietRosLogging& operator=(const QuietRosLogging&) = delete;

 private:
  console_bridge::LogLevel level_;
};

void openBag(const std::filesystem::path& path, rosbag::Bag& bag) {
  try {
    bag.open(path.string(), rosbag::bagmode::Read);
  } catch (const std::exception& error) {
    throw InputError(path.string(), "", std::string("cannot read as a ROS 1 bag: ") + error.what());
  }
}

/// The topics of an open bag, by name; a topic's type is that of its first connection.
std::vector<RosbagTopic> topicsOf(const rosbag::Bag& bag) {
  std::map<std::string, RosbagTopic> topics;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* connection : all.getConnections()) {
    RosbagTopic& topic = topics[connection->topic];
    topic.name = connection->topic;
    if (topic.type.empty()) topic.type = connection->datatype;
  }
  std::vector<RosbagTopic> result;
  for (auto& [name, topic] : topics) {
    topic.messages = rosbag::View(bag, rosbag::TopicQuery(name)).size();
    result.push_back(topic);
  }
  return result;
}

/// Calls `use(message, index)` for every message on `topic`, in bag order.
/// @throw terramesh::InputError naming the message for one of another type or one that does not
///        decode.
template <class Message, class Use>
void forEachMessage(const rosbag::Bag& bag, const std::string& file, const std::string& topic,
                    std::string_view type, Use use) {
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  std::size_t index = 0;
  for (const rosbag::MessageInstance& instance : view) {
    boost::shared_ptr<const Message> message;
    try {
      message = instance.instantiate<Message>();
    } catch (const std::exception& error) {
      throw InputError(file, messageLocation(topic, index),
                       "cannot decode " + std::string(type) + ": " + error.what());
    }
    if (!message) {
      throw InputError(file, messageLocation(topic, index),
                       "is " + instance.getDataType() + ", expected " + std::string(type));
    }
    use(*message, index);
    ++index;
  }
}

TimedPose timedPose(const std::string& file, const std::string& topic, std::size_t index,
                    double time_s, const geometry_msgs::Point& p,
                    const geometry_msgs::Quaternion& q) {
  TimedPose pose;
  pose.time_s = time_s;
  pose.position_W = Eigen::Vector3d(p.x, p.y, p.z);
  const std::string problem =
      internal::poseProblem(pose.position_W, Eigen::Vector4d(q.x, q.y, q.z, q.w));
  if (!problem.empty()) throw InputError(file, messageLocation(topic, index), problem);
  pose.rotation_W_S = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized();
  return pose;
}

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
  if (type == internal::kOdometryType) {
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

PoseTrack readTfPoses(const rosbag::Bag& bag, const std::string& file, const std::string& topic,
                      const std::string& parent, const std::string& child) {
  PoseTrack track;
  track.world_frame = normalizedFrame(parent);
  track.sensor_frame = normalizedFrame(child);
  track.source = topic + " (" + std::string(internal::kTfMessageType) + ", " + track.world_frame +
                 " -> " + track.sensor_frame + ")";
  std::set<std::string> pairs;
  forEachMessage<tf2_msgs::TFMessage>(
      bag, file, topic, internal::kTfMessageType, [&](const tf2_msgs::TFMessage& m, std::size_t i) {
        for (const geometry_msgs::TransformStamped& t : m.transforms) {
          const std::string from = normalizedFrame(t.header.frame_id);
          const std::string to = normalizedFrame(t.child_frame_id);
          if (from != track.world_frame || to != track.sensor_frame) {
            if (pairs.size() < 20) pairs.insert(from + " -> " + to);
            continue;
          }
          const geometry_msgs::Vector3& v = t.transform.translation;
          geometry_msgs::Point p;
          p.x = v.x;
          p.y = v.y;
          p.z = v.z;
          track.poses.push_back(
              timedPose(file, topic, i, t.header.stamp.toSec(), p, t.transform.rotation));
        }
      });
  if (track.poses.empty()) {
    std::string found;
    for (const std::string& pair : pairs) found += (found.empty() ? "" : ", ") + pair;
    throw InputError(file, "topic " + topic,
                     "no transform " + track.world_frame + " -> " + track.sensor_frame +
                         " (the topic has: " + (found.empty() ? "none" : found) + ")");
  }
  sortByTime(track);
  return track;
}

std::string topicList(const std::vector<const RosbagTopic*>& topics) {
  std::string list;
  for (const RosbagTopic* topic : topics) {
    list += (list.empty() ? "" : ", ") + topic->name + " (" + topic->type + ", " +
            std::to_string(topic->messages) + " messages)";
  }
  return list;
}

/// The topic `wanted` (checked to be of one of `types`), or the bag's only topic of those types;
/// `how` says which of the two it was, for the run's report.
/// @throw terramesh::InputError: no such topic, another type, none or several candidates.
const RosbagTopic& chooseTopic(const std::string& file, const std::vector<RosbagTopic>& topics,
                               const std::string& wanted,
                               const std::vector<std::string_view>& types, const std::string& kind,
                               const std::string& flag, std::string& how) {
  auto typed = [&types](const RosbagTopic& topic) {
    return std::find(types.begin(), types.end(), topic.type) != types.end();
  };
  std::string expected;
  for (const std::string_view type : types)
    expected += (expected.empty() ? "" : " or ") + std::string(type);
  if (!wanted.empty()) {
    const auto it = std::find_if(topics.begin(), topics.end(), [&wanted](const RosbagTopic& topic) {
      return topic.name == wanted;
    });
    std::vector<const RosbagTopic*> all;
    for (const RosbagTopic& topic : topics) all.push_back(&topic);
    if (it == topics.end()) {
      throw InputError(file, "topic " + wanted,
                       "not in the bag (its topics: " + topicList(all) + ")");
    }
    if (!typed(*it)) {
      throw InputError(file, messageLocation(wanted, 0),
                       "is " + it->type + ", expected " + expected);
    }
    how = "as " + flag + " says";
    return *it;
  }
  std::vector<const RosbagTopic*> candidates;
  for (const RosbagTopic& topic : topics) {
    if (typed(topic)) candidates.push_back(&topic);
  }
  if (candidates.size() == 1) {
    how = "the bag's only " + kind + " topic";
    return *candidates.front();
  }
  if (candidates.empty()) {
    throw InputError(file, "", "no " + kind + " topic (" + expected + ") in the bag");
  }
  throw InputError(file, "",
                   std::to_string(candidates.size()) + " " + kind +
                       " topics: " + topicList(candidates) + "; choose one with " + flag);
}

/// Whether the clouds are in the world frame, from the first cloud's frame id unless the options
/// say; `reason` says why, for the run's report.
/// @throw terramesh::InputError naming the message when the frame id matches neither frame.
bool cloudsInWorld(const std::string& file, const std::string& topic,
                   const std::string& cloud_frame, const PoseTrack& track, CloudFrame option,
                   std::string& reason) {
  if (option != CloudFrame::kAuto) {
    reason = "as --cloud-frame says";
    return option == CloudFrame::kWorld;
  }
  if (!cloud_frame.empty() && cloud_frame == track.world_frame) {
    reason = "its header.frame_id \"" + cloud_frame + "\" is the poses' frame";
    return true;
  }
  if (!cloud_frame.empty() && cloud_frame == track.sensor_frame) {
    reason = "its header.frame_id \"" + cloud_frame + "\" is the poses' child frame";
    return false;
  }
  throw InputError(file, messageLocation(topic, 0),
                   "PointCloud2 header.frame_id \"" + cloud_frame +
                       "\" is neither the poses' frame \"" + track.world_frame +
                       "\" nor their child frame \"" + track.sensor_frame +
                       "\": say which with --cloud-frame sensor|world");
}

internal::CloudBytes cloudBytes(const sensor_msgs::PointCloud2& cloud) {
  internal::CloudBytes bytes;
  for (const sensor_msgs::PointField& field : cloud.fields) {
    bytes.fields.push_back({field.name, field.offset, field.datatype, field.count});
  }
  bytes.height = cloud.height;
  bytes.width = cloud.width;
  bytes.point_step = cloud.point_step;
  bytes.row_step = cloud.row_step;
  bytes.is_bigendian = cloud.is_bigendian != 0;
  bytes.data = cloud.data.data();
  bytes.size = cloud.data.size();
  return bytes;
}

/// What readRosbag learns while it reads the clouds, for the run's report.
struct CloudsRead {
  std::size_t clouds = 0, dropped = 0, points = 0, non_finite = 0;
  bool in_world = false;
  bool ids_from_field = false;
  std::string frame_id;      ///< the first cloud's
  std::string frame_reason;  ///< why in_world is what it is
  std::string lidar_filter;  ///< LidarScanFilter::describe() of clouds without ids
};

/// The keyframe of cloud `index`, posed by `pose`, with the decoded points.
mesher::Keyframe cloudKeyframe(std::size_t index, const TimedPose& pose,
                               const internal::DecodedCloud& cloud, bool in_world) {
  mesher::Keyframe keyframe;
  keyframe.id.value = index;
  keyframe.position_W_C = pose.position_W;
  keyframe.rotation_W_C = pose.rotation_W_S;
  const Eigen::Matrix3d rotation_W_S = pose.rotation_W_S.toRotationMatrix();
  keyframe.observations.reserve(cloud.positions.size());
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
    const std::uint64_t id =
        cloud.ids_from_field ? cloud.ids[i] : (std::uint64_t{index} << 32) | cloud.ids[i];
    keyframe.observations.push_back(
        {{id},
         in_world ? cloud.positions[i]
                  : Eigen::Vector3d(rotation_W_S * cloud.positions[i] + pose.position_W)});
  }
  return keyframe;
}

/// Every cloud on `topic` as a keyframe event of `stream`, posed from `track`.
/// @throw terramesh::InputError naming the message: a malformed cloud, a frame id that differs
///        from the first cloud's (deciding the frame from the data), ids in some clouds only.
CloudsRead readClouds(const rosbag::Bag& bag, const std::string& file, const std::string& topic,
                      const PoseTrack& track, const RosbagOptions& options, SlamStream& stream) {
  CloudsRead read;
  LidarScanFilter filter(options.lidar);
  forEachMessage<sensor_msgs::PointCloud2>(
      bag, file, topic, internal::kPointCloud2Type,
      [&](const sensor_msgs::PointCloud2& cloud, std::size_t index) {
        const std::string frame = normalizedFrame(cloud.header.frame_id);
        internal::DecodedCloud decoded;
        try {
          decoded = internal::decodeCloud(cloudBytes(cloud), options.point_id_field);
        } catch (const internal::CloudProblem& problem) {
          throw InputError(file, messageLocation(topic, index), problem.what());
        }
        if (read.clouds++ == 0) {
          read.frame_id = frame;
          read.in_world =
              cloudsInWorld(file, topic, frame, track, options.cloud_frame, read.frame_reason);
          read.ids_from_field = decoded.ids_from_field;
        } else if (options.cloud_frame == CloudFrame::kAuto && frame != read.frame_id) {
          throw InputError(file, messageLocation(topic, index),
                           "PointCloud2 header.frame_id \"" + frame +
                               "\" differs from the first cloud's \"" + read.frame_id +
                               "\" (say which frame the clouds are in with --cloud-frame)");
        }
        if (decoded.ids_from_field != read.ids_from_field) {
          throw InputError(file, messageLocation(topic, index),
                           "PointCloud2 " + std::string(decoded.ids_from_field ? "has" : "has no") +
                               " field \"" + options.point_id_field +
                               "\", unlike the first cloud (point ids must come from "
                               "every cloud or from none)");
        }
        const std::optional<TimedPose> pose =
            internal::poseAt(track.poses, cloud.header.stamp.toSec(), options.max_pose_interval_s,
                             options.pose_time_tolerance_s);
        if (!pose) {
          ++read.dropped;
          return;
        }
        read.points += decoded.positions.size();
        read.non_finite += decoded.non_finite_points;
        mesher::Keyframe keyframe = cloudKeyframe(index, *pose, decoded, read.in_world);
        if (!read.ids_from_field) {
          try {
            filter.filter(keyframe);
          } catch (const std::out_of_range& error) {
            throw InputError(file, messageLocation(topic, index), error.what());
          }
        }
        stream.events.emplace_back(std::move(keyframe));
        stream.keyframe_names[{index}] = topic + " message " + std::to_string(index);
      });
  if (!read.ids_from_field) read.lidar_filter = filter.describe();
  return read;
}

/// The sensor's up axis from its frame's name: REP 103 body frames have z up; optical frames
/// (REP 103's "_optical" suffix: z forward, y down) have -y up.
Eigen::Vector3d sensorUp(const std::string& sensor_frame) {
  return sensor_frame.find("optical") != std::string::npos
             ? Eigen::Vector3d(-Eigen::Vector3d::UnitY())
             : Eigen::Vector3d(Eigen::Vector3d::UnitZ());
}

/// The poses the options name, or those of the bag's only pose topic; `notes` say which.
PoseTrack readPoses(const rosbag::Bag& bag, const std::string& file,
                    const std::vector<RosbagTopic>& topics, const RosbagOptions& options,
                    std::vector<std::string>& notes) {
  std::string how;
  PoseTrack track;
  if (!options.tf_parent_frame.empty()) {
    const RosbagTopic& tf = chooseTopic(file, topics, options.tf_topic, {internal::kTfMessageType},
                                        "tf", "--tf-topic", how);
    track = readTfPoses(bag, file, tf.name, options.tf_parent_frame, options.tf_child_frame);
    how = "as --tf-frames says";
  } else {
    const RosbagTopic& topic = chooseTopic(file, topics, options.pose_topic,
                                           {internal::kOdometryType, internal::kPoseStampedType},
                                           "pose", "--pose-topic", how);
    track = readPoseTopic(bag, file, topic.name, topic.type);
  }
  notes.push_back("poses from " + track.source + ", " + std::to_string(track.poses.size()) +
                  " poses, " + how + "; frame \"" + track.world_frame + "\"" +
                  (track.sensor_frame.empty() ? std::string()
                                              : ", child frame \"" + track.sensor_frame + "\""));
  return track;
}

/// The stream's advice and notes that follow from the clouds: frame, ids, the sensor's up axis.
void describeClouds(const CloudsRead& read, const PoseTrack& track, const RosbagOptions& options,
                    SlamStream& stream) {
  stream.reader_notes.push_back(std::string("clouds in the ") +
                                (read.in_world
                                     ? "world frame (points used as they are)"
                                     : "sensor frame (points moved into the world by the pose)") +
                                ": " + read.frame_reason);
  if (read.ids_from_field) {
    stream.reader_notes.push_back("point ids from the field \"" + options.point_id_field + "\"");
  } else {
    stream.recommended_min_views = 1;
    stream.reader_notes.push_back(
        "no field \"" + options.point_id_field +
        (options.lidar.voxel_size_m > 0 ? "\": untracked LiDAR returns, min_views 1 advised"
                                        : "\": every return is its own point (seen once), min_views 1 advised"));
    stream.reader_notes.push_back(read.lidar_filter);
  }
  const std::string sensor_frame = !track.sensor_frame.empty() ? track.sensor_frame
                                   : read.in_world             ? std::string()
                                                               : read.frame_id;
  stream.sensor_up_S = sensorUp(sensor_frame);
  stream.reader_notes.push_back(
      "sensor up axis " + std::string(stream.sensor_up_S.z() > 0 ? "+z" : "-y") +
      (sensor_frame.empty() ? " (sensor frame unnamed: REP 103 body frame)"
                            : " (sensor frame \"" + sensor_frame + "\")"));
  if (read.non_finite > 0) {
    stream.reader_notes.push_back(std::to_string(read.non_finite) + " non-finite points skipped");
  }
}

std::string seconds(double value) {
  std::ostringstream out;
  out << value << " s";
  return out.str();
}

/// Notes and warnings on the clouds dropped for want of a pose.
/// @throw terramesh::InputError if every cloud was dropped.
void reportDropped(const std::string& file, const std::string& topic, const CloudsRead& read,
                   const PoseTrack& track, const RosbagOptions& options, SlamStream& stream) {
  if (read.dropped == 0) return;
  const std::string rule = "no pose at the stamp, none between two poses at most " +
                           seconds(options.max_pose_interval_s) + " apart, none within " +
                           seconds(options.pose_time_tolerance_s);
  const std::string counts = std::to_string(read.dropped) + " of " + std::to_string(read.clouds);
  if (read.dropped == read.clouds) {
    std::ostringstream span;
    span.precision(15);
    span << track.poses.front().time_s << " to " << track.poses.back().time_s << " s";
    throw InputError(file, "topic " + topic,
                     "all " + std::to_string(read.clouds) + " clouds dropped: " + rule +
                         " (the poses " + track.source + " span " + span.str() + ")");
  }
  stream.reader_notes.push_back(counts + " clouds dropped: " + rule);
  if (2 * read.dropped > read.clouds) {
    stream.reader_warnings.push_back("most clouds were dropped (" + counts + "): " + rule);
  }
}

}  // namespace

std::string_view toString(CloudFrame frame) {
  switch (frame) {
    case CloudFrame::kSensor:
      return "sensor";
    case CloudFrame::kWorld:
      return "world";
    case CloudFrame::kAuto:
      break;
  }
  return "auto";
}

std::vector<std::string> RosbagOptions::problems() const {
  std::vector<std::string> found;
  if (tf_parent_frame.empty() != tf_child_frame.empty()) {
    found.push_back("tf poses need both frames, parent and child");
  }
  if (!tf_parent_frame.empty() && !pose_topic.empty()) {
    found.push_back("give a pose topic or tf frames, not both");
  }
  if (!(max_pose_interval_s >= 0) || !std::isfinite(max_pose_interval_s)) {
    found.push_back("max_pose_interval_s must be a finite number >= 0");
  }
  if (!(pose_time_tolerance_s >= 0) || !std::isfinite(pose_time_tolerance_s)) {
    found.push_back("pose_time_tolerance_s must be a finite number >= 0");
  }
  for (const std::string& problem : lidar.problems()) found.push_back("lidar." + problem);
  return found;
}

std::vector<RosbagTopic> listRosbagTopics(const std::filesystem::path& path) {
  const QuietRosLogging quiet;
  rosbag::Bag bag;
  openBag(path, bag);
  return topicsOf(bag);
}

SlamStream readRosbag(const std::filesystem::path& path, const RosbagOptions& options) {
  if (const std::vector<std::string> problems = options.problems(); !problems.empty()) {
    std::string message = "readRosbag: invalid options:";
    for (const std::string& problem : problems) message += " " + problem + ";";
    message.pop_back();
    throw std::invalid_argument(message);
  }
  const std::string file = path.string();
  const QuietRosLogging quiet;
  rosbag::Bag bag;
  openBag(path, bag);
  const std::vector<RosbagTopic> topics = topicsOf(bag);
  SlamStream stream;
  std::string how;
  const RosbagTopic& cloud_topic =
      chooseTopic(file, topics, options.cloud_topic, {internal::kPointCloud2Type}, "PointCloud2",
                  "--cloud-topic", how);
  stream.reader_notes.push_back("clouds from " + cloud_topic.name + " (" + cloud_topic.type + ", " +
                                std::to_string(cloud_topic.messages) + " messages), " + how);
  const PoseTrack track = readPoses(bag, file, topics, options, stream.reader_notes);
  const CloudsRead read = readClouds(bag, file, cloud_topic.name, track, options, stream);
  if (read.clouds == 0)
    throw InputError(file, "topic " + cloud_topic.name, "has no PointCloud2 message");

  stream.metres_per_unit = 1.0;  // REP 103: metres
  stream.scale_known = true;
  stream.description = file + " (ROS bag: " + cloud_topic.name + ", poses " + track.source + ")";
  describeClouds(read, track, options, stream);
  reportDropped(file, cloud_topic.name, read, track, options, stream);
  return stream;
}

}  // namespace terramesh::datasets
