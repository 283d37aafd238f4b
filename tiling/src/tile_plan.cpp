// The tile grid of a stream and which tile owns a plan position.
#include "tiling/tile_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>
#include <variant>

#include "stream_positions.h"

namespace terramesh::tiling {
namespace {

bool finitePositive(double value) { return std::isfinite(value) && value > 0; }

/// Plan bounds of every keyframe and point position (the largest ones on max_x_m, max_y_m).
PlanRect extentOf(const internal::StreamPositions& positions) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  PlanRect extent{kInf, kInf, -kInf, -kInf};
  const auto add = [&extent](const Eigen::Vector2d& xy) {
    extent.min_x_m = std::min(extent.min_x_m, xy.x());
    extent.min_y_m = std::min(extent.min_y_m, xy.y());
    extent.max_x_m = std::max(extent.max_x_m, xy.x());
    extent.max_y_m = std::max(extent.max_y_m, xy.y());
  };
  for (const auto& [id, xy] : positions.keyframes) add(xy);
  for (const auto& [id, xy] : positions.points) add(xy);
  return extent;
}

bool holdsAny(const internal::StreamPositions& positions, const PlanRect& rect) {
  const auto inside = [&rect](const auto& entry) { return rect.contains(entry.second); };
  return std::any_of(positions.keyframes.begin(), positions.keyframes.end(), inside) ||
         std::any_of(positions.points.begin(), positions.points.end(), inside);
}

}  // namespace

void TilingConfig::validate() const {
  std::string problems;
  const auto add = [&problems](const std::string& problem) { problems += (problems.empty() ? "" : "; ") + problem; };
  if (!finitePositive(tile_m)) add("tile_m: " + std::to_string(tile_m) + " (expected > 0)");
  if (!std::isfinite(overlap_m) || overlap_m < 0) add("overlap_m: " + std::to_string(overlap_m) + " (expected >= 0)");
  if (!std::isfinite(guard_m) || guard_m < 0) add("guard_m: " + std::to_string(guard_m) + " (expected >= 0)");
  if (!problems.empty()) throw std::invalid_argument("TilingConfig: " + problems);
}

PlanRect PlanRect::intersection(const PlanRect& other) const {
  return {std::max(min_x_m, other.min_x_m), std::max(min_y_m, other.min_y_m), std::min(max_x_m, other.max_x_m),
          std::min(max_y_m, other.max_y_m)};
}

bool PlanRect::meetsSegment(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) const {
  double t0 = 0, t1 = 1;
  const Eigen::Vector2d d = b_m - a_m;
  const double lower[2] = {min_x_m, min_y_m}, upper[2] = {max_x_m, max_y_m};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0) {
      if (a_m[k] < lower[k] || a_m[k] > upper[k]) return false;
      continue;
    }
    double enter = (lower[k] - a_m[k]) / d[k], leave = (upper[k] - a_m[k]) / d[k];
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
    if (t0 > t1) return false;
  }
  return true;
}

double PlanRect::distanceM(const Eigen::Vector2d& xy_m) const {
  const double dx = std::max({min_x_m - xy_m.x(), 0.0, xy_m.x() - max_x_m});
  const double dy = std::max({min_y_m - xy_m.y(), 0.0, xy_m.y() - max_y_m});
  return std::hypot(dx, dy);
}

std::size_t TilePlan::ownerOf(const Eigen::Vector2d& xy_m) const {
  if (tiles.empty()) throw std::logic_error("TilePlan::ownerOf: the plan has no tile");
  const double column = std::floor((xy_m.x() - extent.min_x_m) / config.tile_m);
  const double row = std::floor((xy_m.y() - extent.min_y_m) / config.tile_m);
  const auto before = [](const TileSpec& tile, const std::pair<double, double>& cell) {
    return std::make_pair(static_cast<double>(tile.row), static_cast<double>(tile.column)) < cell;
  };
  const auto found = std::lower_bound(tiles.begin(), tiles.end(), std::make_pair(row, column), before);
  if (found != tiles.end() && found->row == row && found->column == column && found->bounds.contains(xy_m)) {
    return found->index;
  }
  std::size_t best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const TileSpec& tile : tiles) {
    const double distance = tile.bounds.distanceM(xy_m);
    if (distance < best_distance) {
      best_distance = distance;
      best = tile.index;
    }
  }
  return best;
}

std::string tileName(std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "tile_%03zu", index);
  return name;
}

TilePlan planTiles(const datasets::SlamStream& stream, const Eigen::Vector3d& up_W, double metres_per_unit,
                   const TilingConfig& config) {
  config.validate();
  TilePlan plan;
  plan.config = config;
  plan.up_W = up_W.normalized();
  plan.metres_per_unit = metres_per_unit;
  const traversability::MapPlane plane = plan.plane();  // validates up and scale
  plan.stream_events = stream.events.size();
  plan.stream_keyframe_events = stream.keyframeEventCount();
  if (plan.stream_keyframe_events == 0) throw std::invalid_argument("planTiles: the stream has no keyframe");
  const internal::StreamPositions positions = internal::lastStreamPositions(stream, plane);
  plan.extent = extentOf(positions);
  const auto cells = [&config](double span) { return static_cast<long>(std::floor(span / config.tile_m)) + 1; };
  const long columns = cells(plan.extent.max_x_m - plan.extent.min_x_m);
  const long rows = cells(plan.extent.max_y_m - plan.extent.min_y_m);
  for (long row = 0; row < rows; ++row) {
    for (long column = 0; column < columns; ++column) {
      TileSpec tile;
      tile.column = column;
      tile.row = row;
      tile.bounds.min_x_m = plan.extent.min_x_m + static_cast<double>(column) * config.tile_m;
      tile.bounds.min_y_m = plan.extent.min_y_m + static_cast<double>(row) * config.tile_m;
      tile.bounds.max_x_m = tile.bounds.min_x_m + config.tile_m;
      tile.bounds.max_y_m = tile.bounds.min_y_m + config.tile_m;
      if (!holdsAny(positions, tile.bounds)) continue;
      tile.index = plan.tiles.size();
      tile.name = tileName(tile.index);
      plan.tiles.push_back(tile);
      const internal::TileMembers members = internal::tileMembers(stream, positions, plan.inputBounds(tile.index));
      plan.tiles.back().keyframes = members.keyframes.size();
      plan.tiles.back().points = members.points.size();
    }
  }
  return plan;
}

}  // namespace terramesh::tiling
