#pragma once

// What one tile meshes: the part of a stream that its bounds grown by the overlap need.
#include <cstddef>

#include "datasets/slam_stream.h"
#include "tiling/tile_plan.h"

namespace terramesh::tiling {

/// The events of one tile and what they hold.
struct TileInput {
  /// The stream's events restricted to the tile, in stream order; every other field of the
  /// stream is copied.
  datasets::SlamStream stream;
  std::size_t keyframes = 0;  ///< distinct keyframes
  std::size_t points = 0;     ///< distinct points
};

/// The input of tile `tile`. With G its input bounds (TilePlan::inputBounds) and positions taken
/// from the last estimate the stream sends (so that every event of a keyframe or point is judged
/// alike), in the plan:
/// - an observation belongs to the tile if its point lies in G or its ray (camera centre to point)
///   crosses G: every ray that carves free space over G;
/// - a point belongs if one of its observations does, and then every observation of it belongs
///   too (so the tile's mesher counts its views, min_views, and follows its moves as the whole
///   stream's does); a keyframe belongs if its camera centre lies in G (its driven ground) or one
///   of its observations belongs;
/// - a keyframe event keeps only the tile's observations (possibly none); a point removal keeps
///   the tile's points (dropped when none is left); a keyframe removal is kept for the tile's
///   keyframes.
/// So two tiles receive the same points, views and rays over the overlap of their input bounds,
/// which holds the overlap of their maps (TilePlan::overlapBounds) with a guard band around it.
/// O(events + observations).
TileInput selectTileInput(const datasets::SlamStream& stream, const TilePlan& plan, std::size_t tile);

}  // namespace terramesh::tiling
