#include "datasets/point_cloud_index.h"

#include <cmath>
#include <stdexcept>

namespace terramesh::datasets {

PointCloudIndex::PointCloudIndex(std::vector<Eigen::Vector3d> points, double cell_size_m)
    : points_(std::move(points)), cell_size_(cell_size_m) {
  if (!(cell_size_m > 0) || !std::isfinite(cell_size_m)) {
    throw std::invalid_argument("PointCloudIndex: the cell size must be positive");
  }
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!points_[i].allFinite()) throw std::invalid_argument("PointCloudIndex: point " + std::to_string(i) + " is not finite");
    cells_[keyOf(points_[i])].push_back(static_cast<std::uint32_t>(i));
  }
}

PointCloudIndex::Key PointCloudIndex::keyOf(const Eigen::Vector3d& p) const {
  return {static_cast<std::int64_t>(std::floor(p.x() / cell_size_)),
          static_cast<std::int64_t>(std::floor(p.y() / cell_size_)),
          static_cast<std::int64_t>(std::floor(p.z() / cell_size_))};
}

std::optional<PointCloudIndex::Nearest> PointCloudIndex::nearest(const Eigen::Vector3d& query,
                                                                 double max_distance_m) const {
  const Key centre = keyOf(query);
  std::optional<Nearest> best;
  const auto max_shell = static_cast<std::int64_t>(std::ceil(max_distance_m / cell_size_));
  for (std::int64_t shell = 0; shell <= max_shell; ++shell) {
    // Every point in shell `shell` is at least (shell - 1) cells away: stop once that is farther.
    if (best && static_cast<double>(shell - 1) * cell_size_ > best->distance) break;
    for (std::int64_t di = -shell; di <= shell; ++di) {
      for (std::int64_t dj = -shell; dj <= shell; ++dj) {
        for (std::int64_t dk = -shell; dk <= shell; ++dk) {
          if (std::max({std::abs(di), std::abs(dj), std::abs(dk)}) != shell) continue;
          const auto it = cells_.find({centre.i + di, centre.j + dj, centre.k + dk});
          if (it == cells_.end()) continue;
          for (std::uint32_t index : it->second) {
            const double distance = (points_[index] - query).norm();
            if (distance <= max_distance_m && (!best || distance < best->distance)) best = Nearest{index, distance};
          }
        }
      }
    }
  }
  return best;
}

}  // namespace terramesh::datasets
