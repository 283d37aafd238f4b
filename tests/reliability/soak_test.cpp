// The invariant soak: thousands of keyframes of a randomised stream (moving, culled and outlier
// points, corrected and removed keyframes, a sliding window), checkInvariants() every K updates,
// in every mode; the final surface is a closed manifold.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "mesher/mesher.h"
#include "random_stream.h"

namespace terramesh::mesher {
namespace {

struct SoakCase {
  MesherMode mode;
  std::size_t keyframes;
  std::size_t check_every;
};

/// TERRAMESH_SOAK_KEYFRAMES overrides the keyframe count (for longer runs by hand).
std::size_t keyframeCount(std::size_t fallback) {
  const char* value = std::getenv("TERRAMESH_SOAK_KEYFRAMES");
  return value != nullptr ? static_cast<std::size_t>(std::strtoull(value, nullptr, 10)) : fallback;
}

class InvariantSoak : public ::testing::TestWithParam<SoakCase> {};

TEST_P(InvariantSoak, EveryCheckIsCleanAndTheSurfaceStaysAManifold) {
  const SoakCase soak = GetParam();
  test::RandomStreamConfig stream_config;
  stream_config.seed = 11 + static_cast<std::uint64_t>(soak.mode);
  stream_config.keyframes = keyframeCount(soak.keyframes);
  test::RandomStream stream(stream_config);
  MesherConfig config = MesherConfig::forMode(soak.mode);
  config.steiner_step_m = 4.0;
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = test::RandomStream::bounds();
  Mesher mesher(config);

  UpdateStats totals;
  std::size_t updates = 0, checks = 0, max_points = 0;
  test::StreamEvent event;
  while (stream.next(event)) {
    switch (event.kind) {
      case test::StreamEvent::Kind::kKeyframe:
        totals += mesher.integrateKeyframe(event.keyframe);
        break;
      case test::StreamEvent::Kind::kRemovePoints:
        totals += mesher.removePoints(event.points);
        break;
      case test::StreamEvent::Kind::kRemoveKeyframe:
        totals += mesher.removeKeyframe(event.removed);
        break;
    }
    max_points = std::max(max_points, mesher.size().inserted_points);
    if (++updates % soak.check_every == 0) {
      ++checks;
      const InvariantReport report = mesher.checkInvariants();
      ASSERT_TRUE(report.ok()) << "update " << updates << ", keyframe " << stream.counts().keyframes << ": "
                               << report.summary();
    }
  }
  const InvariantReport report = mesher.checkInvariants();
  ASSERT_TRUE(report.ok()) << "at the end: " << report.summary();
  const MeshTopology topology = analyzeTopology(mesher.extractMesh());
  EXPECT_TRUE(topology.isClosedManifold());
  EXPECT_GT(topology.faces, 100u);

  // The stream exercised what it claims to.
  const test::RandomStreamCounts& counts = stream.counts();
  EXPECT_EQ(counts.keyframes, stream_config.keyframes);
  EXPECT_GT(counts.corrections, 0u);
  EXPECT_GT(counts.keyframe_removals, counts.keyframes / 2);
  EXPECT_GT(counts.point_removals, 0u);
  EXPECT_GT(counts.outliers, 0u);
  if (config.point_policy == PointPolicy::kExactMoves) {
    EXPECT_GT(totals.moved_points, 0u);
  }
  EXPECT_GT(totals.removed_points, 0u);
  EXPECT_GT(totals.cells_grown, 0u);
  EXPECT_GT(checks, counts.keyframes / soak.check_every);
  EXPECT_EQ(totals.walk_failures, 0u);
  EXPECT_EQ(totals.walk_step_limit_hits, 0u);
  // The sliding window keeps the map bounded (the stream creates 20,000+ points): a point lives
  // while a keyframe of the window sees it, and is re-observed at most track_keyframes after its
  // creation; twice the window leaves room for keyframes removed at random inside it.
  EXPECT_LE(max_points, (2 * stream_config.window + stream_config.track_keyframes) *
                            static_cast<std::size_t>(stream_config.new_points_per_keyframe));
  std::printf("[ soak ] %s: %zu keyframes, %zu updates, %zu checks clean, max %zu points, %zu faces\n",
              toString(soak.mode), counts.keyframes, updates, checks + 1, max_points, topology.faces);
}

INSTANTIATE_TEST_SUITE_P(AllModes, InvariantSoak,
                         ::testing::Values(SoakCase{MesherMode::kProposed, 2000, 25},
                                           SoakCase{MesherMode::kLitvinov13, 1000, 25},
                                           SoakCase{MesherMode::kRomanoni15, 1000, 25}),
                         [](const auto& param_info) { return std::string(toString(param_info.param.mode)); });

}  // namespace
}  // namespace terramesh::mesher
