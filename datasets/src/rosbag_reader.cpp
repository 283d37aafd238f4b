#include "datasets/rosbag_reader.h"

#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/input_error.h"
#include "point_cloud2.h"
#include "rosbag_bag.h"
#include "rosbag_pose_source.h"

namespace terramesh::datasets {
namespace {

using internal::CloudPosing;
using internal::messageLocation;
using internal::normalizedFrame;
using internal::PoseSource;
using internal::TimedPose;
using internal::chooseTopic;
using internal::forEachMessage;

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
  bool ids_from_field = false;
  std::string frame_id;  ///< the first cloud's
  CloudPosing posing;    ///< decided from the first cloud
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

/// Every cloud on `topic` as a keyframe event of `stream`, posed from `poses`.
/// @throw terramesh::InputError naming the message: a malformed cloud, a frame id that differs
///        from the first cloud's (deciding the frame from the data), a frame not in the tf tree,
///        ids in some clouds only.
CloudsRead readClouds(const rosbag::Bag& bag, const std::string& file, const std::string& topic,
                      const PoseSource& poses, const RosbagOptions& options, SlamStream& stream) {
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
          read.posing = internal::decidePosing(poses, file, topic, frame, options);
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
        const std::optional<TimedPose> pose = internal::cloudPose(
            poses, read.posing, file, topic, index, frame, cloud.header.stamp.toSec());
        if (!pose) {
          ++read.dropped;
          return;
        }
        read.points += decoded.positions.size();
        read.non_finite += decoded.non_finite_points;
        mesher::Keyframe keyframe = cloudKeyframe(index, *pose, decoded, read.posing.in_world);
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

/// The stream's advice and notes that follow from the clouds: frame, ids, the sensor's up axis.
void describeClouds(const CloudsRead& read, const RosbagOptions& options, SlamStream& stream) {
  if (!read.posing.chain.empty()) stream.reader_notes.push_back(read.posing.chain);
  stream.reader_notes.push_back(std::string("clouds in the ") +
                                (read.posing.in_world
                                     ? "world frame (points used as they are)"
                                     : "sensor frame (points moved into the world by the pose)") +
                                ": " + read.posing.reason);
  if (read.ids_from_field) {
    stream.reader_notes.push_back("point ids from the field \"" + options.point_id_field + "\"");
  } else {
    stream.recommended_min_views = 1;
    stream.recommended_steiner_step_m = kLidarSteinerStepM;
    stream.reader_notes.push_back(
        "no field \"" + options.point_id_field +
        (options.lidar.voxel_size_m > 0 ? "\": untracked LiDAR returns, min_views 1 advised"
                                        : "\": every return is its own point (seen once), min_views 1 advised"));
    stream.reader_notes.push_back(read.lidar_filter);
  }
  const std::string sensor_frame = !read.posing.sensor_frame.empty() ? read.posing.sensor_frame
                                   : read.posing.in_world             ? std::string()
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
                   const PoseSource& poses, const RosbagOptions& options, SlamStream& stream) {
  if (read.dropped == 0) return;
  const std::string rule = "no pose at the stamp, none between two poses at most " +
                           seconds(options.max_pose_interval_s) + " apart, none within " +
                           seconds(options.pose_time_tolerance_s);
  const std::string counts = std::to_string(read.dropped) + " of " + std::to_string(read.clouds);
  if (read.dropped == read.clouds) {
    throw InputError(file, "topic " + topic,
                     "all " + std::to_string(read.clouds) + " clouds dropped: " + rule + " (" +
                         internal::poseSpan(poses) + ")");
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
  const internal::QuietRosLogging quiet;
  rosbag::Bag bag;
  internal::openBag(path, bag);
  return internal::topicsOf(bag);
}

SlamStream readRosbag(const std::filesystem::path& path, const RosbagOptions& options) {
  if (const std::vector<std::string> problems = options.problems(); !problems.empty()) {
    std::string message = "readRosbag: invalid options:";
    for (const std::string& problem : problems) message += " " + problem + ";";
    message.pop_back();
    throw std::invalid_argument(message);
  }
  const std::string file = path.string();
  const internal::QuietRosLogging quiet;
  rosbag::Bag bag;
  internal::openBag(path, bag);
  const std::vector<RosbagTopic> topics = internal::topicsOf(bag);
  SlamStream stream;
  std::string how;
  const RosbagTopic& cloud_topic =
      chooseTopic(file, topics, options.cloud_topic, {internal::kPointCloud2Type}, "PointCloud2",
                  "--cloud-topic", how);
  stream.reader_notes.push_back("clouds from " + cloud_topic.name + " (" + cloud_topic.type + ", " +
                                std::to_string(cloud_topic.messages) + " messages), " + how);
  const PoseSource poses =
      internal::readPoseSource(bag, file, topics, options, stream.reader_notes);
  const CloudsRead read = readClouds(bag, file, cloud_topic.name, poses, options, stream);
  if (read.clouds == 0)
    throw InputError(file, "topic " + cloud_topic.name, "has no PointCloud2 message");

  stream.metres_per_unit = 1.0;  // REP 103: metres
  stream.scale_known = true;
  stream.description = file + " (ROS bag: " + cloud_topic.name + ", poses " + poses.source + ")";
  describeClouds(read, options, stream);
  reportDropped(file, cloud_topic.name, read, poses, options, stream);
  return stream;
}

}  // namespace terramesh::datasets
