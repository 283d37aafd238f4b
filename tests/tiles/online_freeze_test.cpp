// The online freeze's rules on drives along a line: which tiles freeze, which keyframes retire,
// revisits, and the plan it gives `tiles merge`.
#include "tiling/online_freeze.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "test_support/temp_dir.h"
#include "tiling/tile_files.h"

namespace terramesh::tiling {
namespace {

constexpr double kReachM = 5.0;

FreezeConfig smallTiles() {
  FreezeConfig config;
  config.tile_m = 10.0;
  config.radius_m = 20.0;
  config.recent_keyframes = 3;
  config.idle_keyframes = 2;
  return config;
}

OnlineFreeze makeFreeze(const FreezeConfig& config = smallTiles()) {
  return OnlineFreeze(config, traversability::MapPlane::fromUp(Eigen::Vector3d::UnitZ(), 1.0),
                      kReachM);
}

Eigen::Vector3d at(double x) { return {x, 0.0, 1.5}; }

/// What one drive did: every tile freezeDue returned, every keyframe retireDue returned, every
/// tile thawed and every keyframe brought back.
struct Drive {
  std::multiset<std::size_t> frozen, thawed;
  std::set<std::uint64_t> retired, returned;
};

/// Sends keyframes `first_id`, ... at the positions `xs`, collecting what freezes, retires, thaws
/// and comes back, and checks after each keyframe that no tile within the radius of it froze and
/// that every keyframe brought back had reached a thawed tile.
Drive drive(OnlineFreeze& freeze, const std::vector<double>& xs, std::uint64_t first_id = 0) {
  Drive result;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    freeze.keyframe(first_id + k, at(xs[k]));
    const std::vector<std::size_t> thawed = freeze.takeThawed();
    result.thawed.insert(thawed.begin(), thawed.end());
    for (std::uint64_t id : freeze.takeReturned()) {
      EXPECT_FALSE(freeze.retired(id));
      EXPECT_EQ(result.returned.count(id), 0u);
      result.returned.insert(id);
    }
    for (std::size_t tile : freeze.freezeDue()) {
      result.frozen.insert(tile);
      EXPECT_GT(freeze.tiles()[tile].bounds.distanceM({xs[k], 0.0}), smallTiles().radius_m)
          << "tile " << tile;
    }
    for (std::uint64_t id : freeze.retireDue()) result.retired.insert(id);
  }
  return result;
}

std::vector<double> straight(double from, double to, double step) {
  std::vector<double> xs;
  for (double x = from; step > 0 ? x <= to : x >= to; x += step) xs.push_back(x);
  return xs;
}

TEST(FreezeConfig, ValidateListsEveryProblem) {
  FreezeConfig config;
  config.tile_m = 0;
  config.radius_m = -1;
  config.recent_keyframes = 0;
  try {
    config.validate();
    FAIL() << "no throw";
  } catch (const std::invalid_argument& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("tile_m"), std::string::npos) << what;
    EXPECT_NE(what.find("radius_m"), std::string::npos) << what;
    EXPECT_NE(what.find("recent_keyframes"), std::string::npos) << what;
  }
  EXPECT_THROW(OnlineFreeze(FreezeConfig{}, traversability::MapPlane{}, 0.0),
               std::invalid_argument);
}

TEST(OnlineFreeze, TilesBehindTheDriveFreezeOnceAndTheirKeyframesRetire) {
  OnlineFreeze freeze = makeFreeze();
  const Drive result = drive(freeze, straight(0, 100, 2));
  // Every tile is returned at most once, and the tiles far behind the end all froze.
  for (std::size_t tile : result.frozen) EXPECT_EQ(result.frozen.count(tile), 1u);
  for (const TileSpec& spec : freeze.tiles()) {
    const bool behind = spec.bounds.max_x_m < 100.0 - smallTiles().radius_m;
    EXPECT_EQ(freeze.frozen(spec.index), behind) << spec.name << " at x " << spec.bounds.min_x_m;
    EXPECT_EQ(result.frozen.count(spec.index), behind ? 1u : 0u);
  }
  // A keyframe retires exactly when every tile within its reach is frozen.
  ASSERT_FALSE(result.retired.empty());
  for (std::uint64_t id = 0; id <= 50; ++id) {
    const double x = 2.0 * static_cast<double>(id);
    bool all_frozen = true;
    for (const TileSpec& spec : freeze.tiles()) {
      if (spec.bounds.distanceM({x, 0.0}) <= kReachM)
        all_frozen = all_frozen && freeze.frozen(spec.index);
    }
    EXPECT_EQ(freeze.retired(id), all_frozen) << "keyframe at x " << x;
    EXPECT_EQ(result.retired.count(id), all_frozen ? 1u : 0u);
  }
  const FreezeStats stats = freeze.stats();
  EXPECT_EQ(stats.frozen_tiles, result.frozen.size());
  EXPECT_EQ(stats.retired_keyframes, result.retired.size());
  EXPECT_EQ(stats.thawed_tiles, 0u);
  EXPECT_TRUE(result.thawed.empty());
}

TEST(OnlineFreeze, NothingFreezesWhileTheDriveStaysNear) {
  OnlineFreeze freeze = makeFreeze();
  std::vector<double> xs;
  for (int lap = 0; lap < 10; ++lap) {
    for (double x : straight(0, 10, 2)) xs.push_back(x);
    for (double x : straight(10, 0, -2)) xs.push_back(x);
  }
  const Drive result = drive(freeze, xs);
  EXPECT_TRUE(result.frozen.empty());
  EXPECT_TRUE(result.retired.empty());
}

TEST(OnlineFreeze, IdleKeyframesHoldATileBack) {
  FreezeConfig config = smallTiles();
  config.idle_keyframes = 1000;
  OnlineFreeze freeze = makeFreeze(config);
  const Drive result = drive(freeze, straight(0, 100, 2));
  EXPECT_TRUE(result.frozen.empty());  // far enough, but seen fewer than 1000 keyframes ago
}

TEST(OnlineFreeze, ADriveBackThawsTheTilesAndBringsTheirKeyframesBack) {
  OnlineFreeze freeze = makeFreeze();
  const Drive out = drive(freeze, straight(0, 100, 2));
  ASSERT_FALSE(out.frozen.empty());
  const Drive back = drive(freeze, straight(98, 0, -2), 1000);
  // Every tile the drive back reached thawed (the tiles frozen on the way out), and the keyframes
  // of the way out that had reached one came back: all of the way out's retired keyframes.
  EXPECT_EQ(std::set<std::size_t>(back.thawed.begin(), back.thawed.end()),
            std::set<std::size_t>(out.frozen.begin(), out.frozen.end()));
  EXPECT_EQ(back.returned, out.retired);
  EXPECT_EQ(freeze.stats().thawed_tiles, back.thawed.size());
  EXPECT_EQ(freeze.stats().returned_keyframes, out.retired.size());
  // Behind the drive back the tiles froze again, and the keyframes there (of both ways) retired.
  for (const TileSpec& spec : freeze.tiles()) {
    EXPECT_EQ(freeze.frozen(spec.index), spec.bounds.min_x_m > smallTiles().radius_m) << spec.name;
  }
  EXPECT_TRUE(freeze.retired(50));   // the way out's last keyframe, at x = 100
  EXPECT_TRUE(freeze.retired(1000));  // the way back's first, at x = 98
  EXPECT_FALSE(freeze.retired(0));    // at x = 0, where the drive is
  // A removed keyframe, retired or not, never comes back.
  freeze.removed(50);
  EXPECT_FALSE(freeze.retired(50));
  const Drive again = drive(freeze, straight(2, 100, 2), 2000);
  EXPECT_EQ(again.returned.count(50), 0u);
  EXPECT_GT(again.returned.count(1000), 0u);
}

TEST(OnlineFreeze, PlanSortsTheTilesAndKeepsTheirNames) {
  OnlineFreeze freeze = makeFreeze();
  drive(freeze, straight(0, 60, 2));
  const TilePlan plan = freeze.plan(Eigen::Vector3d::UnitZ(), 1.0, 40, 31);
  ASSERT_EQ(plan.tiles.size(), freeze.tiles().size());
  std::set<std::string> names;
  for (std::size_t i = 0; i < plan.tiles.size(); ++i) {
    const TileSpec& tile = plan.tiles[i];
    EXPECT_EQ(tile.index, i);
    names.insert(tile.name);
    if (i > 0) {
      EXPECT_LT(std::make_pair(plan.tiles[i - 1].row, plan.tiles[i - 1].column),
                std::make_pair(tile.row, tile.column));
    }
    // The grid starts at the extent's corner: column and row from there.
    EXPECT_DOUBLE_EQ(tile.bounds.min_x_m,
                     plan.extent.min_x_m + 10.0 * static_cast<double>(tile.column));
    EXPECT_DOUBLE_EQ(tile.bounds.min_y_m,
                     plan.extent.min_y_m + 10.0 * static_cast<double>(tile.row));
    EXPECT_EQ(plan.ownerOf({tile.bounds.min_x_m + 5, tile.bounds.min_y_m + 5}), i);
  }
  EXPECT_EQ(names.size(), plan.tiles.size());
  EXPECT_EQ(plan.tiles.front().name,
            "tile_000");  // x [-10, 0), y [-10, 0): reached first, lowest cell
  // The plan file reads back as written.
  const test::TempDir dir;
  writeTilePlan(dir / "plan.json", plan);
  const TilePlan read = readTilePlan(dir / "plan.json");
  ASSERT_EQ(read.tiles.size(), plan.tiles.size());
  for (std::size_t i = 0; i < plan.tiles.size(); ++i)
    EXPECT_EQ(read.tiles[i].name, plan.tiles[i].name);
  EXPECT_EQ(read.stream_keyframe_events, 31u);
}

}  // namespace
}  // namespace terramesh::tiling
