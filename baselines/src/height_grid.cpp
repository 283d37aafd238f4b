#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "baselines/height_grid.h"

namespace terramesh::baselines {

void GridRobotConfig::validate() const {
  std::ostringstream problems;
  if (!(max_step_m >= 0)) problems << " max_step_m: " << max_step_m << " (expected >= 0);";
  if (!(max_slope_deg > 0 && max_slope_deg < 90)) problems << " max_slope_deg: " << max_slope_deg << " (expected in (0, 90));";
  if (!(min_clearance_m >= 0)) problems << " min_clearance_m: " << min_clearance_m << " (expected >= 0);";
  if (!(footprint_radius_m >= 0) || !std::isfinite(footprint_radius_m)) {
    problems << " footprint_radius_m: " << footprint_radius_m << " (expected >= 0);";
  }
  if (!(cost_weight >= 0) || !std::isfinite(cost_weight)) problems << " cost_weight: " << cost_weight << " (expected >= 0);";
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("GridRobotConfig:" + text);
}

Eigen::Vector2i HeightGrid::cellOf(double x_m, double y_m) const {
  return {static_cast<int>(std::floor((x_m - origin_x_m) / resolution_m)),
          static_cast<int>(std::floor((y_m - origin_y_m) / resolution_m))};
}

void HeightGrid::classify(const GridRobotConfig& robot) {
  robot.validate();
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  step_m.assign(n, nan);
  slope_deg.assign(n, nan);
  cost.assign(n, nan);
  traversable.assign(n, 0);
  valid_pose.assign(n, 0);
  auto known = [&](int i, int j) { return inside(i, j) && !std::isnan(ground_z_m[index(i, j)]); };
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const std::size_t c = index(i, j);
      if (!known(i, j)) continue;
      const float h = ground_z_m[c];
      float step = 0;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          if ((di || dj) && known(i + di, j + dj)) step = std::max(step, std::abs(ground_z_m[index(i + di, j + dj)] - h));
        }
      }
      auto gradient = [&](int di, int dj) -> double {
        const bool forward = known(i + di, j + dj), backward = known(i - di, j - dj);
        if (forward && backward) return (ground_z_m[index(i + di, j + dj)] - ground_z_m[index(i - di, j - dj)]) / (2 * resolution_m);
        if (forward) return (ground_z_m[index(i + di, j + dj)] - h) / resolution_m;
        if (backward) return (h - ground_z_m[index(i - di, j - dj)]) / resolution_m;
        return 0.0;
      };
      const double gx = gradient(1, 0), gy = gradient(0, 1);
      const double slope = std::atan(std::sqrt(gx * gx + gy * gy)) * 180.0 / M_PI;
      step_m[c] = step;
      slope_deg[c] = static_cast<float>(slope);
      if (step <= robot.max_step_m && slope <= robot.max_slope_deg && clearance_m[c] >= robot.min_clearance_m) {
        traversable[c] = 1;
        cost[c] = static_cast<float>(std::clamp(0.5 * slope / robot.max_slope_deg +
                                                    0.5 * (robot.max_step_m > 0 ? step / robot.max_step_m : 0.0),
                                                0.0, 1.0));
      }
    }
  }
  const int r = static_cast<int>(std::ceil(robot.footprint_radius_m / resolution_m));
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      if (!traversable[index(i, j)]) continue;
      bool ok = true;
      for (int dj = -r; dj <= r && ok; ++dj) {
        for (int di = -r; di <= r && ok; ++di) {
          if (std::hypot(di, dj) * resolution_m > robot.footprint_radius_m) continue;
          if (known(i + di, j + dj) && !traversable[index(i + di, j + dj)]) ok = false;
        }
      }
      valid_pose[index(i, j)] = ok ? 1 : 0;
    }
  }
}

std::size_t HeightGrid::knownCells() const {
  return static_cast<std::size_t>(std::count_if(ground_z_m.begin(), ground_z_m.end(), [](float h) { return !std::isnan(h); }));
}

std::size_t HeightGrid::traversableCells() const {
  return static_cast<std::size_t>(std::count(traversable.begin(), traversable.end(), 1));
}

std::size_t HeightGrid::memoryBytes() const {
  return sizeof(float) * (ground_z_m.size() + clearance_m.size() + step_m.size() + slope_deg.size() + cost.size()) +
         traversable.size() + valid_pose.size();
}

}  // namespace terramesh::baselines
