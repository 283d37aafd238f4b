#include "datasets/kitti_trajectory.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "common/atomic_file.h"

namespace terramesh::datasets {

void writeKittiPoses(const std::filesystem::path& path, const PoseList& poses_T_W_C) {
  writeFileAtomically(path, [&poses_T_W_C](std::ostream& out) {
    char number[32];
    for (const Eigen::Isometry3d& pose : poses_T_W_C) {
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 4; ++col) {
          std::snprintf(number, sizeof(number), "%.17g", pose.matrix()(row, col));
          out << number << (row == 2 && col == 3 ? '\n' : ' ');
        }
      }
    }
  });
}

PoseList selectFrames(const PoseList& poses, std::size_t first, std::size_t last) {
  last = std::min(last, poses.size());
  if (first >= last) {
    throw std::invalid_argument("frame range " + std::to_string(first) + ":" + std::to_string(last) +
                                " is empty (the trajectory has " + std::to_string(poses.size()) +
                                " frames)");
  }
  return PoseList(poses.begin() + static_cast<std::ptrdiff_t>(first),
                  poses.begin() + static_cast<std::ptrdiff_t>(last));
}

}  // namespace terramesh::datasets
