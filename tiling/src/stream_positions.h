#pragma once

// The last position a stream sends for each keyframe and point, in plan metres (internal).
#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>

#include "datasets/slam_stream.h"
#include "tiling/tile_plan.h"
#include "traversability/map_levels.h"

namespace terramesh::tiling::internal {

struct StreamPositions {
  /// Keyframe id -> camera centre; point id -> point. Both in plan metres (MapPlane::planM).
  std::unordered_map<std::uint64_t, Eigen::Vector2d> keyframes;
  std::unordered_map<std::uint64_t, Eigen::Vector2d> points;
};

/// One pass over the stream's keyframe events; later estimates replace earlier ones.
StreamPositions lastStreamPositions(const datasets::SlamStream& stream, const traversability::MapPlane& plane);

}  // namespace terramesh::tiling::internal

namespace terramesh::tiling::internal {

/// The keyframes and points of one tile's input (selectTileInput's rule), by id.
struct TileMembers {
  std::unordered_set<std::uint64_t> keyframes;
  std::unordered_set<std::uint64_t> points;
};

/// Whether the observation of `point` by `keyframe` (both in `positions`) makes the point a member
/// of the tile with input bounds `input_bounds`: the point lies in them or the ray from the camera
/// to it crosses them. (The tile then keeps every observation of the point.)
bool keepsObservation(const StreamPositions& positions, const PlanRect& input_bounds, std::uint64_t keyframe,
                      std::uint64_t point);

/// Members of the tile whose input bounds are `input_bounds`. O(points + observations).
TileMembers tileMembers(const datasets::SlamStream& stream, const StreamPositions& positions,
                        const PlanRect& input_bounds);

}  // namespace terramesh::tiling::internal
