// Checkpoint and resume (issue 11, "Nothing lost"): a mesher saved after N updates, loaded and
// run to the end gives exactly the mesh, surface history and per-update work of the run that was
// never interrupted, in every mode; a truncated, bit-flipped or foreign checkpoint is refused with
// an InputError naming the file, and nothing is half-loaded.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "common/input_error.h"
#include "datasets/slam_simulation.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"
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

UpdateStats apply(Mesher& mesher, const datasets::StreamEvent& event) {
  return datasets::applyEvent(mesher, event);
}

/// What an update did, timings left out (they are the only part allowed to differ).
auto work(const UpdateStats& s) {
  return std::make_tuple(s.new_points, s.moved_points, s.removed_points, s.dropped_points, s.duplicate_points,
                         s.deferred_points, s.steiner_points, s.rays_traced, s.rays_retraced, s.rays_untraced,
                         s.cells_shrunk, s.cells_grown, s.genus_pass_cells, s.edge_pass_cells, s.walk_steps,
                         s.cache_hits);
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
  std::vector<std::size_t> outside_cells_per_update;  ///< size of O after each update
  SurfaceDelta last_changes;
  MapSize size;
};

/// Runs `events`; at each index in `stops` (ascending) saves, checks the checkpoint round trip and
/// continues with a mesher loaded from it instead of the original.
template <class Event>
RunResult run(MesherConfig config, const std::vector<Event>& events,
              const std::vector<std::size_t>& stops) {
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
    result.outside_cells_per_update.push_back(mesher.size().outside_cells);
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
    ASSERT_EQ(resumed.outside_cells_per_update[i], straight.outside_cells_per_update[i])
        << "O differs after update " << i;
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
  config.handle_min_rays = 17;  // romanoni15's default is 0
  config.surface_history_max_bytes = 777777;
  config.driven_ground_up_W = Eigen::Vector3d(0.6, 0.0, 0.8);
  Mesher mesher(config);
  const LoadedCheckpoint loaded = load(save(mesher));
  const MesherConfig& back = loaded.mesher.config();
  EXPECT_EQ(back.mode(), MesherMode::kRomanoni15);
  EXPECT_EQ(back.metres_per_unit, 0.5);
  EXPECT_EQ(back.min_views, 3);
  EXPECT_EQ(back.edge_pass_min_weight, 123.0);
  EXPECT_EQ(back.handle_min_rays, 17);
  EXPECT_EQ(back.surface_history_max_bytes, 777777u);
  EXPECT_EQ(back.driven_ground_up_W, config.driven_ground_up_W);
  EXPECT_EQ(back.spread_cap, config.spread_cap);
  EXPECT_EQ(back.point_policy, config.point_policy);
  ASSERT_TRUE(back.fixed_grid_bounds_W.has_value());
  EXPECT_EQ(back.fixed_grid_bounds_W->max_W, config.fixed_grid_bounds_W->max_W);
  EXPECT_EQ(loaded.mesher.size().cells, mesher.size().cells);
}

// The ball pass of manifold growing (issue 14) remembers, from one update to the next, the balls
// it tried and in what neighbourhood, and skips those whose neighbourhood has not changed (at most
// 32 tries per update). A resumed run must remember the same. On this street (the scene of
// `terramesh generate street --seed 1`), update 41 carves a ball that the uninterrupted run skips,
// remembered as refused since update 37-39: a run that forgets on resume carves more there (found
// with a checkpoint every 4 events, and every 8 as here; a single one at event 36 or 31 misses it).
// Cut after 56 events to keep the test short; the checkpoints chain (each resumes from the last).
TEST(CheckpointResume, BallPassMemoryComesBackOnAStreet) {
  datasets::StreetSceneConfig street;
  street.seed = 1;
  const datasets::SyntheticScene scene = datasets::buildStreetScene(street);
  const datasets::TriangleBvh bvh(scene.ground_truth.mesh);
  datasets::SlamSimulationConfig slam;
  slam.seed = 1;
  const datasets::SimulatedSlam simulated = datasets::simulateSlam(scene, bvh, slam);
  ASSERT_GT(simulated.stream.events.size(), 56u);
  const std::vector<datasets::StreamEvent> events(simulated.stream.events.begin(),
                                                  simulated.stream.events.begin() + 56);
  const MesherConfig config = MesherConfig::forMode(MesherMode::kProposed);
  ASSERT_TRUE(config.edge_growing_pass);
  const RunResult straight = run(config, events, {});
  std::size_t edge_and_ball_cells = 0;
  for (const auto& w : straight.work_per_update) edge_and_ball_cells += std::get<13>(w);
  EXPECT_GT(edge_and_ball_cells, 0u) << "the edge and ball passes must carve on this stream";
  ASSERT_GT(straight.mesh.faces.size(), 1000u);
  std::vector<std::size_t> stops;
  for (std::size_t i = 8; i < events.size(); i += 8) stops.push_back(i);
  expectSameRun(run(config, events, stops), straight);
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

/// FNV-1a 64 (the header's checksum, docs/formats.md).
std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

template <class T>
void putLittleEndian(std::string& bytes, T value) {
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    bytes.push_back(static_cast<char>((value >> (8 * i)) & 0xff));
  }
}

template <class T>
T getLittleEndian(const std::string& bytes, std::size_t at) {
  T value = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    value |= static_cast<T>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
  }
  return value;
}

/// `checkpoint` with its ball-refusal table (the payload's last section: a uint64 count, then a
/// uint32 uid and a uint64 signature per entry) replaced by `count` and `entries`, with the size
/// and checksum redone.
std::string withBallRefusals(const std::string& checkpoint, std::uint64_t count,
                             const std::vector<std::pair<std::uint32_t, std::uint64_t>>& entries) {
  constexpr std::size_t kHeader = 28;
  std::size_t table = std::string::npos;
  for (std::uint64_t n = 0; n < 100000 && 8 + 12 * n <= checkpoint.size() - kHeader; ++n) {
    const std::size_t at = checkpoint.size() - 8 - 12 * n;
    if (getLittleEndian<std::uint64_t>(checkpoint, at) == n) {
      table = at;
      break;
    }
  }
  EXPECT_NE(table, std::string::npos) << "no ball-refusal table at the end of the payload";
  std::string payload = checkpoint.substr(kHeader, table - kHeader);
  putLittleEndian(payload, count);
  for (const auto& [uid, signature] : entries) {
    putLittleEndian(payload, uid);
    putLittleEndian(payload, signature);
  }
  std::string bytes = checkpoint.substr(0, 12);
  putLittleEndian(bytes, static_cast<std::uint64_t>(payload.size()));
  putLittleEndian(bytes, fnv1a64(payload));
  return bytes + payload;
}

TEST(CheckpointRefusal, InconsistentBallRefusalsAreRefused) {
  const std::string bytes = smallCheckpoint();
  // The table as saved, and a well-formed one, load and save back to the same bytes.
  for (const std::string& good :
       {withBallRefusals(bytes, 0, {}), withBallRefusals(bytes, 2, {{1, 7}, {9, 5}})}) {
    const LoadedCheckpoint loaded = load(good);
    EXPECT_EQ(firstDifference(save(loaded.mesher, loaded.app_data), good), std::string::npos);
  }
  expectRefused(withBallRefusals(bytes, 1, {{0xfffffff0u, 1}}), "a cell uid below");
  expectRefused(withBallRefusals(bytes, 2, {{9, 1}, {1, 2}}), "cell uids in increasing order");
  expectRefused(withBallRefusals(bytes, 2, {{9, 1}, {9, 2}}), "cell uids in increasing order");
  expectRefused(withBallRefusals(bytes, 2, {{9, 1}}), "more than the remaining");
  std::vector<std::pair<std::uint32_t, std::uint64_t>> too_many;
  for (std::uint32_t uid = 1; uid <= 65537; ++uid) too_many.emplace_back(uid, 0);
  expectRefused(withBallRefusals(bytes, too_many.size(), too_many),
                "at most 65536 remembered ball refusals");
}

TEST(CheckpointRefusal, ForeignFilesAreRefused) {
  expectRefused("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n", "not a terramesh checkpoint");
}

}  // namespace
}  // namespace terramesh::mesher
