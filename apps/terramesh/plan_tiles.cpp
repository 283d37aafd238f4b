#include "plan_tiles.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tiling/tile_index.h"

namespace terramesh::cli {

std::optional<std::filesystem::path> tileIndexOf(const std::filesystem::path& map) {
  if (std::filesystem::is_regular_file(map) && map.extension() == ".json") return map;
  if (std::filesystem::is_directory(map) && !std::filesystem::exists(map / "traversability.ply") &&
      std::filesystem::is_regular_file(map / "tiles.json")) {
    return map / "tiles.json";
  }
  return std::nullopt;
}

std::string TiledPlan::describe() const {
  std::ostringstream out;
  out << "tiles_loaded " << tiles_loaded << "\ntiles_with_faces " << tiles_with_faces
      << "\ntile_attempts " << attempts << "\nborder_edges " << border_edges << '\n';
  return out.str();
}

TiledPlan planOnTiles(const std::filesystem::path& index_path, const Eigen::Vector3d& start_W,
                      const Eigen::Vector3d& goal_W, std::optional<double> margin_m,
                      double min_margin_m, const TilePlanner& plan) {
  if (!start_W.allFinite() || !goal_W.allFinite())
    throw std::invalid_argument("planOnTiles: start and goal must be finite");
  const tiling::TileIndex index = tiling::readTileIndex(index_path);
  const double first_margin = std::max(margin_m.value_or(index.tile_m), min_margin_m);
  if (!(first_margin > 0) || !std::isfinite(first_margin))
    throw std::invalid_argument("planOnTiles: the margin must be > 0");
  const Eigen::Vector2d a = index.plane.planM(start_W), b = index.plane.planM(goal_W);
  const tiling::PlanRect around{std::min(a.x(), b.x()), std::min(a.y(), b.y()),
                                std::max(a.x(), b.x()), std::max(a.y(), b.y())};
  TiledPlan tiled;
  tiled.tiles_with_faces = static_cast<std::size_t>(std::count_if(
      index.tiles.begin(), index.tiles.end(), [](const tiling::IndexedTile& t) { return t.faces > 0; }));
  std::vector<std::size_t> loaded;
  for (double margin = first_margin;; margin *= 2) {
    std::vector<std::size_t> tiles = tiling::tilesMeeting(index, around.grown(margin));
    if (tiles.empty() && tiled.tiles_with_faces > 0) continue;  // nothing near yet: widen
    if (tiles == loaded && tiles.size() < tiled.tiles_with_faces) continue;
    loaded = tiles;
    ++tiled.attempts;
    if (tiles.empty()) {
      tiled.result.status = planning::PlanStatus::kNoStart;
      tiled.result.reason = "no tile of " + index_path.string() + " owns a face";
      return tiled;
    }
    const tiling::JoinedTiles joined = tiling::joinTiles(index, tiles);
    tiled.tiles_loaded = tiles.size();
    tiled.border_edges = joined.border_edges;
    tiled.result = plan(joined.map, joined.profile);
    const bool all = tiles.size() >= tiled.tiles_with_faces;
    if (tiled.result.status != planning::PlanStatus::kUnreachable || all) return tiled;
  }
}

}  // namespace terramesh::cli
