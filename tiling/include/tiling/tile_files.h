#pragma once

// The files of a tiled map (docs/tiles.md): the plan, each tile's result record, where a tile's
// outputs go beside the plan.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tiling/tile_plan.h"

namespace terramesh::tiling {

/// Writes the plan as JSON (format "terramesh tile plan", version 1), atomically, mode 0644.
/// @throw std::runtime_error naming the file if it cannot be written.
void writeTilePlan(const std::filesystem::path& path, const TilePlan& plan);

/// Reads a plan written by writeTilePlan.
/// @throw terramesh::InputError naming the file and the field (e.g. "tiles[2].bounds_m.min_x")
///        that is missing, of the wrong type or inconsistent (index, name, order, bounds).
TilePlan readTilePlan(const std::filesystem::path& path);

/// Where tile `tile`'s outputs go: the folder named after it beside the plan file.
std::filesystem::path tileDirectory(const std::filesystem::path& plan_path, const TileSpec& tile);
/// The folder of the part of its map a tile owns (the files the tile index lists): "map" in the
/// tile's folder.
std::filesystem::path tileMapDirectory(const std::filesystem::path& plan_path, const TileSpec& tile);

/// What meshing one tile produced: written by `terramesh mesh --tile` into the tile's folder
/// ("tile.json") once its owned map is complete, read by the merge.
struct TileRecord {
  std::size_t index = 0;
  /// The mesher's revision at the end of the tile's run (mesher::Mesher::revision): a loader
  /// reloads a tile whose revision changed.
  std::uint64_t revision = 0;
  std::size_t faces = 0;  ///< faces the tile owns
  /// Per level of the owned map: mean height, metres (level_N files).
  std::vector<double> level_heights_m;
  /// The owned map's files, relative to tileMapDirectory, sorted.
  std::vector<std::string> files;
};

/// "tile.json" in the tile's folder, atomically.
void writeTileRecord(const std::filesystem::path& plan_path, const TileSpec& tile, const TileRecord& record);
/// @throw terramesh::InputError naming the file: missing (the tile was not meshed), malformed,
///        or for another tile.
TileRecord readTileRecord(const std::filesystem::path& plan_path, const TileSpec& tile);

}  // namespace terramesh::tiling
