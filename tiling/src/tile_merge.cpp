// The tile index and the overview of a tiled map.
#include "tiling/tile_merge.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "common/json_fields.h"
#include "tiling/tile_files.h"
#include "tile_reading.h"
#include "traversability/map_directory.h"

namespace terramesh::tiling {
namespace {

constexpr const char* kIndexName = "tiles.json";
constexpr const char* kOverviewName = "overview";

nlohmann::json vectorJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

/// Per level: its Nav2 maps and GeoTIFF among `files` (relative to `folder`).
nlohmann::json levelsJson(const std::vector<double>& heights_m, const std::vector<std::string>& files,
                          const std::string& folder) {
  nlohmann::json levels = nlohmann::json::array();
  const auto listed = [&files](const std::string& name) { return std::find(files.begin(), files.end(), name) != files.end(); };
  for (std::size_t l = 0; l < heights_m.size(); ++l) {
    const std::string base = "level_" + std::to_string(l);
    nlohmann::json level = {{"level", l}, {"mean_height_m", heights_m[l]}, {"nav2_map", folder + base + ".yaml"}};
    if (listed(base + "_cost.yaml")) level["nav2_cost_map"] = folder + base + "_cost.yaml";
    if (listed("layers_" + base + ".tif")) level["geotiff"] = folder + "layers_" + base + ".tif";
    levels.push_back(level);
  }
  return levels;
}

/// The relative names of `files` in `folder`, sorted.
std::vector<std::string> prefixed(std::vector<std::string> files, const std::string& folder) {
  std::sort(files.begin(), files.end());
  for (std::string& file : files) file = folder + file;
  return files;
}

/// Reads every owned part, checks the robot, writes the overview; fills the tiles' index entries.
traversability::ExportReport writeOverview(const std::filesystem::path& plan_path, const TilePlan& plan,
                                           const MergeConfig& config, nlohmann::json& tiles, MergeReport& report) {
  traversability::LayeredMesh joined;
  std::optional<traversability::RobotProfile> profile;
  internal::OwnedMapReader reader;
  for (const TileSpec& tile : plan.tiles) {
    const TileRecord record = readTileRecord(plan_path, tile);
    traversability::MapDirectory owned = reader.read(tileMapDirectory(plan_path, tile), tile.name);
    if (!profile) profile = owned.profile;
    report.faces += owned.map.mesh.faces.size();
    appendMap(joined, owned.map);
    const std::string folder = tile.name + "/map/";
    tiles.push_back({{"index", tile.index},
                     {"name", tile.name},
                     {"column", tile.column},
                     {"row", tile.row},
                     {"bounds_m", {{"min_x", tile.bounds.min_x_m}, {"min_y", tile.bounds.min_y_m},
                                   {"max_x", tile.bounds.max_x_m}, {"max_y", tile.bounds.max_y_m}}},
                     {"revision", record.revision},
                     {"faces", record.faces},
                     {"levels", levelsJson(record.level_heights_m, record.files, folder)},
                     {"files", prefixed(record.files, folder)}});
  }
  traversability::ExportConfig overview;
  overview.grid_resolution_m = config.overview_resolution_m;
  overview.write_geotiff = false;
  overview.write_mesh_map_h5 = false;
  overview.write_layered_ply = false;
  overview.levels = config.levels;
  if (config.compare_with) {
    const traversability::LayeredMesh other = traversability::readMapDirectory(*config.compare_with).map;
    report.compared = classAgreement(joined, other, plan.extent, config.levels, config.border_cell_m);
    report.compared_only_other_m2 =
        classAgreement(other, joined, plan.extent, config.levels, config.border_cell_m).only_a_m2;
  }
  return traversability::writeMapDirectory(plan_path.parent_path() / kOverviewName, joined, *profile, overview);
}

std::vector<BorderAgreement> compareBorders(const std::filesystem::path& plan_path, const TilePlan& plan,
                                            const MergeConfig& config) {
  std::map<std::size_t, traversability::LayeredMesh> whole;  // each tile's map with its overlap, read once
  const auto map = [&](std::size_t i) -> const traversability::LayeredMesh& {
    auto found = whole.find(i);
    if (found == whole.end()) {
      found = whole.emplace(i, traversability::readMapDirectory(tileDirectory(plan_path, plan.tiles[i])).map).first;
    }
    return found->second;
  };
  std::vector<BorderAgreement> borders;
  for (std::size_t a = 0; a < plan.tiles.size(); ++a) {
    for (std::size_t b = a + 1; b < plan.tiles.size(); ++b) {
      const long gap = std::abs(plan.tiles[a].column - plan.tiles[b].column) + std::abs(plan.tiles[a].row - plan.tiles[b].row);
      if (gap != 1) continue;
      BorderAgreement border;
      border.tile_a = a;
      border.tile_b = b;
      border.region = plan.overlapBounds(a).intersection(plan.overlapBounds(b));
      border.agreement = classAgreement(map(a), map(b), border.region, config.levels, config.border_cell_m);
      border.seam = plan.seamBounds(a, b);
      border.at_seam = classAgreement(map(a), map(b), border.seam, config.levels, config.border_cell_m);
      borders.push_back(border);
    }
  }
  return borders;
}

}  // namespace

void MergeConfig::validate() const {
  std::string problems;
  const auto positive = [&problems](double value, const char* name) {
    if (!(value > 0) || !std::isfinite(value)) {
      problems += (problems.empty() ? "" : "; ") + std::string(name) + ": " + std::to_string(value) + " (expected > 0)";
    }
  };
  positive(overview_resolution_m, "overview_resolution_m");
  positive(border_cell_m, "border_cell_m");
  try {
    levels.validate();
  } catch (const std::invalid_argument& error) {
    problems += (problems.empty() ? "" : "; ") + std::string(error.what());
  }
  if (!problems.empty()) throw std::invalid_argument("MergeConfig: " + problems);
}

MergeReport mergeTiles(const std::filesystem::path& plan_path, const MergeConfig& config) {
  config.validate();
  const TilePlan plan = readTilePlan(plan_path);
  MergeReport report;
  report.tiles = plan.tiles.size();
  report.overlap_m = plan.config.overlap_m;
  nlohmann::json tiles = nlohmann::json::array();
  const traversability::ExportReport overview = writeOverview(plan_path, plan, config, tiles, report);
  report.overview_levels = overview.levels;
  const std::string overview_folder = std::string(kOverviewName) + "/";
  const traversability::MapPlane plane = plan.plane();
  const nlohmann::json index = {
      {"format", "terramesh tile index"},
      {"version", 1},
      {"plan", plan_path.filename().string()},
      {"frame", {{"up", vectorJson(plane.z_W)}, {"metres_per_unit", plane.metres_per_unit},
                 {"plan_x", vectorJson(plane.x_W)}, {"plan_y", vectorJson(plane.y_W)}}},
      {"tile_m", plan.config.tile_m},
      {"overlap_m", plan.config.overlap_m},
      {"overview", {{"resolution_m", config.overview_resolution_m},
                    {"levels", levelsJson(overview.level_heights_m, overview.files, overview_folder)},
                    {"files", prefixed(overview.files, overview_folder)}}},
      {"tiles", tiles}};
  json::writeJsonFile(plan_path.parent_path() / kIndexName, index);
  report.files = prefixed(overview.files, overview_folder);
  report.files.push_back(kIndexName);
  std::sort(report.files.begin(), report.files.end());
  if (config.check_borders) report.borders = compareBorders(plan_path, plan, config);
  return report;
}

}  // namespace terramesh::tiling
