#include "mesh_freeze.h"

#include <malloc.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <variant>

#include "common/input_error.h"
#include "tiling/tile_map.h"
#include "traversability/map_directory.h"

namespace terramesh::cli {

void addFreezeOptions(CLI::App& app, FreezeOptions& options) {
  app.add_option("--freeze-radius-m", options.radius_m,
                 "online freeze of a long drive (needs --robot): a tile farther than this from the "
                 "last keyframes, and not seen for a while, is written to OUTDIR/tiles and its "
                 "keyframes leave the mesher, so memory stays bounded by the active region "
                 "(docs/tiles.md)")
      ->check(positiveNumber())
      ->option_text("M");
  app.add_option("--freeze-tile-m", options.config.tile_m, "side of a frozen tile, metres")
      ->check(positiveNumber());
  app.add_option("--freeze-recent-keyframes", options.config.recent_keyframes,
                 "the freeze radius is measured from each of this many last keyframes")
      ->check(positiveNumber());
  app.add_option("--freeze-idle-keyframes", options.config.idle_keyframes,
                 "a tile freezes only after this many keyframes without one within reach of it");
}

std::optional<MeshFreeze> MeshFreeze::fromOptions(const FreezeOptions& options,
                                                  const TraversabilitySession* session,
                                                  double reach_m,
                                                  const std::filesystem::path& output) {
  if (!options.radius_m) return std::nullopt;
  if (session == nullptr) {
    throw UsageError("mesh: --freeze-radius-m needs --robot YAML (a frozen tile is its layers)");
  }
  // Large blocks (ray paths, snapshots, rasters) from mmap, returned to the system when freed: with
  // glibc's adaptive threshold they come from the heap after a while and fragment it, so the
  // resident memory of a long drive would creep although the map's size stays flat.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  tiling::FreezeConfig config = options.config;
  config.radius_m = *options.radius_m;
  const traversability::MapFrame& frame = session->frame();
  const traversability::MapPlane plane =
      traversability::MapPlane::fromUp(frame.up_W, frame.metres_per_unit);
  return MeshFreeze(tiling::OnlineFreeze(config, plane, reach_m), config,
                    output / "tiles" / "plan.json", *session);
}

MeshFreeze::MeshFreeze(tiling::OnlineFreeze freeze, const tiling::FreezeConfig& config,
                       std::filesystem::path plan_path, const TraversabilitySession& session)
    : freeze_(std::move(freeze)),
      config_(config),
      plan_path_(std::move(plan_path)),
      up_W_(session.frame().up_W),
      metres_per_unit_(session.frame().metres_per_unit) {}

bool MeshFreeze::skips(const datasets::StreamEvent& event, std::size_t index) {
  if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
    latest_event_[keyframe->id.value] = index;
    const bool skip = freeze_.retired(keyframe->id.value);
    skipped_events_ += skip ? 1 : 0;
    return skip;
  }
  const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event);
  if (removal == nullptr || !freeze_.retired(removal->keyframe.value)) return false;
  freeze_.removed(removal->keyframe.value);
  latest_event_.erase(removal->keyframe.value);
  ++skipped_events_;
  return true;
}

namespace {

/// Plan index of each tile by creation index (OnlineFreeze::tiles() names tile t tileName(t)).
std::vector<std::size_t> planIndices(const tiling::TilePlan& plan,
                                     const std::vector<tiling::TileSpec>& created) {
  std::unordered_map<std::string, std::size_t> by_name;
  for (const tiling::TileSpec& spec : plan.tiles) by_name.emplace(spec.name, spec.index);
  std::vector<std::size_t> indices;
  for (const tiling::TileSpec& spec : created) indices.push_back(by_name.at(spec.name));
  return indices;
}

}  // namespace

void MeshFreeze::writeTile(const traversability::LayeredMesh& map, const tiling::TilePlan& plan,
                           std::size_t plan_index, std::size_t tile,
                           const TraversabilitySession& session, std::uint64_t revision) {
  const tiling::TileSpec& spec = freeze_.tiles().at(tile);
  const traversability::LayeredMesh owned = tiling::ownedPart(map, plan, plan_index);
  const traversability::ExportReport report = traversability::writeMapDirectory(
      tiling::tileMapDirectory(plan_path_, spec), owned, session.profile(), session.exportConfig());
  tiling::TileRecord& record = records_[tile];
  record.revision = revision;
  record.faces = owned.mesh.faces.size();
  record.level_heights_m = report.level_heights_m;
  record.files = report.files;
}

MeshFreeze::Step MeshFreeze::afterKeyframe(const mesher::Keyframe& keyframe, std::size_t index,
                                           const TraversabilitySession* session,
                                           std::uint64_t revision) {
  latest_event_[keyframe.id.value] = index;
  freeze_.keyframe(keyframe.id.value, keyframe.position_W_C);
  // A thawed tile is written again when it freezes again.
  for (std::size_t tile : freeze_.takeThawed()) records_.erase(tile);
  Step step;
  for (std::uint64_t id : freeze_.takeReturned()) step.returned_events.push_back(latest_event_.at(id));
  std::sort(step.returned_events.begin(), step.returned_events.end());
  const std::vector<std::size_t> due = freeze_.freezeDue();
  if (!due.empty() && session != nullptr) {
    const traversability::LayeredMesh map = session->snapshot();
    const tiling::TilePlan plan = freeze_.plan(up_W_, metres_per_unit_, 0, 0);
    const std::vector<std::size_t> indices = planIndices(plan, freeze_.tiles());
    for (std::size_t tile : due) writeTile(map, plan, indices[tile], tile, *session, revision);
  }
  frozen_during_run_ += due.size();
  for (std::uint64_t id : freeze_.retireDue()) step.retire.push_back(mesher::KeyframeId{id});
  return step;
}

std::string MeshFreeze::settings() const {
  std::ostringstream line;
  line.precision(17);
  line << "radius_m=" << config_.radius_m << " tile_m=" << config_.tile_m
       << " recent_keyframes=" << config_.recent_keyframes
       << " idle_keyframes=" << config_.idle_keyframes;
  return line.str();
}

std::string MeshFreeze::state() const {
  // "records N", then per record: tile revision faces, the level heights and the files, each
  // list after its length (file names hold no spaces: writeMapDirectory's).
  std::ostringstream line;
  line.precision(17);
  line << "records " << records_.size();
  for (const auto& [tile, record] : records_) {
    line << ' ' << tile << ' ' << record.revision << ' ' << record.faces << ' '
         << record.level_heights_m.size();
    for (double height : record.level_heights_m) line << ' ' << height;
    line << ' ' << record.files.size();
    for (const std::string& file : record.files) line << ' ' << file;
  }
  return line.str();
}

void MeshFreeze::restore(const std::string& line, const std::string& file) {
  constexpr std::size_t kMaxListed = 10000;
  std::istringstream in(line);
  std::string tag;
  std::size_t count = 0;
  const auto fail = [&](const std::string& problem) {
    throw InputError(file, "run state.freeze_state", problem);
  };
  if (!(in >> tag >> count) || tag != "records") fail("expected \"records N\"");
  std::map<std::size_t, tiling::TileRecord> records;
  for (std::size_t r = 0; r < count; ++r) {
    std::size_t tile = 0, levels = 0, files = 0;
    tiling::TileRecord record;
    // A tile has a few levels and a dozen files: larger counts are a damaged line, not a
    // reason to allocate.
    if (!(in >> tile >> record.revision >> record.faces >> levels) || levels > kMaxListed) {
      fail("a truncated or damaged tile record");
    }
    record.level_heights_m.resize(levels);
    for (double& height : record.level_heights_m) in >> height;
    if (!(in >> files) || files > kMaxListed) fail("a truncated or damaged tile record");
    record.files.resize(files);
    for (std::string& name : record.files) in >> name;
    if (!in || tile >= freeze_.tiles().size() || !freeze_.frozen(tile)) {
      fail("the record of tile " + std::to_string(tile) + ", which the stream's replay did not freeze");
    }
    records.emplace(tile, std::move(record));
  }
  for (std::size_t tile = 0; tile < freeze_.tiles().size(); ++tile) {
    if (freeze_.frozen(tile) && records.count(tile) == 0) {
      fail("no record of tile " + std::to_string(tile) + ", which the stream's replay froze");
    }
  }
  records_ = std::move(records);
}

void MeshFreeze::finish(const TraversabilitySession& session, const datasets::SlamStream& stream,
                        std::uint64_t revision, std::ostream& summary) {
  const tiling::TilePlan plan =
      freeze_.plan(up_W_, metres_per_unit_, stream.events.size(), stream.keyframeEventCount());
  if (plan.tiles.empty()) {
    summary << "freeze: no keyframe, no tile\n";
    return;
  }
  const traversability::LayeredMesh map = session.snapshot();
  const std::vector<std::size_t> indices = planIndices(plan, freeze_.tiles());
  std::size_t faces = 0;
  for (std::size_t tile = 0; tile < indices.size(); ++tile) {
    if (records_.count(tile) == 0) writeTile(map, plan, indices[tile], tile, session, revision);
    tiling::TileRecord record = records_.at(tile);
    record.index = indices[tile];
    faces += record.faces;
    tiling::writeTileRecord(plan_path_, plan.tiles[indices[tile]], record);
  }
  tiling::writeTilePlan(plan_path_, plan);
  const tiling::FreezeStats stats = freeze_.stats();
  summary << "freeze: " << plan.tiles.size() << " tile(s) of " << plan.config.tile_m << " m in "
          << plan_path_.parent_path().string() << " (" << stats.frozen_tiles
          << " frozen during the drive, " << plan.tiles.size() - stats.frozen_tiles
          << " written at the end; " << frozen_during_run_ << " freeze(s) in all), " << faces
          << " faces; " << stats.retired_keyframes << " keyframe(s) retired from the mesher at the end, "
          << skipped_events_ << " event(s) of retired keyframes held back; " << stats.thawed_tiles
          << " tile thaw(s) (a keyframe reached a frozen tile again), which brought "
          << stats.returned_keyframes << " retired keyframe(s) back; join with terramesh tiles merge "
          << plan_path_.string() << "\n";
}

}  // namespace terramesh::cli
