#pragma once

// Joins the meshed tiles of a plan into one tiled map: the tile index and the overview Nav2 maps
// (docs/tiles.md, "The tiled map").
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tiling/tile_map.h"
#include "tiling/tile_plan.h"
#include "traversability/map_levels.h"

namespace terramesh::tiling {

struct MergeConfig {
  /// Cell size of the overview Nav2 maps over the whole area, metres.
  double overview_resolution_m = 1.0;
  /// Also compare the classes of every two neighbouring tiles (sharing an edge) over the overlap
  /// of their input bounds, on their maps meshed with the overlap (classAgreement), and over its
  /// half nearest the border (TilePlan::seamBounds).
  bool check_borders = false;
  /// Cell size of that comparison, metres.
  double border_cell_m = 0.1;
  /// Also compare the joined tiles' classes with the map in this folder (a map of the same frame,
  /// e.g. one meshed without the freeze) over the plan's extent, at border_cell_m (classAgreement).
  std::optional<std::filesystem::path> compare_with;
  /// The level split of the overview and of the border comparison (the tiles' default).
  traversability::LevelConfig levels;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Class agreement across one border.
struct BorderAgreement {
  std::size_t tile_a = 0, tile_b = 0;
  PlanRect region;  ///< where both tiles have input
  ClassAgreement agreement;
  PlanRect seam;  ///< TilePlan::seamBounds: the half of that overlap nearest the border
  ClassAgreement at_seam;
};

struct MergeReport {
  /// Files written, relative to the plan's folder, sorted.
  std::vector<std::string> files;
  std::size_t tiles = 0;
  std::size_t faces = 0;  ///< faces owned by all tiles together
  std::size_t overview_levels = 0;
  std::vector<BorderAgreement> borders;  ///< with check_borders, by tile pair
  double overlap_m = 0;                  ///< the plan's overlap (the seams are half as wide each side)
  /// With compare_with: the joined tiles (a) against that map (b) ...
  std::optional<ClassAgreement> compared;
  /// ... and the area that map covers where the tiles have no face (on its levels).
  double compared_only_other_m2 = 0;
};

/// Reads every tile's record and owned map (all tiles must have been meshed with the same robot
/// profile), writes the overview (folder "overview" beside the plan: Nav2 maps per level of all
/// owned parts joined, at overview_resolution_m, with robot.yaml, map_frame.yaml and the summary)
/// and then the tile index "tiles.json" (format "terramesh tile index": frame, each tile's bounds,
/// revision, levels and files, the overview's files), each atomically. Byte for byte the same for
/// the same tile outputs: no time stamps, tiles in plan order, files sorted.
/// Holds every owned part in memory at once (and, with check_borders, every tile's whole map).
/// @throw terramesh::InputError naming the file for a bad plan, a tile not meshed yet or meshed
///        for another robot; std::invalid_argument for a bad config; std::runtime_error if a file
///        cannot be written.
MergeReport mergeTiles(const std::filesystem::path& plan_path, const MergeConfig& config);

}  // namespace terramesh::tiling
