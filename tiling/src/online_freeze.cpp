// Which tiles of a long drive freeze and which keyframes retire.
#include "tiling/online_freeze.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace terramesh::tiling {

void FreezeConfig::validate() const {
  std::string problems;
  const auto add = [&problems](const std::string& problem) {
    problems += (problems.empty() ? "" : "; ") + problem;
  };
  if (!(std::isfinite(tile_m) && tile_m > 0))
    add("tile_m: " + std::to_string(tile_m) + " (expected > 0)");
  if (!(std::isfinite(radius_m) && radius_m > 0))
    add("radius_m: " + std::to_string(radius_m) + " (expected > 0)");
  if (recent_keyframes < 1) add("recent_keyframes: 0 (expected >= 1)");
  if (!problems.empty()) throw std::invalid_argument("freeze config: " + problems);
}

OnlineFreeze::OnlineFreeze(const FreezeConfig& config, const traversability::MapPlane& plane,
                           double reach_m)
    : config_(config), plane_(plane), reach_m_(reach_m) {
  config_.validate();
  if (!(std::isfinite(reach_m) && reach_m > 0)) {
    throw std::invalid_argument("OnlineFreeze: reach " + std::to_string(reach_m) +
                                " m (expected > 0)");
  }
}

std::vector<OnlineFreeze::Cell> OnlineFreeze::cellsWithin(const Eigen::Vector2d& xy_m) const {
  const double t = config_.tile_m;
  const auto first = [t](double v) { return static_cast<long>(std::floor(v / t)); };
  std::vector<Cell> cells;
  for (long col = first(xy_m.x() - reach_m_); col <= first(xy_m.x() + reach_m_); ++col) {
    for (long row = first(xy_m.y() - reach_m_); row <= first(xy_m.y() + reach_m_); ++row) {
      const PlanRect rect{static_cast<double>(col) * t, static_cast<double>(row) * t,
                          static_cast<double>(col + 1) * t, static_cast<double>(row + 1) * t};
      if (rect.distanceM(xy_m) <= reach_m_) cells.emplace_back(col, row);
    }
  }
  return cells;
}

void OnlineFreeze::keyframe(std::uint64_t id, const Eigen::Vector3d& centre_W) {
  ++count_;
  const Eigen::Vector2d xy = plane_.planM(centre_W);
  recent_.push_back(xy);
  if (recent_.size() > config_.recent_keyframes) recent_.pop_front();
  std::vector<std::size_t> reach;
  std::vector<std::size_t> thawing;
  for (const Cell& cell : cellsWithin(xy)) {
    auto found = tile_of_.find(cell);
    if (found == tile_of_.end()) {
      const std::size_t index = tiles_.size();
      found = tile_of_.emplace(cell, index).first;
      tiles_.emplace_back();
      TileSpec spec;
      spec.index = index;
      spec.name = tileName(index);
      spec.column = cell.first;
      spec.row = cell.second;
      const double t = config_.tile_m;
      spec.bounds = {static_cast<double>(cell.first) * t, static_cast<double>(cell.second) * t,
                     static_cast<double>(cell.first + 1) * t,
                     static_cast<double>(cell.second + 1) * t};
      specs_.push_back(spec);
    }
    Tile& tile = tiles_[found->second];
    if (tile.frozen) thawing.push_back(found->second);
    tile.frozen = false;
    tile.last_seen = count_;
    ++specs_[found->second].keyframes;
    reach.push_back(found->second);
  }
  live_[id] = Live{centre_W, std::move(reach)};
  if (thawing.empty()) return;
  thawed_.insert(thawed_.end(), thawing.begin(), thawing.end());
  thawed_count_ += thawing.size();
  // The keyframes that saw a thawed tile come back, so that it is whole when it freezes again.
  for (auto it = retired_.begin(); it != retired_.end();) {
    const std::vector<std::size_t>& tiles = it->second.reach;
    const bool back = std::any_of(tiles.begin(), tiles.end(), [&](std::size_t t) {
      return std::find(thawing.begin(), thawing.end(), t) != thawing.end();
    });
    if (!back) {
      ++it;
      continue;
    }
    returned_.push_back(it->first);
    ++returned_count_;
    live_.emplace(it->first, std::move(it->second));
    it = retired_.erase(it);
  }
}

void OnlineFreeze::removed(std::uint64_t id) {
  live_.erase(id);
  retired_.erase(id);
}

std::vector<std::size_t> OnlineFreeze::takeThawed() { return std::exchange(thawed_, {}); }

std::vector<std::uint64_t> OnlineFreeze::takeReturned() {
  std::vector<std::uint64_t> returned = std::exchange(returned_, {});
  std::sort(returned.begin(), returned.end());
  return returned;
}

std::vector<std::size_t> OnlineFreeze::freezeDue() {
  std::vector<std::size_t> due;
  for (std::size_t i = 0; i < tiles_.size(); ++i) {
    Tile& tile = tiles_[i];
    if (tile.frozen || count_ - tile.last_seen < config_.idle_keyframes) continue;
    const PlanRect& bounds = specs_[i].bounds;
    const bool far = std::all_of(recent_.begin(), recent_.end(), [&](const Eigen::Vector2d& xy) {
      return bounds.distanceM(xy) > config_.radius_m;
    });
    if (!far) continue;
    tile.frozen = true;
    due.push_back(i);
  }
  return due;
}

std::vector<std::uint64_t> OnlineFreeze::retireDue() {
  std::vector<std::uint64_t> due;
  for (const auto& [id, live] : live_) {
    const std::vector<std::size_t>& reach = live.reach;
    if (std::all_of(reach.begin(), reach.end(), [this](std::size_t t) { return tiles_[t].frozen; }))
      due.push_back(id);
  }
  for (std::uint64_t id : due) {
    auto it = live_.find(id);
    retired_.emplace(id, std::move(it->second));
    live_.erase(it);
  }
  return due;
}

TilePlan OnlineFreeze::plan(const Eigen::Vector3d& up_W, double metres_per_unit,
                            std::size_t stream_events, std::size_t stream_keyframe_events) const {
  TilePlan plan;
  plan.config.tile_m = config_.tile_m;
  plan.config.overlap_m = 0;
  plan.config.guard_m = 0;
  plan.up_W = up_W;
  plan.metres_per_unit = metres_per_unit;
  plan.stream_events = stream_events;
  plan.stream_keyframe_events = stream_keyframe_events;
  if (specs_.empty()) return plan;
  plan.extent = specs_.front().bounds;
  for (const TileSpec& spec : specs_) {
    plan.extent.min_x_m = std::min(plan.extent.min_x_m, spec.bounds.min_x_m);
    plan.extent.min_y_m = std::min(plan.extent.min_y_m, spec.bounds.min_y_m);
    plan.extent.max_x_m = std::max(plan.extent.max_x_m, spec.bounds.max_x_m);
    plan.extent.max_y_m = std::max(plan.extent.max_y_m, spec.bounds.max_y_m);
  }
  // The plan's grid starts at the extent's corner, which lies on the grid: columns and rows from
  // it.
  const long column0 = static_cast<long>(std::lround(plan.extent.min_x_m / config_.tile_m));
  const long row0 = static_cast<long>(std::lround(plan.extent.min_y_m / config_.tile_m));
  plan.tiles = specs_;
  for (TileSpec& spec : plan.tiles) {
    spec.column -= column0;
    spec.row -= row0;
  }
  std::sort(plan.tiles.begin(), plan.tiles.end(), [](const TileSpec& a, const TileSpec& b) {
    return std::make_pair(a.row, a.column) < std::make_pair(b.row, b.column);
  });
  for (std::size_t i = 0; i < plan.tiles.size(); ++i) plan.tiles[i].index = i;
  return plan;
}

std::vector<Eigen::Vector3d> OnlineFreeze::liveCentres() const {
  std::vector<Eigen::Vector3d> centres;
  centres.reserve(live_.size());
  for (const auto& [id, live] : live_) centres.push_back(live.centre_W);
  return centres;
}

FreezeStats OnlineFreeze::stats() const {
  FreezeStats stats;
  stats.tiles = tiles_.size();
  stats.frozen_tiles = static_cast<std::size_t>(
      std::count_if(tiles_.begin(), tiles_.end(), [](const Tile& tile) { return tile.frozen; }));
  stats.retired_keyframes = retired_.size();
  stats.thawed_tiles = thawed_count_;
  stats.returned_keyframes = returned_count_;
  return stats;
}

}  // namespace terramesh::tiling
