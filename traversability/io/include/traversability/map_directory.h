#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "traversability/layered_mesh.h"
#include "traversability/map_levels.h"
#include "traversability/robot_profile.h"

namespace terramesh::traversability {

/// Options of the exports written into a map directory.
struct ExportConfig {
  /// Cell size of the Nav2 maps and the GeoTIFF grid, in metres.
  double grid_resolution_m = 0.1;
  /// Also write the GeoTIFF multi-layer grid(s) (GDAL).
  bool write_geotiff = true;
  /// Also write `traversability.h5`, the HDF5 mesh map that mesh_navigation's mesh_map reads.
  bool write_mesh_map_h5 = true;
  /// Also write `traversability.ply` (off for a map directory of 2D maps only, such as a tiled
  /// map's overview; readMapDirectory needs it).
  bool write_layered_ply = true;
  /// How faces are split into walkable levels (one 2D map per level).
  LevelConfig levels;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// What writeMapDirectory wrote (file names relative to the directory) and per-level areas.
struct ExportReport {
  std::vector<std::string> files;
  std::size_t levels = 0;
  /// Per level: mean height of its walkable surface along up, metres.
  std::vector<double> level_heights_m;
  /// The text written to traversability_summary.txt.
  std::string summary;
};

/// Writes every export of a traversability map into `dir` (created if missing), each file
/// atomically (temp file + rename), so a map server may reload any of them at any time:
/// - `traversability.ply`: the mesh with per-face layers and per-vertex cost (if write_layered_ply);
/// - `level_N.pgm` + `level_N.yaml`: Nav2 map_server trinary maps, one per walkable level
///   (levels numbered by increasing height, see segmentLevels);
///   `level_N_cost.png` + `level_N_cost.yaml`: the same in `scale` mode, grey levels = cost,
///   alpha 0 = unknown (a PGM has no alpha, and scale mode marks unknown only by alpha);
/// - `layers_level_N.tif`: GeoTIFF, one float band per layer, NaN for no data (if write_geotiff);
/// - `traversability.h5`: lvr2's HDF5 MeshIO layout with per-vertex layers under mesh_map's
///   layer names, for mesh_navigation (if write_mesh_map_h5; docs/mesh_navigation.md);
/// - `robot.yaml`: the profile the layers were computed for; `map_frame.yaml`: up vector, scale,
///   the plan axes (see MapPlane);
/// - `traversability_summary.txt`: area free / lethal / unknown per level, layer statistics
///   (not `summary.txt`: `terramesh mesh` writes its own summary.txt into the same directory).
/// Level files of an earlier export with more levels are removed.
/// See docs/traversability.md for every format.
/// @throw std::invalid_argument if the config does not validate or layers and faces differ in
///        number; std::runtime_error if a file cannot be written.
ExportReport writeMapDirectory(const std::filesystem::path& dir, const LayeredMesh& map,
                               const RobotProfile& profile, const ExportConfig& config);

/// What readMapDirectory loads: the layered mesh and the profile it was computed for.
struct MapDirectory {
  LayeredMesh map;
  RobotProfile profile;
};

/// Reads `traversability.ply`, `robot.yaml` and `map_frame.yaml` of a directory written by
/// writeMapDirectory.
/// @throw terramesh::InputError naming the file and what is wrong or missing.
MapDirectory readMapDirectory(const std::filesystem::path& dir);

}  // namespace terramesh::traversability
