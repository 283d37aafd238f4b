// Checkpoint and resume (issue 11, "Nothing lost"): a mesher saved after N updates, loaded and
// run to the end gives exactly the mesh, surface history and per-update work of the run that was
// never interrupted, in every mode; a truncated, bit-flipped or foreign checkpoint is refused with
// an InputError naming the file, and nothing is half-loaded.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "common/input_error.h"
#include "mesher/checkpoint.h"
#include "mesher/mesher.h"
#include "random_stream.h"

namespace terramesh::mesher {
namespace {

constexpr MesherMode kModes[] = {MesherMode::kProposed, MesherMode::kLitvinov13, MesherMode::kRomanoni15};

std::vector<test::StreamEvent> randomEvents(std::uint64_t seed, std::size_t keyframes) {
  test::RandomStreamConfig config;
  config.seed = seed;
  config.keyframes = keyframes;
  test::RandomStream stream(config);
  std::vector<test::StreamEvent> events;
  test::StreamEvent event;
  while (stream.next(event)) events.push_back(event);
  return events;
}

MesherConfig configFor(MesherMode mode) {
  MesherConfig config = MesherConfig::forMode(mode);
  config.steiner_step_m = 4.0;
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = test::RandomStream::bounds();
  return config;
}

UpdateStats apply(Mesher& mesher, const test::StreamEvent& event) {
  switch (event.kind) {
    case test::StreamEvent::Kind::kKeyframe:
      return mesher.integrateKeyframe(event.keyframe);
    case test::StreamEvent::Kind::kRemovePoints:
      return mesher.removePoints(event.points);
    case test::StreamEvent::Kind::kRemoveKeyframe:
      return mesher.removeKeyframe(event.removed);
  }
  return {};
}

/// What an update did, timings left out (they are the only part allowed to differ).
auto work(const UpdateStats& s) {
  return std::make_tuple(s.new_points, s.moved_points, s.removed_points, s.dropped_points, s.duplicate_points,
                         s.deferred_points, s.steiner_points, s.rays_traced, s.rays_retraced, s.rays_untraced,
                         s.cells_shrunk, s.cells_grown, s.genus_pass_cells, s.walk_steps, s.cache_hits);
}

std::string save(const Mesher& mesher, const std::string& app_data = {}) {
  std::ostringstream out(std::ios::binary);
  saveCheckpoint(mesher, out, app_data);
  return out.str();
}

LoadedCheckpoint load(const std::string& bytes, const std::string& name = "test.ckpt") {
  std::istringstream in(bytes, std::ios::binary);
  return loadCheckpoint(in, name);
}

/// Offset of the first byte where `a` and `b` differ, npos if equal.
std::size_t firstDifference(const std::string& a, const std::string& b) {
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (a[i] != b[i]) return i;
  }
  return a.size() == b.size() ? std::string::npos : n;
}

struct RunResult {
  TriangleMesh mesh;
  std::uint64_t revision = 0;
  std::vector<decltype(work(UpdateStats{}))> work_per_update;
  SurfaceDelta last_changes;
  MapSize size;
};

/// Runs `events`; at each index in `stops` (ascending) saves, checks the checkpoint round trip and
/// continues with a mesher loaded from it instead of the original.
RunResult run(MesherConfig config, const std::vector<test::StreamEvent>& events, const std::vector<std::size_t>& stops) {
  RunResult result;
  Mesher mesher(config);
  std::size_t next_stop = 0;
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (next_stop < stops.size() && stops[next_stop] == i) {
      ++next_stop;
      const std::string bytes = save(mesher, "event " + std::to_string(i));
      LoadedCheckpoint loaded = load(bytes);
      EXPECT_EQ(loaded.app_data, "event " + std::to_string(i));
      const std::string again = save(loaded.mesher, loaded.app_data);
      EXPECT_EQ(firstDifference(again, bytes), std::string::npos)
          << "a loaded checkpoint saves to the same bytes (sizes " << again.size() << ", " << bytes.size() << ")";
      const InvariantReport report = loaded.mesher.checkInvariants();
      EXPECT_TRUE(report.ok()) << "after loading at event " << i << ": " << report.summary();
      EXPECT_EQ(loaded.mesher.revision(), mesher.revision());
      mesher = std::move(loaded.mesher);
    }
    result.work_per_update.push_back(work(apply(mesher, events[i])));
  }
  result.mesh = mesher.extractMesh();
  result.revision = mesher.revision();
  result.last_changes = mesher.changesSince(result.revision > 20 ? result.revision - 20 : 0);
  result.size = mesher.size();
  EXPECT_TRUE(mesher.checkInvariants().ok());
  return result;
}

void expectSameRun(const RunResult& resumed, const RunResult& straight) {
  EXPECT_EQ(resumed.mesh.vertices, straight.mesh.vertices);
  EXPECT_EQ(resumed.mesh.faces, straight.mesh.faces);
  EXPECT_EQ(resumed.mesh.is_steiner, straight.mesh.is_steiner);
  EXPECT_EQ(resumed.revision, straight.revision);
  EXPECT_EQ(resumed.last_changes.removed, straight.last_changes.removed);
  EXPECT_EQ(resumed.last_changes.added.size(), straight.last_changes.added.size());
  EXPECT_EQ(resumed.size.cells, straight.size.cells);
  EXPECT_EQ(resumed.size.rays, straight.size.rays);
  EXPECT_EQ(resumed.size.ray_crossings, straight.size.ray_crossings);
  ASSERT_EQ(resumed.work_per_update.size(), straight.work_per_update.size());
  for (std::size_t i = 0; i < straight.work_per_update.size(); ++i) {
    ASSERT_EQ(resumed.work_per_update[i], straight.work_per_update[i]) << "update " << i << " did different work";
  }
}

class CheckpointResume : public ::testing::TestWithParam<MesherMode> {};

// The premise: the mesher is deterministic. Two runs in one process (different heap addresses)
// do the same work and give the same mesh.
TEST_P(CheckpointResume, TwoUninterruptedRunsAgree) {
  const MesherMode mode = GetParam();
  const std::vector<test::StreamEvent> events = randomEvents(21 + static_cast<std::uint64_t>(mode), 50);
  const RunResult first = run(configFor(mode), events, {});
  const RunResult second = run(configFor(mode), events, {});
  expectSameRun(second, first);
}

TEST_P(CheckpointResume, ResumedRunEqualsTheUninterruptedRun) {
  const MesherMode mode = GetParam();
  const std::vector<test::StreamEvent> events = randomEvents(21 + static_cast<std::uint64_t>(mode), 60);
  ASSERT_GT(events.size(), 70u);
  const RunResult straight = run(configFor(mode), events, {});
  ASSERT_GT(straight.mesh.faces.size(), 100u);
  // Checkpoints early (small map), mid-stream and late, and a chain of them.
  const std::size_t n = events.size();
  for (const std::vector<std::size_t>& stops :
       {std::vector<std::size_t>{0, n / 2}, std::vector<std::size_t>{3, n / 4, 3 * n / 4, n - 2}}) {
    SCOPED_TRACE(std::string(toString(mode)) + ", first stop at event " + std::to_string(stops.front()));
    expectSameRun(run(configFor(mode), events, stops), straight);
    if (HasFatalFailure()) return;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMode, CheckpointResume, ::testing::ValuesIn(kModes),
                         [](const ::testing::TestParamInfo<MesherMode>& param) { return std::string(toString(param.param)); });

TEST(CheckpointResume, ConfigurationComesBackWithTheState) {
  MesherConfig config = configFor(MesherMode::kRomanoni15);
  config.metres_per_unit = 0.5;
  config.min_views = 3;
  config.edge_pass_min_weight = 123.0;
  config.surface_history_max_bytes = 777777;
  Mesher mesher(config);
  const LoadedCheckpoint loaded = load(save(mesher));
  const MesherConfig& back = loaded.mesher.config();
  EXPECT_EQ(back.mode(), MesherMode::kRomanoni15);
  EXPECT_EQ(back.metres_per_unit, 0.5);
  EXPECT_EQ(back.min_views, 3);
  EXPECT_EQ(back.edge_pass_min_weight, 123.0);
  EXPECT_EQ(back.surface_history_max_bytes, 777777u);
  EXPECT_EQ(back.spread_cap, config.spread_cap);
  EXPECT_EQ(back.point_policy, config.point_policy);
  ASSERT_TRUE(back.fixed_grid_bounds_W.has_value());
  EXPECT_EQ(back.fixed_grid_bounds_W->max_W, config.fixed_grid_bounds_W->max_W);
  EXPECT_EQ(loaded.mesher.size().cells, mesher.size().cells);
}

/// A checkpoint of a small but real map.
std::string smallCheckpoint() {
  const std::vector<test::StreamEvent> events = randomEvents(5, 12);
  Mesher mesher(configFor(MesherMode::kProposed));
  for (const test::StreamEvent& event : events) apply(mesher, event);
  return save(mesher, "app");
}

void expectRefused(const std::string& bytes, const std::string& what_contains) {
  try {
    load(bytes, "/runs/a/mesher.ckpt");
    ADD_FAILURE() << "accepted a bad checkpoint (expected: " << what_contains << ")";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), "/runs/a/mesher.ckpt");
    EXPECT_NE(std::string(error.what()).find(what_contains), std::string::npos) << error.what();
  }
}

TEST(CheckpointRefusal, TruncatedFilesAreRefused) {
  const std::string bytes = smallCheckpoint();
  ASSERT_GT(bytes.size(), 10000u);
  for (std::size_t length : {std::size_t{0}, std::size_t{5}, std::size_t{27}, std::size_t{28}, std::size_t{100},
                             bytes.size() / 2, bytes.size() - 1}) {
    SCOPED_TRACE("length " + std::to_string(length));
    expectRefused(bytes.substr(0, length), "truncated");
  }
  expectRefused(bytes + "x", "after the checkpoint");
}

TEST(CheckpointRefusal, EveryFlippedBitIsCaught) {
  const std::string bytes = smallCheckpoint();
  // Header fields, then payload bytes spread over the file (configuration, triangulation, rays,
  // registry, surface history): the magic and version are named, the rest fails the checksum
  // (or a size flip makes the payload look truncated).
  for (std::size_t at = 0; at < bytes.size(); at += (at < 64 ? 1 : 997)) {
    std::string bad = bytes;
    bad[at] = static_cast<char>(bad[at] ^ (1 << (at % 8)));
    SCOPED_TRACE("byte " + std::to_string(at));
    try {
      load(bad, "/runs/a/mesher.ckpt");
      ADD_FAILURE() << "accepted a checkpoint with byte " << at << " flipped";
    } catch (const InputError& error) {
      EXPECT_EQ(error.file(), "/runs/a/mesher.ckpt");
      const std::string what = error.what();
      const std::string expected = at < 8    ? "not a terramesh checkpoint"
                                   : at < 12 ? "format version"
                                   : at < 20 ? "checkpoint"
                                             : "checksum mismatch";
      EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
  }
}

TEST(CheckpointRefusal, ForeignFilesAreRefused) {
  expectRefused("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n", "not a terramesh checkpoint");
}

}  // namespace
}  // namespace terramesh::mesher
