#pragma once

// `terramesh plan` on a tiled map: the tiles around start and goal are joined and planned on, and
// more of them while the loaded ones do not connect the two (docs/tiles.md, "Planning across
// tiles").
#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "planning/surface_planner.h"
#include "traversability/layered_mesh.h"
#include "traversability/robot_profile.h"

namespace terramesh::cli {

/// The tile index MAP names: MAP itself if it is a .json file, MAP/tiles.json if MAP is a folder
/// holding one and no traversability.ply; nothing otherwise (a map directory, or a file that
/// loading a map directory refuses, naming what it expects).
std::optional<std::filesystem::path> tileIndexOf(const std::filesystem::path& map);

/// Plans on the joined map of some tiles (the caller builds its graph and planner).
using TilePlanner = std::function<planning::PlanResult(
    const traversability::LayeredMesh& map, const traversability::RobotProfile& profile)>;

struct TiledPlan {
  planning::PlanResult result;
  std::size_t tiles_loaded = 0;      ///< tiles of the last attempt
  std::size_t tiles_with_faces = 0;  ///< tiles of the index that own faces
  std::size_t attempts = 0;
  std::size_t border_edges = 0;  ///< edges joined across tile borders in the last attempt
  /// plan.txt lines: tiles, the attempts, the tiles loaded at last.
  std::string describe() const;
};

/// First the tiles meeting the plan rectangle of start and goal grown by `margin_m` (default: the
/// index's tile size; at least `min_margin_m`, e.g. the planner's snap radius); while start and
/// goal lie on walkable faces the loaded tiles do not connect (PlanStatus::kUnreachable) and tiles
/// are left out, the margin doubles. So the answer "unreachable" is the whole map's; any other is
/// given by the tiles loaded then.
/// @throw terramesh::InputError for a bad index or tile (readTileIndex, joinTiles);
///        std::invalid_argument for a point or margin that is not finite, or a margin not > 0.
TiledPlan planOnTiles(const std::filesystem::path& index_path, const Eigen::Vector3d& start_W,
                      const Eigen::Vector3d& goal_W, std::optional<double> margin_m,
                      double min_margin_m, const TilePlanner& plan);

}  // namespace terramesh::cli
