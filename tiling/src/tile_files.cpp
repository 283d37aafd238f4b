// The plan and tile records as JSON (docs/tiles.md, "Files").
#include "tiling/tile_files.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "common/input_error.h"
#include "common/json_fields.h"
#include "tile_reading.h"

namespace terramesh::tiling {
namespace {

constexpr const char* kPlanFormat = "terramesh tile plan";
constexpr const char* kRecordFormat = "terramesh tile result";
constexpr const char* kRecordName = "tile.json";

nlohmann::json rectJson(const PlanRect& rect) {
  return {{"min_x", rect.min_x_m}, {"min_y", rect.min_y_m}, {"max_x", rect.max_x_m}, {"max_y", rect.max_y_m}};
}

TileSpec readTile(const json::FieldReader& json, const nlohmann::json& item, std::size_t i) {
  const std::string path = "tiles[" + std::to_string(i) + "]";
  TileSpec tile;
  tile.index = json.count(item, "index", path);
  if (tile.index != i) json.fail(json::FieldReader::join(path, "index"), "expected " + std::to_string(i) + " (tiles in order)");
  tile.name = json.string(item, "name", path);
  // "tile_" and three or more digits: a folder beside the plan (a frozen drive numbers its tiles in
  // the order the drive reached them, so a name need not be its position's).
  const bool digits = tile.name.size() >= 8 && tile.name.compare(0, 5, "tile_") == 0 &&
                      std::all_of(tile.name.begin() + 5, tile.name.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!digits) json.fail(json::FieldReader::join(path, "name"), "expected \"tile_\" and three or more digits");
  tile.column = json.integer(item, "column", path);
  tile.row = json.integer(item, "row", path);
  tile.bounds = internal::readBounds(json, item, path);
  tile.keyframes = json.count(item, "keyframes", path);
  tile.points = json.count(item, "points", path);
  return tile;
}

}  // namespace

void writeTilePlan(const std::filesystem::path& path, const TilePlan& plan) {
  nlohmann::json tiles = nlohmann::json::array();
  for (const TileSpec& tile : plan.tiles) {
    tiles.push_back({{"index", tile.index}, {"name", tile.name}, {"column", tile.column}, {"row", tile.row},
                     {"bounds_m", rectJson(tile.bounds)}, {"keyframes", tile.keyframes}, {"points", tile.points}});
  }
  nlohmann::json extent = rectJson(plan.extent);
  const nlohmann::json root = {
      {"format", kPlanFormat},
      {"version", 2},
      {"tile_m", plan.config.tile_m},
      {"overlap_m", plan.config.overlap_m},
      {"guard_m", plan.config.guard_m},
      {"up", {plan.up_W.x(), plan.up_W.y(), plan.up_W.z()}},
      {"metres_per_unit", plan.metres_per_unit},
      {"stream", {{"events", plan.stream_events}, {"keyframe_events", plan.stream_keyframe_events}}},
      {"extent_m", extent},
      {"tiles", tiles}};
  json::writeJsonFile(path, root);
}

TilePlan readTilePlan(const std::filesystem::path& path) {
  const nlohmann::json root = json::readJsonFile(path, "a tile plan written by terramesh tiles plan");
  const json::FieldReader json(path.string());
  json.header(root, kPlanFormat, 2);
  TilePlan plan;
  plan.config.tile_m = json.number(root, "tile_m", "");
  plan.config.overlap_m = json.number(root, "overlap_m", "");
  plan.config.guard_m = json.number(root, "guard_m", "");
  try {
    plan.config.validate();
  } catch (const std::invalid_argument& error) {
    json.fail("tile_m, overlap_m, guard_m", error.what());
  }
  plan.up_W = internal::readDirection(json, root, "up", "");
  plan.metres_per_unit = json.number(root, "metres_per_unit", "");
  if (!(plan.metres_per_unit > 0) || !std::isfinite(plan.metres_per_unit)) json.fail("metres_per_unit", "expected > 0");
  const nlohmann::json& stream = json.member(root, "stream", "");
  plan.stream_events = json.count(stream, "events", "stream");
  plan.stream_keyframe_events = json.count(stream, "keyframe_events", "stream");
  const nlohmann::json& extent = json.member(root, "extent_m", "");
  plan.extent = {json.number(extent, "min_x", "extent_m"), json.number(extent, "min_y", "extent_m"),
                 json.number(extent, "max_x", "extent_m"), json.number(extent, "max_y", "extent_m")};
  const nlohmann::json& tiles = json.array(root, "tiles", "");
  if (tiles.empty()) json.fail("tiles", "expected at least one tile");
  std::set<std::string> names;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    plan.tiles.push_back(readTile(json, tiles[i], i));
    if (i > 0 && std::make_pair(plan.tiles[i - 1].row, plan.tiles[i - 1].column) >=
                     std::make_pair(plan.tiles[i].row, plan.tiles[i].column)) {
      json.fail("tiles[" + std::to_string(i) + "]", "expected tiles sorted by row, then column, each cell once");
    }
    if (!names.insert(plan.tiles[i].name).second) {
      json.fail("tiles[" + std::to_string(i) + "].name", "\"" + plan.tiles[i].name + "\" names another tile too");
    }
  }
  return plan;
}

std::filesystem::path tileDirectory(const std::filesystem::path& plan_path, const TileSpec& tile) {
  return plan_path.parent_path() / tile.name;
}

std::filesystem::path tileMapDirectory(const std::filesystem::path& plan_path, const TileSpec& tile) {
  return tileDirectory(plan_path, tile) / "map";
}

void writeTileRecord(const std::filesystem::path& plan_path, const TileSpec& tile, const TileRecord& record) {
  std::vector<std::string> files = record.files;
  std::sort(files.begin(), files.end());
  nlohmann::json levels = nlohmann::json::array();
  for (std::size_t l = 0; l < record.level_heights_m.size(); ++l) {
    levels.push_back({{"level", l}, {"mean_height_m", record.level_heights_m[l]}});
  }
  const nlohmann::json root = {{"format", kRecordFormat}, {"version", 1},       {"index", record.index},
                               {"name", tile.name},       {"revision", record.revision}, {"faces", record.faces},
                               {"levels", levels},        {"files", files}};
  json::writeJsonFile(tileDirectory(plan_path, tile) / kRecordName, root);
}

TileRecord readTileRecord(const std::filesystem::path& plan_path, const TileSpec& tile) {
  const std::filesystem::path path = tileDirectory(plan_path, tile) / kRecordName;
  if (!std::filesystem::exists(path)) {
    throw InputError(path.string(), "", "missing: tile " + std::to_string(tile.index) +
                                            " has no result yet (run terramesh mesh STREAM --tile PLAN:" +
                                            std::to_string(tile.index) + " --robot R.yaml)");
  }
  const nlohmann::json root = json::readJsonFile(path, "a tile result written by terramesh mesh --tile");
  const json::FieldReader json(path.string());
  json.header(root, kRecordFormat, 1);
  TileRecord record;
  record.index = json.count(root, "index", "");
  if (record.index != tile.index) json.fail("index", "expected " + std::to_string(tile.index));
  record.revision = json.count(root, "revision", "");
  record.faces = json.count(root, "faces", "");
  const nlohmann::json& levels = json.array(root, "levels", "");
  for (std::size_t l = 0; l < levels.size(); ++l) {
    record.level_heights_m.push_back(json.number(levels[l], "mean_height_m", "levels[" + std::to_string(l) + "]"));
  }
  const nlohmann::json& files = json.array(root, "files", "");
  for (std::size_t k = 0; k < files.size(); ++k) {
    if (!files[k].is_string()) json.fail("files[" + std::to_string(k) + "]", "expected a file name");
    record.files.push_back(files[k].get<std::string>());
  }
  return record;
}

}  // namespace terramesh::tiling
