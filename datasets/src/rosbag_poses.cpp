#include "rosbag_poses.h"

#include <algorithm>
#include <cmath>

namespace terramesh::datasets::internal {

std::string normalizedFrame(std::string_view frame_id) {
  const std::size_t first = frame_id.find_first_not_of('/');
  return first == std::string_view::npos ? std::string() : std::string(frame_id.substr(first));
}

std::string messageLocation(const std::string& topic, std::size_t index) {
  return "topic " + topic + ": message " + std::to_string(index);
}

std::string poseProblem(const Eigen::Vector3d& position, const Eigen::Vector4d& quaternion_xyzw) {
  if (!position.allFinite()) return "the position is not finite";
  if (!quaternion_xyzw.allFinite()) return "the orientation is not finite";
  if (std::abs(quaternion_xyzw.norm() - 1.0) > 1e-2) {
    return "the orientation quaternion has norm " + std::to_string(quaternion_xyzw.norm()) +
           ", expected 1 (within 1e-2)";
  }
  return "";
}

std::optional<TimedPose> poseAt(const std::vector<TimedPose>& poses, double time_s,
                                double max_interval_s, double tolerance_s) {
  const auto after =
      std::lower_bound(poses.begin(), poses.end(), time_s,
                       [](const TimedPose& pose, double time) { return pose.time_s < time; });
  if (after != poses.end() && after->time_s == time_s) return *after;
  if (after != poses.end() && after != poses.begin()) {
    const TimedPose& before = *std::prev(after);
    const double interval_s = after->time_s - before.time_s;
    if (interval_s <= max_interval_s) {
      const double a = (time_s - before.time_s) / interval_s;
      TimedPose pose;
      pose.time_s = time_s;
      pose.position_W = (1.0 - a) * before.position_W + a * after->position_W;
      pose.rotation_W_S = before.rotation_W_S.slerp(a, after->rotation_W_S).normalized();
      return pose;
    }
  }
  // Before the first pose, after the last or in a wide gap: the nearer neighbour, if close.
  const double gap_after_s = after == poses.end() ? tolerance_s + 1 : after->time_s - time_s;
  const double gap_before_s =
      after == poses.begin() ? tolerance_s + 1 : time_s - std::prev(after)->time_s;
  if (std::min(gap_after_s, gap_before_s) > tolerance_s) return std::nullopt;
  return gap_before_s <= gap_after_s ? *std::prev(after) : *after;
}

}  // namespace terramesh::datasets::internal
