#pragma once

// Horizontal geometry shared by the trajectory evidence's parts (internal): the frame check and a
// horizontal bucket grid in the plan frame of up (common/plan_frame.h).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

#include "common/grid_key.h"
#include "common/plan_frame.h"

namespace terramesh::traversability::internal {

/// @throw std::invalid_argument unless `up_W` is a finite unit vector and `metres_per_unit` > 0.
inline void requireFrame(const Eigen::Vector3d& up_W, double metres_per_unit) {
  if (!up_W.allFinite() || std::abs(up_W.norm() - 1.0) > 1e-6) {
    throw std::invalid_argument("trajectory evidence: up must be a finite unit vector");
  }
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    throw std::invalid_argument("trajectory evidence: metres_per_unit must be finite and > 0");
  }
}

/// Values (point indices, keyframe ids) bucketed by the horizontal grid cell of a position.
template <class Value>
class HorizontalGrid {
 public:
  explicit HorizontalGrid(double cell) : cell_(cell) {}
  /// Point i's index under its position (cell size = the search radius).
  HorizontalGrid(const std::vector<Eigen::Vector3d>& points, const geometry::PlanFrame& plane, double cell)
      : cell_(cell) {
    for (std::size_t i = 0; i < points.size(); ++i) add(plane.project(points[i]), static_cast<Value>(i));
  }
  void add(const Eigen::Vector2d& at, Value value) { cells_[key(at)].push_back(value); }
  /// Removes one `value` listed under `at` (nothing if it is not there).
  void erase(const Eigen::Vector2d& at, Value value) {
    const auto it = cells_.find(key(at));
    if (it == cells_.end()) return;
    auto& values = it->second;
    const auto found = std::find(values.begin(), values.end(), value);
    if (found != values.end()) values.erase(found);
    if (values.empty()) cells_.erase(it);
  }
  /// Calls `visit(value)` for every value in the cells overlapping the box [lo, hi] and returns
  /// true; visits nothing and returns false if that is more than `max_cells` cells.
  template <class Visit>
  bool inBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, std::size_t max_cells, Visit visit) const {
    const auto [x0, y0] = cellOf(lo);
    const auto [x1, y1] = cellOf(hi);
    if (x1 < x0 || y1 < y0) return true;
    if (static_cast<double>(x1 - x0 + 1) * static_cast<double>(y1 - y0 + 1) > static_cast<double>(max_cells)) return false;
    for (std::int64_t x = x0; x <= x1; ++x) {
      for (std::int64_t y = y0; y <= y1; ++y) {
        const auto it = cells_.find(pack(x, y));
        if (it == cells_.end()) continue;
        for (const Value& value : it->second) visit(value);
      }
    }
    return true;
  }
  /// Calls `visit(value)` for every value in the 3x3 cells around `at`.
  template <class Visit>
  void around(const Eigen::Vector2d& at, Visit visit) const {
    const auto [cx, cy] = cellOf(at);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find(pack(cx + dx, cy + dy));
        if (it == cells_.end()) continue;
        for (const Value& value : it->second) visit(value);
      }
    }
  }

 private:
  std::pair<std::int64_t, std::int64_t> cellOf(const Eigen::Vector2d& p) const {
    // Clamped so that absurd coordinates (refused later by the mesher) cannot overflow the cast.
    const auto index = [this](double x) {
      return static_cast<std::int64_t>(std::clamp(std::floor(x / cell_), -1e15, 1e15));
    };
    return {index(p.x()), index(p.y())};
  }
  static std::uint64_t pack(std::int64_t x, std::int64_t y) { return geometry::packCell2(x, y); }
  std::uint64_t key(const Eigen::Vector2d& p) const {
    const auto [x, y] = cellOf(p);
    return pack(x, y);
  }

  double cell_;
  std::unordered_map<std::uint64_t, std::vector<Value>> cells_;
};

}  // namespace terramesh::traversability::internal
