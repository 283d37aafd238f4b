#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

namespace terramesh::datasets {

/// Nearest-point queries on a fixed point cloud (e.g. a LiDAR ground truth), by hashing points
/// into cubic cells and searching shells of cells outwards. Const queries are thread-safe.
class PointCloudIndex {
 public:
  /// @param cell_size_m edge of the hash cells; about the typical spacing of the points is right.
  /// @throw std::invalid_argument for a non-positive cell size or a non-finite point.
  PointCloudIndex(std::vector<Eigen::Vector3d> points, double cell_size_m);

  struct Nearest {
    std::size_t index = 0;
    double distance = 0.0;
  };
  /// The nearest point no farther than `max_distance_m`, or nothing.
  std::optional<Nearest> nearest(const Eigen::Vector3d& query, double max_distance_m) const;

  const std::vector<Eigen::Vector3d>& points() const { return points_; }

 private:
  struct Key {
    std::int64_t i, j, k;
    bool operator==(const Key& o) const { return i == o.i && j == o.j && k == o.k; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& key) const noexcept {
      return static_cast<std::size_t>(static_cast<std::uint64_t>(key.i) * 73856093u ^
                                      static_cast<std::uint64_t>(key.j) * 19349663u ^
                                      static_cast<std::uint64_t>(key.k) * 83492791u);
    }
  };
  Key keyOf(const Eigen::Vector3d& p) const;

  std::vector<Eigen::Vector3d> points_;
  double cell_size_;
  std::unordered_map<Key, std::vector<std::uint32_t>, KeyHash> cells_;
};

}  // namespace terramesh::datasets
