#include "rosbag_bag.h"

#include <algorithm>
#include <map>

namespace terramesh::datasets::internal {
namespace {

std::string topicList(const std::vector<const RosbagTopic*>& topics) {
  std::string list;
  for (const RosbagTopic* topic : topics) {
    list += (list.empty() ? "" : ", ") + topic->name + " (" + topic->type + ", " +
            std::to_string(topic->messages) + " messages)";
  }
  return list;
}

}  // namespace

void openBag(const std::filesystem::path& path, rosbag::Bag& bag) {
  try {
    bag.open(path.string(), rosbag::bagmode::Read);
  } catch (const std::exception& error) {
    throw InputError(path.string(), "", std::string("cannot read as a ROS 1 bag: ") + error.what());
  }
}

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

std::vector<const RosbagTopic*> topicsOfType(const std::vector<RosbagTopic>& topics,
                                             const std::vector<std::string_view>& types) {
  std::vector<const RosbagTopic*> found;
  for (const RosbagTopic& topic : topics) {
    if (std::find(types.begin(), types.end(), topic.type) != types.end()) found.push_back(&topic);
  }
  return found;
}

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
  const std::vector<const RosbagTopic*> candidates = topicsOfType(topics, types);
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

}  // namespace terramesh::datasets::internal
