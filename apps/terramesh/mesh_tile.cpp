#include "mesh_tile.h"

#include <sstream>

#include "common/input_error.h"
#include "tiling/tile_files.h"
#include "tiling/tile_map.h"

namespace terramesh::cli {

MeshTile MeshTile::fromOption(const std::string& value) {
  const std::size_t colon = value.rfind(':');
  const std::string form = "--tile must be PLAN:I (a plan file written by terramesh tiles plan and a tile index)";
  if (colon == std::string::npos || colon == 0 || colon + 1 == value.size()) throw UsageError(form + ", got \"" + value + "\"");
  const std::vector<std::optional<std::size_t>> index = parseColonIntegers(value.substr(colon + 1), "--tile", "PLAN:I", 1);
  if (!index.front()) throw UsageError(form + ", got \"" + value + "\"");
  const std::filesystem::path plan_path = value.substr(0, colon);
  tiling::TilePlan plan = tiling::readTilePlan(plan_path);
  if (*index.front() >= plan.tiles.size()) {
    throw InputError(plan_path.string(), "tiles",
                     "no tile " + std::to_string(*index.front()) + ": the plan has " + std::to_string(plan.tiles.size()) +
                         " tiles (0 to " + std::to_string(plan.tiles.size() - 1) + ")");
  }
  return MeshTile(plan_path, std::move(plan), *index.front());
}

std::filesystem::path MeshTile::outputDirectory() const {
  return tiling::tileDirectory(plan_path_, plan_.tiles[index_]);
}

void MeshTile::selectInput(const datasets::SlamStream& stream, const std::filesystem::path& stream_path) {
  if (stream.events.size() != plan_.stream_events || stream.keyframeEventCount() != plan_.stream_keyframe_events) {
    throw InputError(stream_path.string(), "",
                     "not the stream " + plan_path_.string() + " was planned for (" + std::to_string(stream.events.size()) +
                         " events, " + std::to_string(stream.keyframeEventCount()) + " keyframe events; the plan expects " +
                         std::to_string(plan_.stream_events) + " and " + std::to_string(plan_.stream_keyframe_events) +
                         ")");
  }
  input_ = tiling::selectTileInput(stream, plan_, index_);
}

void MeshTile::attach(TraversabilitySession& session, const traversability::ExportConfig& config,
                      double metres_per_unit) {
  if ((session.frame().up_W - plan_.up_W).norm() > 1e-9 || metres_per_unit != plan_.metres_per_unit) {
    std::ostringstream problem;
    problem.precision(17);
    problem << "mesh --tile: this run's frame (up " << session.frame().up_W.transpose() << ", metres_per_unit "
            << metres_per_unit << ") is not the plan's (up " << plan_.up_W.transpose() << ", metres_per_unit "
            << plan_.metres_per_unit << "); plan and mesh with the same --robot and --metres-per-unit";
    throw std::invalid_argument(problem.str());
  }
  const traversability::RobotProfile profile = session.profile();
  session.setExportHook([this, profile, config](const traversability::LayeredMesh& map, std::uint64_t revision) {
    const tiling::TileSpec& tile = plan_.tiles[index_];
    const traversability::LayeredMesh owned = tiling::ownedPart(map, plan_, index_);
    const traversability::ExportReport report =
        traversability::writeMapDirectory(tiling::tileMapDirectory(plan_path_, tile), owned, profile, config);
    tiling::TileRecord record;
    record.index = index_;
    record.revision = revision;
    record.faces = owned.mesh.faces.size();
    record.level_heights_m = report.level_heights_m;
    record.files = report.files;
    tiling::writeTileRecord(plan_path_, tile, record);
  });
}

std::string MeshTile::describe() const {
  const tiling::TileSpec& tile = plan_.tiles[index_];
  std::ostringstream out;
  out << "tile: " << index_ << " (" << tile.name << ") of " << plan_.tiles.size() << " in " << plan_path_.string()
      << ", bounds x [" << tile.bounds.min_x_m << ", " << tile.bounds.max_x_m << ") y [" << tile.bounds.min_y_m << ", "
      << tile.bounds.max_y_m << ") m, overlap " << plan_.config.overlap_m << " m, guard " << plan_.config.guard_m
      << " m; input "
      << (input_ ? input_->keyframes : 0) << " keyframes, " << (input_ ? input_->points : 0) << " points, "
      << (input_ ? input_->stream.events.size() : 0) << " events";
  return out.str();
}

}  // namespace terramesh::cli
