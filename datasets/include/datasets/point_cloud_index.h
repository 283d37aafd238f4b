#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

namespace terramesh::datasets {

/// Nearest-point queries on a fixed point cloud (e.g. a LiDAR ground truth), on nanoflann's k-d
/// tree (leaf size 10). Distances are Euclidean, in the points' units, in double precision.
/// Building is O(N log N); a query visits O(log N) nodes on typical clouds. Const queries are
/// thread-safe. Movable, not copyable.
class PointCloudIndex {
 public:
  /// @throw std::invalid_argument for a non-finite point.
  explicit PointCloudIndex(std::vector<Eigen::Vector3d> points);
  ~PointCloudIndex();
  PointCloudIndex(PointCloudIndex&&) noexcept;
  PointCloudIndex& operator=(PointCloudIndex&&) noexcept;
  PointCloudIndex(const PointCloudIndex&) = delete;
  PointCloudIndex& operator=(const PointCloudIndex&) = delete;

  struct Nearest {
    std::size_t index = 0;   ///< into points()
    double distance = 0.0;   ///< to the query
  };
  /// The nearest point no farther than `max_distance_m`, or nothing (also for an empty cloud or a
  /// negative radius). Of points at exactly the same distance, any one may be returned.
  std::optional<Nearest> nearest(const Eigen::Vector3d& query, double max_distance_m) const;

  const std::vector<Eigen::Vector3d>& points() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terramesh::datasets
