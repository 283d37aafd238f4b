#pragma once
// The integer cell of a point in a cubic grid, and its hash: the one grid key the evaluation code
// and the comparison harness share.

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace terramesh::evaluation {

/// Index of a cell of a cubic grid (cell (i, j, k) covers [i c, (i + 1) c) along x, and so on).
struct CellKey {
  std::int64_t x = 0, y = 0, z = 0;
  friend bool operator==(const CellKey& a, const CellKey& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const noexcept {
    return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};

/// The cell of p in a grid of cubes `cell_m` wide (same units as p).
inline CellKey cellKeyOf(const Eigen::Vector3d& p, double cell_m) {
  return {static_cast<std::int64_t>(std::floor(p.x() / cell_m)), static_cast<std::int64_t>(std::floor(p.y() / cell_m)),
          static_cast<std::int64_t>(std::floor(p.z() / cell_m))};
}

}  // namespace terramesh::evaluation
