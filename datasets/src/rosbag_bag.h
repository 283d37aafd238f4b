#pragma once

// The ROS 1 bag plumbing readRosbag's parts share: opening, topics, typed messages, poses read
// from messages. Includes rosbag and message headers: only the bag reader's sources use it.
#include <console_bridge/console.h>
#include <geometry_msgs/Point.h>
#include <geometry_msgs/Quaternion.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "common/input_error.h"
#include "datasets/rosbag_reader.h"
#include "rosbag_poses.h"

namespace terramesh::datasets::internal {

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

/// @throw terramesh::InputError naming the file if it cannot be read as a bag.
void openBag(const std::filesystem::path& path, rosbag::Bag& bag);

/// The topics of an open bag, by name; a topic's type is that of its first connection.
std::vector<RosbagTopic> topicsOf(const rosbag::Bag& bag);

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

/// The pose in a message, checked (finite, unit quaternion within 1e-2) and normalized.
/// @throw terramesh::InputError naming the message otherwise.
TimedPose timedPose(const std::string& file, const std::string& topic, std::size_t index,
                    double time_s, const geometry_msgs::Point& p,
                    const geometry_msgs::Quaternion& q);

/// The topics of one of `types`.
std::vector<const RosbagTopic*> topicsOfType(const std::vector<RosbagTopic>& topics,
                                             const std::vector<std::string_view>& types);

/// The topic `wanted` (checked to be of one of `types`), or the bag's only topic of those types;
/// `how` says which of the two it was, for the run's report.
/// @throw terramesh::InputError: no such topic, another type, none or several candidates.
const RosbagTopic& chooseTopic(const std::string& file, const std::vector<RosbagTopic>& topics,
                               const std::string& wanted,
                               const std::vector<std::string_view>& types, const std::string& kind,
                               const std::string& flag, std::string& how);

}  // namespace terramesh::datasets::internal
