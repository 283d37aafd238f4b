#pragma once

// `terramesh mesh STREAM --tile PLAN:I --robot R.yaml`: one tile of a plan (docs/tiles.md). The
// run meshes the tile's input (tiling::selectTileInput) in the frame of the whole stream, writes
// its usual outputs (the whole meshed surface with the overlap, the map with the overlap) into the
// tile's folder, and at every export the part of the map the tile owns into its map folder, with
// the tile record last.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "datasets/slam_stream.h"
#include "tiling/tile_input.h"
#include "tiling/tile_plan.h"
#include "traversability/map_directory.h"
#include "traversability_session.h"

namespace terramesh::cli {

class MeshTile {
 public:
  /// Parses PLAN:I and reads the plan.
  /// @throw UsageError for a malformed value; terramesh::InputError naming the plan for a bad plan
  ///        or a tile it does not have.
  static MeshTile fromOption(const std::string& value);

  /// Where the tile's outputs go.
  std::filesystem::path outputDirectory() const;
  /// Checks that `stream` is the one planned (event counts) and selects the tile's input.
  /// @throw terramesh::InputError naming the stream file otherwise.
  void selectInput(const datasets::SlamStream& stream, const std::filesystem::path& stream_path);
  /// The tile's events (after selectInput).
  const datasets::SlamStream& input() const { return input_->stream; }
  /// Checks the run's frame against the plan's and makes every export of `session` also write the
  /// tile's owned part and record.
  /// @throw std::invalid_argument if up or scale differ from the plan's.
  void attach(TraversabilitySession& session, const traversability::ExportConfig& config, double metres_per_unit);
  /// One summary line.
  std::string describe() const;

 private:
  MeshTile(std::filesystem::path plan_path, tiling::TilePlan plan, std::size_t index)
      : plan_path_(std::move(plan_path)), plan_(std::move(plan)), index_(index) {}

  std::filesystem::path plan_path_;
  tiling::TilePlan plan_;
  std::size_t index_ = 0;
  std::optional<tiling::TileInput> input_;
};

}  // namespace terramesh::cli
