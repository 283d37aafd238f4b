#include "datasets/tum_trajectory.h"

#include <algorithm>
#include <cmath>

#include "common/input_error.h"
#include "text_lines.h"

namespace terramesh::datasets {

std::vector<StampedPose> readTumTrajectory(const std::filesystem::path& path) {
  internal::TextLineReader lines(path);
  std::vector<StampedPose> poses;
  std::vector<std::string_view> tokens;
  while (lines.nextTokens(tokens)) {
    lines.expectCount(tokens, 8, "timestamp tx ty tz qx qy qz qw");
    StampedPose pose;
    pose.time_s = lines.real(tokens[0], "timestamp");
    if (!poses.empty() && pose.time_s < poses.back().time_s) {
      lines.fail("timestamp " + std::string(tokens[0]) +
                 " is earlier than the previous pose's (expected poses in time order)");
    }
    const Eigen::Vector3d position(lines.real(tokens[1], "tx"), lines.real(tokens[2], "ty"),
                                   lines.real(tokens[3], "tz"));
    // Eigen's constructor takes w first; the file has it last.
    const Eigen::Quaterniond rotation(lines.real(tokens[7], "qw"), lines.real(tokens[4], "qx"),
                                      lines.real(tokens[5], "qy"), lines.real(tokens[6], "qz"));
    if (std::abs(rotation.norm() - 1.0) > 1e-2) {
      lines.fail("quaternion qx qy qz qw must have unit norm");
    }
    pose.pose_W_C.linear() = rotation.normalized().toRotationMatrix();
    pose.pose_W_C.translation() = position;
    poses.push_back(pose);
  }
  if (poses.empty())
    throw InputError(path.string(), "", "no poses (expected TUM trajectory lines)");
  return poses;
}

const StampedPose* nearestPose(const std::vector<StampedPose>& poses, double time_s,
                               double tolerance_s) {
  const auto after =
      std::lower_bound(poses.begin(), poses.end(), time_s,
                       [](const StampedPose& pose, double time) { return pose.time_s < time; });
  const StampedPose* best = nullptr;
  double best_gap_s = tolerance_s;
  for (auto it : {after, after == poses.begin() ? poses.end() : std::prev(after)}) {
    if (it == poses.end()) continue;
    const double gap_s = std::abs(it->time_s - time_s);
    if (gap_s <= best_gap_s) {
      best = &*it;
      best_gap_s = gap_s;
    }
  }
  return best;
}

}  // namespace terramesh::datasets
