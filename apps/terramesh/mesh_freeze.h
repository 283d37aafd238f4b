#pragma once

// `terramesh mesh STREAM --robot R.yaml --freeze-radius-m R`: the online freeze of a long drive
// (tiling/online_freeze.h, docs/tiles.md "Online: the freeze"). Tiles the drive left behind are
// written into OUTDIR/tiles as they freeze; the keyframes that only saw frozen tiles leave the
// mesher; at the end the tiles still active are written, with the plan and each tile's record,
// so that `terramesh tiles merge OUTDIR/tiles/plan.json` joins them like tiles meshed apart.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <ostream>
#include <unordered_map>
#include <vector>

#include "cli_args.h"
#include "datasets/slam_stream.h"
#include "tiling/online_freeze.h"
#include "tiling/tile_files.h"
#include "traversability_session.h"

namespace terramesh::cli {

/// The options of the freeze.
struct FreezeOptions {
  std::optional<double> radius_m;  ///< --freeze-radius-m: enables the freeze
  tiling::FreezeConfig config;
};
/// Adds --freeze-radius-m, --freeze-tile-m, --freeze-recent-keyframes and --freeze-idle-keyframes.
void addFreezeOptions(CLI::App& app, FreezeOptions& options);

class MeshFreeze {
 public:
  /// nullopt without --freeze-radius-m. `reach_m`: the mesher's max_camera_distance_m.
  /// @throw UsageError without a traversability session (--robot); std::invalid_argument for a bad
  ///        config.
  static std::optional<MeshFreeze> fromOptions(const FreezeOptions& options,
                                               const TraversabilitySession* session, double reach_m,
                                               const std::filesystem::path& output);

  /// Whether to leave event `index` out: a retired keyframe sent again (a correction of a frozen
  /// tile's keyframe: kept as that keyframe's latest version, for when it comes back) or removed
  /// (it never comes back). Counted for the summary.
  bool skips(const datasets::StreamEvent& event, std::size_t index);
  /// What the mesher has to do after a keyframe.
  struct Step {
    /// Events to integrate again (the latest versions of the keyframes that came back), in order.
    std::vector<std::size_t> returned_events;
    /// Keyframes to remove from the mesher (after those).
    std::vector<mesher::KeyframeId> retire;
  };
  /// After keyframe `keyframe` (event `index`) was integrated and the layers updated: thaws the
  /// frozen tiles it reached, writes the tiles that froze from `session`'s map at mesher revision
  /// `revision` and says which keyframes come back and which retire. Without a session (the replay
  /// of --resume) it decides alike and writes nothing: the tiles are on disk, their records in the
  /// checkpoint (restore).
  Step afterKeyframe(const mesher::Keyframe& keyframe, std::size_t index,
                     const TraversabilitySession* session, std::uint64_t revision);

  /// The options that decide what freezes, as one line: a resumed run must have the same.
  std::string settings() const;
  /// The records of the tiles written and frozen, as one line (for a checkpoint).
  std::string state() const;
  /// After replaying the stream up to a checkpoint (skips and afterKeyframe without a session):
  /// takes the records of state() back.
  /// @throw terramesh::InputError naming `file` if the line is malformed or its tiles are not the
  ///        ones the replay froze.
  void restore(const std::string& line, const std::string& file);
  /// The sensor positions of the keyframes still in the mesher (map units).
  std::vector<Eigen::Vector3d> liveCentres() const { return freeze_.liveCentres(); }
  /// The stream removed keyframe `id`.
  void removed(mesher::KeyframeId id) { freeze_.removed(id.value); }
  /// Writes the tiles not frozen from the final map, every tile's record and the plan; appends
  /// summary lines.
  void finish(const TraversabilitySession& session, const datasets::SlamStream& stream,
              std::uint64_t revision, std::ostream& summary);

 private:
  MeshFreeze(tiling::OnlineFreeze freeze, const tiling::FreezeConfig& config,
             std::filesystem::path plan_path, const TraversabilitySession& session);
  /// Writes tile `tile` (creation index; `plan_index` in `plan`) of `map` into its map folder and
  /// keeps its record.
  void writeTile(const traversability::LayeredMesh& map, const tiling::TilePlan& plan,
                 std::size_t plan_index, std::size_t tile, const TraversabilitySession& session,
                 std::uint64_t revision);

  tiling::OnlineFreeze freeze_;
  tiling::FreezeConfig config_;
  std::filesystem::path plan_path_;
  Eigen::Vector3d up_W_;
  double metres_per_unit_;
  /// Records of the tiles written, by creation index (their plan index is set at the end).
  std::map<std::size_t, tiling::TileRecord> records_;
  /// The event of each keyframe's latest version sent so far.
  std::unordered_map<std::uint64_t, std::size_t> latest_event_;
  std::size_t skipped_events_ = 0;
  std::size_t frozen_during_run_ = 0;
};

}  // namespace terramesh::cli
