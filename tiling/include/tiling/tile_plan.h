#pragma once

// A city-scale map cut into square tiles of the plan (docs/tiles.md): the tiles, their bounds in
// the metric map plane, and which tile owns a point of the plan.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "datasets/slam_stream.h"
#include "traversability/map_levels.h"

namespace terramesh::tiling {

/// How a stream is cut into tiles.
struct TilingConfig {
  /// Side of a tile in the map plane, metres.
  double tile_m = 200.0;
  /// How far beyond its own bounds a tile's map reaches, metres: the surface and layers near a
  /// border see what lies across it, and two neighbours' maps meet over this band.
  double overlap_m = 20.0;
  /// How much farther than the overlap a tile also reads points and keyframes, metres. The
  /// incremental mesher carves the free space near the edge of its input otherwise than a run
  /// that sees beyond it, so the guard keeps that edge away from the overlap.
  double guard_m = 40.0;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// An axis-aligned rectangle of the map plane, metres (MapPlane coordinates). Holds x in
/// [min_x_m, max_x_m) and y in [min_y_m, max_y_m).
struct PlanRect {
  double min_x_m = 0, min_y_m = 0, max_x_m = 0, max_y_m = 0;

  bool contains(const Eigen::Vector2d& xy_m) const {
    return xy_m.x() >= min_x_m && xy_m.x() < max_x_m && xy_m.y() >= min_y_m && xy_m.y() < max_y_m;
  }
  /// The rectangle grown by `margin_m` on every side.
  PlanRect grown(double margin_m) const {
    return {min_x_m - margin_m, min_y_m - margin_m, max_x_m + margin_m, max_y_m + margin_m};
  }
  /// The overlap of two rectangles (empty: max <= min on an axis).
  PlanRect intersection(const PlanRect& other) const;
  bool empty() const { return !(max_x_m > min_x_m && max_y_m > min_y_m); }
  /// Whether the segment from `a_m` to `b_m` meets the rectangle (closed; Liang-Barsky).
  bool meetsSegment(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) const;
  /// Distance from a point to the rectangle, metres (0 inside).
  double distanceM(const Eigen::Vector2d& xy_m) const;
};

/// One tile of a plan.
struct TileSpec {
  std::size_t index = 0;  ///< position in TilePlan::tiles
  std::string name;       ///< folder of its outputs beside the plan, "tile_NNN"
  long column = 0;        ///< grid column (x) and row (y), from the plan's extent corner
  long row = 0;
  PlanRect bounds;        ///< the faces it owns have their centroid here (see TilePlan::ownerOf)
  std::size_t keyframes = 0;  ///< keyframes of its input (see selectTileInput)
  std::size_t points = 0;     ///< points of its input
};

/// Tiles of one stream.
struct TilePlan {
  TilingConfig config;
  /// The map frame every tile is meshed and exported in: up and scale (MapPlane::fromUp).
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  double metres_per_unit = 1.0;
  /// What the plan was made from, checked before a tile is meshed: the stream's event and
  /// keyframe-event counts.
  std::size_t stream_events = 0;
  std::size_t stream_keyframe_events = 0;
  /// Plan bounds of every camera centre and point of the stream; the tile grid starts at its
  /// lower corner.
  PlanRect extent;
  /// The non-empty cells of the grid (some camera centre or point in their bounds), by row then
  /// column.
  std::vector<TileSpec> tiles;

  traversability::MapPlane plane() const { return traversability::MapPlane::fromUp(up_W, metres_per_unit); }
  /// The overlap bounds of tile `i`: its bounds grown by the overlap (where its map meets its
  /// neighbours').
  PlanRect overlapBounds(std::size_t i) const { return tiles.at(i).bounds.grown(config.overlap_m); }
  /// The input bounds of tile `i`: its bounds grown by the overlap and the guard.
  PlanRect inputBounds(std::size_t i) const { return tiles.at(i).bounds.grown(config.overlap_m + config.guard_m); }
  /// The seam between tiles `a` and `b`: their bounds each grown by half the overlap, intersected.
  /// For two tiles sharing an edge, the band within overlap_m / 2 of that edge (as long as it,
  /// plus overlap_m / 2 at either end): where the faces each owns meet the other's, and each
  /// tile's layers still see overlap_m / 2 of surface beyond its border. Empty for tiles farther
  /// apart than the overlap.
  PlanRect seamBounds(std::size_t a, std::size_t b) const {
    const double half_m = 0.5 * config.overlap_m;
    return tiles.at(a).bounds.grown(half_m).intersection(tiles.at(b).bounds.grown(half_m));
  }
  /// The tile that owns a plan position: the one whose bounds hold it; a position in no tile's
  /// bounds (closing geometry beyond the extent, an empty cell) goes to the nearest tile, the
  /// lowest index on ties. Every position has exactly one owner. O(1), O(tiles) outside.
  /// @throw std::logic_error if the plan has no tile.
  std::size_t ownerOf(const Eigen::Vector2d& xy_m) const;
};

/// Cuts a stream into tiles: the grid of `config.tile_m` squares from the lower corner of the
/// extent of every keyframe pose and point estimate the stream sends, keeping the cells that hold
/// any; counts each tile's input (selectTileInput's rule). O(tiles x observations).
/// @throw std::invalid_argument if the config or frame is invalid, or the stream has no keyframe.
TilePlan planTiles(const datasets::SlamStream& stream, const Eigen::Vector3d& up_W, double metres_per_unit,
                   const TilingConfig& config);

/// The folder name of tile `index`: "tile_" and three or more digits.
std::string tileName(std::size_t index);

}  // namespace terramesh::tiling
