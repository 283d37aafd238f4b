// A removed point or keyframe frees its memory: the mesher's own accounting (Mesher::size())
// goes back down after removals, and repeated insert/remove cycles do not make it grow.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "mesher/mesher.h"
#include "random_stream.h"

namespace terramesh::mesher {
namespace {

/// Integrates the keyframes of `stream` and returns their ids (other events are skipped).
std::vector<KeyframeId> integrate(Mesher& mesher, test::RandomStream& stream) {
  std::vector<KeyframeId> ids;
  test::StreamEvent event;
  while (stream.next(event)) {
    if (event.kind != test::StreamEvent::Kind::kKeyframe) continue;
    mesher.integrateKeyframe(event.keyframe);
    ids.push_back(event.keyframe.id);
  }
  return ids;
}

/// A stream of keyframes only: no culls, corrections, removals, outliers or duplicates.
test::RandomStreamConfig addOnly(std::uint64_t seed, std::size_t keyframes) {
  test::RandomStreamConfig config;
  config.seed = seed;
  config.keyframes = keyframes;
  config.window = 0;
  config.cull_probability = 0;
  config.correction_probability = 0;
  config.keyframe_removal_probability = 0;
  config.outlier_fraction = 0;
  config.duplicate_probability = 0;
  return config;
}

std::size_t withoutHistory(const MapSize& s) { return s.triangulation_bytes + s.ray_bytes + s.point_bytes; }

class MemoryAccounting : public ::testing::TestWithParam<MesherMode> {
 protected:
  MesherConfig config() const {
    MesherConfig config = MesherConfig::forMode(GetParam());
    config.steiner_step_m = 4.0;
    if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = test::RandomStream::bounds();
    return config;
  }
};

TEST_P(MemoryAccounting, RemovingEveryKeyframeFreesItsRaysPointsAndCells) {
  Mesher mesher(config());
  // A first lap over every stream of the test fixes the Steiner grid (it never shrinks, and an
  // incremental grid grows to whatever the data reaches), then is removed again.
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    test::RandomStream lap(addOnly(seed, seed == 1 ? 130 : 60));
    for (KeyframeId id : integrate(mesher, lap)) mesher.removeKeyframe(id);
  }
  const MapSize before = mesher.size();
  EXPECT_EQ(before.keyframes, 0u);
  EXPECT_EQ(before.points, 0u);
  EXPECT_EQ(before.rays, 0u);

  std::vector<MapSize> loaded, emptied;
  for (std::uint64_t cycle = 0; cycle < 3; ++cycle) {
    // Each cycle's stream numbers its ids from 0 again: the mesher forgot the removed ones.
    test::RandomStream stream(addOnly(2 + cycle, 60));
    const std::vector<KeyframeId> ids = integrate(mesher, stream);
    loaded.push_back(mesher.size());
    for (KeyframeId id : ids) mesher.removeKeyframe(id);
    emptied.push_back(mesher.size());
  }
  for (std::size_t cycle = 0; cycle < loaded.size(); ++cycle) {
    const MapSize& full = loaded[cycle];
    const MapSize& empty = emptied[cycle];
    SCOPED_TRACE("cycle " + std::to_string(cycle));
    EXPECT_GT(full.rays, 5000u);
    EXPECT_GT(full.inserted_points, 500u);
    EXPECT_GT(full.ray_crossings, 10 * full.rays / 2);
    // Every ray, point and keyframe is gone; the triangulation is back to the Steiner grid.
    EXPECT_EQ(empty.keyframes, 0u);
    EXPECT_EQ(empty.points, 0u);
    EXPECT_EQ(empty.rays, 0u);
    EXPECT_EQ(empty.ray_crossings, 0u);
    EXPECT_EQ(empty.inserted_points, 0u);
    EXPECT_EQ(empty.steiner_vertices, before.steiner_vertices);
    EXPECT_EQ(empty.cells, before.cells);
    // What the rays, points and cells held is returned: the accounting drops to within the
    // recycled record slots of the empty map (at most 5 % of what the loaded map added) ...
    EXPECT_LE(withoutHistory(empty), withoutHistory(before) + (withoutHistory(full) - withoutHistory(before)) / 20)
        << "loaded " << withoutHistory(full) << " B, empty " << withoutHistory(empty) << " B, before "
        << withoutHistory(before) << " B";
    // ... and the surface history stays within its fixed number of revisions.
    EXPECT_LE(empty.index_bytes, full.index_bytes * 2);
  }
  for (std::size_t cycle = 0; cycle < loaded.size(); ++cycle) {
    std::printf("[ memory ] %s cycle %zu: before %zu B, loaded %zu B (%zu rays, %zu points), emptied %zu B "
                "(history %zu -> %zu B)\n",
                toString(GetParam()), cycle, withoutHistory(before), withoutHistory(loaded[cycle]), loaded[cycle].rays,
                loaded[cycle].inserted_points, withoutHistory(emptied[cycle]), loaded[cycle].index_bytes,
                emptied[cycle].index_bytes);
  }
  // Cycles reuse the freed slots: the empty map does not grow from cycle to cycle.
  EXPECT_LE(withoutHistory(emptied.back()), withoutHistory(emptied.front()) + 64 * 1024);
}

TEST_P(MemoryAccounting, CulledPointsFreeTheirRaysAndVertices) {
  Mesher mesher(config());
  const test::RandomStreamConfig stream_config = addOnly(5, 40);
  test::RandomStream stream(stream_config);
  integrate(mesher, stream);
  const MapSize full = mesher.size();
  // Cull every point of the map (ids are dense from 0).
  std::vector<PointId> all;
  const auto created = stream_config.keyframes * static_cast<std::size_t>(stream_config.new_points_per_keyframe);
  for (std::uint64_t id = 0; id < created; ++id) all.push_back(PointId{id});
  mesher.removePoints(all);
  const MapSize culled = mesher.size();
  EXPECT_GT(full.rays, 1000u);
  EXPECT_EQ(culled.points, 0u);
  EXPECT_EQ(culled.rays, 0u);
  EXPECT_EQ(culled.ray_crossings, 0u);
  EXPECT_EQ(culled.inserted_points, 0u);
  EXPECT_EQ(culled.keyframes, full.keyframes) << "keyframes stay, with nothing to observe";
  EXPECT_LT(culled.ray_bytes, full.ray_bytes / 4);
  EXPECT_LT(culled.triangulation_bytes, full.triangulation_bytes);
  const InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
}

INSTANTIATE_TEST_SUITE_P(AllModes, MemoryAccounting,
                         ::testing::Values(MesherMode::kProposed, MesherMode::kRomanoni15),
                         [](const auto& param_info) { return std::string(toString(param_info.param)); });

}  // namespace
}  // namespace terramesh::mesher
