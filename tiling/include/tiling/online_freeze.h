#pragma once

// The online freeze of a long drive (docs/tiles.md, "Online: the freeze"): the map plane is cut
// into square tiles as the drive reaches them; a tile that every recent keyframe has left far
// behind, and that no keyframe has looked at for a while, freezes (its faces and layers are
// written once, as a tile of a tiled map), and a keyframe whose whole reach lies in frozen tiles
// retires (the caller removes it from the mesher, with its rays and the points only it saw). So
// the triangulation, the rays and the layers hold the active region only, and memory stays
// bounded by it, however long the drive.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <utility>
#include <vector>

#include "tiling/tile_plan.h"
#include "traversability/map_levels.h"

namespace terramesh::tiling {

/// When geometry freezes. Lengths in metres.
struct FreezeConfig {
  /// Side of a tile in the map plane; tiles are the cells of the grid aligned to multiples of it.
  double tile_m = 100.0;
  /// A tile freezes when its bounds lie farther than this from each of the last
  /// `recent_keyframes` keyframes' sensor positions (plan distance) ...
  double radius_m = 150.0;
  std::size_t recent_keyframes = 10;
  /// ... and no keyframe within reach of it came for this many keyframes.
  std::size_t idle_keyframes = 20;
  /// @throw std::invalid_argument listing every out-of-range field, each "key: value (expected
  /// ...)".
  void validate() const;
};

/// What the freeze has done so far.
struct FreezeStats {
  std::size_t tiles = 0;  ///< tiles the drive reached
  std::size_t frozen_tiles = 0;
  std::size_t retired_keyframes = 0;  ///< retired now
  /// A keyframe reached a frozen tile (a loop back): the tile thawed and the retired keyframes
  /// that had reached it came back. Counted over the drive.
  std::size_t thawed_tiles = 0;
  std::size_t returned_keyframes = 0;
};

/// Decides which tiles freeze and which keyframes retire. Positions in map units (the mesher's),
/// tiles in metres in the map plane. Not thread-safe.
class OnlineFreeze {
 public:
  /// `reach_m`: how far from its sensor a keyframe's points can lie (the mesher's
  /// max_camera_distance_m): the tiles a keyframe may touch.
  /// @throw std::invalid_argument for a bad config or reach.
  OnlineFreeze(const FreezeConfig& config, const traversability::MapPlane& plane, double reach_m);

  /// A keyframe was integrated (or sent again) with its sensor at `centre_W`. Every frozen tile
  /// within its reach thaws: it will freeze (and be written) again, and the retired keyframes
  /// that had reached it come back (takeReturned).
  void keyframe(std::uint64_t id, const Eigen::Vector3d& centre_W);
  /// A keyframe went (the stream removed it), live or retired.
  void removed(std::uint64_t id);
  /// The tiles thawed and the keyframes brought back since the last call, in id order: integrate
  /// those keyframes again (their latest version). They are live again.
  std::vector<std::size_t> takeThawed();
  std::vector<std::uint64_t> takeReturned();

  /// Tiles that freeze now (indices into tiles(), in creation order); each is returned once.
  std::vector<std::size_t> freezeDue();
  /// Keyframes every tile of whose reach is frozen: they retire now (each is returned once; remove
  /// them from the mesher). Call after writing the tiles freezeDue returned.
  std::vector<std::uint64_t> retireDue();
  /// Whether keyframe `id` retired (a later resend of it is to be skipped).
  bool retired(std::uint64_t id) const { return retired_.count(id) != 0; }
  bool frozen(std::size_t tile) const { return tiles_.at(tile).frozen; }
  /// The sensor positions of the keyframes neither retired nor removed (map units), by id.
  std::vector<Eigen::Vector3d> liveCentres() const;

  /// Every tile the drive reached, in creation order: `index` is that order, `name`
  /// tileName(index), `column` and `row` the grid cell (x / tile_m, y / tile_m, floored),
  /// `keyframes` how many keyframes reached it.
  const std::vector<TileSpec>& tiles() const { return specs_; }
  /// The tiles as a plan (TilePlan: sorted by row and column, `index` the position, `name` kept):
  /// what `tiles merge` reads. `tile_m` is the plan's tile size, its overlap 0.
  TilePlan plan(const Eigen::Vector3d& up_W, double metres_per_unit, std::size_t stream_events,
                std::size_t stream_keyframe_events) const;
  FreezeStats stats() const;

 private:
  struct Tile {
    std::size_t last_seen = 0;  ///< keyframe count when a keyframe last reached it
    bool frozen = false;
  };
  using Cell = std::pair<long, long>;  // column, row
  std::vector<Cell> cellsWithin(const Eigen::Vector2d& xy_m) const;

  FreezeConfig config_;
  traversability::MapPlane plane_;
  double reach_m_;
  std::size_t count_ = 0;  ///< keyframes seen
  std::map<Cell, std::size_t> tile_of_;
  std::vector<Tile> tiles_;
  std::vector<TileSpec> specs_;
  std::deque<Eigen::Vector2d> recent_;
  struct Live {
    Eigen::Vector3d centre_W;
    std::vector<std::size_t> reach;  ///< the tiles within reach
  };
  std::map<std::uint64_t, Live> live_;
  std::map<std::uint64_t, Live> retired_;
  std::vector<std::size_t> thawed_;
  std::vector<std::uint64_t> returned_;
  std::size_t thawed_count_ = 0, returned_count_ = 0;
};

}  // namespace terramesh::tiling
