#pragma once

// A tiled map as a consumer reads it: the tile index that `tiles merge` writes (tiles.json), and
// the owned maps of a chosen set of tiles joined into one map, so that a planner can cross the
// borders between them (docs/tiles.md, "Planning across tiles").
#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "tiling/tile_plan.h"
#include "traversability/layered_mesh.h"
#include "traversability/map_levels.h"
#include "traversability/robot_profile.h"

namespace terramesh::tiling {

/// One tile of the index.
struct IndexedTile {
  std::size_t index = 0;
  std::string name;
  PlanRect bounds;        ///< plan frame, metres
  std::size_t faces = 0;  ///< faces the tile owns
  /// Its owned map's folder (the folder of the traversability.ply the index lists).
  std::filesystem::path map_dir;
};

struct TileIndex {
  std::filesystem::path path;
  traversability::MapPlane plane;  ///< the plan frame of every tile's map
  double tile_m = 0;
  std::vector<IndexedTile> tiles;  ///< in the index's order

  /// The smallest rectangle holding the bounds of every tile that owns faces (empty if none).
  PlanRect extentOfFaces() const;
};

/// Reads a tile index written by mergeTiles ("terramesh tile index", version 1). Map folders are
/// taken relative to the index's folder.
/// @throw terramesh::InputError naming the file and the field that is missing or malformed (e.g.
///        "tiles[2].files: expected a traversability.ply"), or if no tile is listed.
TileIndex readTileIndex(const std::filesystem::path& path);

/// Tiles owning faces whose bounds meet `region` (closed), in index order.
std::vector<std::size_t> tilesMeeting(const TileIndex& index, const PlanRect& region);

/// The owned maps of some tiles joined into one map.
struct JoinedTiles {
  traversability::LayeredMesh map;
  traversability::RobotProfile profile;  ///< the one every joined tile was computed for
  std::vector<std::size_t> tiles;        ///< the tiles joined, as asked
  /// Vertices that two or more tiles hold at exactly the same position, each counted once: the
  /// same mesh vertex on either side of a border (tiles of one run, or meshed apart from the same
  /// points and rays), now one vertex.
  std::size_t welded_vertices = 0;
  /// Edges whose two faces come from different tiles after the weld: where a path may cross.
  std::size_t border_edges = 0;
};

/// Reads each tile's owned map (readMapDirectory) and joins them (appendMap), then welds vertices
/// at bitwise-equal positions, so that faces of two tiles sharing an edge become neighbours. Only
/// exact positions are welded: a vertex that two tiles meshed apart placed differently stays apart
/// (their faces do not join there). The per-vertex data kept for a welded vertex is its first
/// tile's. O(faces of the tiles).
/// @throw terramesh::InputError naming the file of a tile that cannot be read, or whose robot
///        profile or frame differs from the first tile's; std::invalid_argument for an empty list
///        or an index out of range.
JoinedTiles joinTiles(const TileIndex& index, const std::vector<std::size_t>& tiles);

}  // namespace terramesh::tiling
