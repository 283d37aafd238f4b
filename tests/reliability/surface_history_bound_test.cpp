// The surface history kept for Mesher::changesSince is bounded in bytes
// (MesherConfig::surface_history_max_bytes) as well as in revisions: the bound holds after every
// update, the newest revision is always kept, and a consumer asking for a revision older than
// what is kept is told so (`complete == false`: resync from surfaceFaces()), never given a wrong
// delta.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesher/checkpoint.h"
#include "mesher/mesher.h"
#include "random_stream.h"
#include "surface_log.h"  // white-box: mesher/src

namespace terramesh::mesher {
namespace {

using internal::SurfaceLog;
using internal::WoundFace;

WoundFace face(std::uint64_t a) {
  return {VertexKey::point(PointId{a}), VertexKey::point(PointId{a + 1}), VertexKey::point(PointId{a + 2})};
}

/// Commits one revision adding `faces` new faces (ids from `next`).
void commitFaces(SurfaceLog& log, std::size_t faces, std::uint64_t& next) {
  for (std::size_t f = 0; f < faces; ++f, next += 3) log.faceAdded(face(next));
  log.commit();
}

TEST(SurfaceHistoryBound, LogStaysWithinItsBytesAndKeepsTheNewestRevision) {
  constexpr std::size_t kBound = 64 * 1024;
  SurfaceLog log(4096, kBound);
  std::uint64_t next = 0;
  std::size_t max_records = 0;
  for (int r = 1; r <= 400; ++r) {
    commitFaces(log, 50, next);  // ~3 KB per record (faces and their touched vertices)
    ASSERT_EQ(log.revision(), static_cast<std::uint64_t>(r));
    const std::uint64_t kept = log.revision() - log.oldestRevision();
    ASSERT_GE(kept, 1u) << "the newest revision is always kept";
    if (kept > 1) {
      ASSERT_LE(log.memoryBytes(), kBound) << "revision " << r;
    }
    max_records = std::max<std::size_t>(max_records, kept);
  }
  // The bytes, not the 4,096 revisions, limited the history; and it did keep several revisions.
  EXPECT_LT(max_records, 400u);
  EXPECT_GT(max_records, 5u);
  EXPECT_GT(log.memoryBytes(), kBound / 2);
  // What is kept is exact: the last revision added exactly its 50 faces.
  const SurfaceLog::Changes last = log.since(log.revision() - 1);
  EXPECT_EQ(last.added.size(), 50u);
  EXPECT_TRUE(last.removed.empty());

  // A single revision larger than the bound is still kept (alone), so a consumer that polls after
  // every update never has to resync.
  commitFaces(log, 5000, next);
  EXPECT_EQ(log.oldestRevision(), log.revision() - 1);
  EXPECT_GT(log.memoryBytes(), kBound);
  EXPECT_EQ(log.since(log.revision() - 1).added.size(), 5000u);
  // ... and the next small one drops it.
  commitFaces(log, 10, next);
  EXPECT_LE(log.memoryBytes(), kBound);

  // The revision bound still applies when the bytes allow more.
  SurfaceLog few_revisions(8, kBound);
  for (int r = 0; r < 20; ++r) commitFaces(few_revisions, 1, next);
  EXPECT_EQ(few_revisions.revision() - few_revisions.oldestRevision(), 8u);
}

TEST(SurfaceHistoryBound, ConfigurationIsValidated) {
  MesherConfig config;
  EXPECT_EQ(config.surface_history_max_bytes, std::size_t{32} << 20);
  EXPECT_TRUE(config.problems().empty());
  for (std::size_t bad : {std::size_t{0}, std::size_t{65535}, (std::size_t{1} << 40) + 1}) {
    config.surface_history_max_bytes = bad;
    const std::vector<std::string> problems = config.problems();
    ASSERT_EQ(problems.size(), 1u) << bad;
    EXPECT_NE(problems.front().find("surface_history_max_bytes"), std::string::npos) << problems.front();
    EXPECT_THROW(config.validate(), std::invalid_argument);
    EXPECT_THROW(Mesher{config}, std::invalid_argument);
  }
  config.surface_history_max_bytes = 65536;
  EXPECT_TRUE(config.problems().empty());
}

/// Face keys of a face list, sorted.
std::vector<FaceKey> keysOf(const std::vector<SurfaceFace>& faces) {
  std::vector<FaceKey> keys;
  for (const SurfaceFace& f : faces) keys.push_back(f.key);
  std::sort(keys.begin(), keys.end());
  return keys;
}

/// Oldest revision whose changes the mesher can still give.
std::uint64_t oldestKept(const Mesher& mesher) {
  std::uint64_t oldest = mesher.revision();
  while (oldest > 0 && mesher.changesSince(oldest - 1).complete) --oldest;
  return oldest;
}

TEST(SurfaceHistoryBound, TooOldRevisionIsReportedNotSilentlyWrong) {
  test::RandomStreamConfig stream_config;
  stream_config.seed = 5;
  stream_config.keyframes = 120;
  test::RandomStream stream(stream_config);
  MesherConfig config = MesherConfig::forMode(MesherMode::kProposed);
  config.steiner_step_m = 4.0;
  MesherConfig unbounded_config = config;
  config.surface_history_max_bytes = 1 << 20;
  unbounded_config.surface_history_max_bytes = std::size_t{1} << 40;
  Mesher bounded(config);
  Mesher unbounded(unbounded_config);  // the same map, all its history

  // A consumer that polls after every update and replays the deltas onto its face keys.
  std::vector<FaceKey> replica;
  std::uint64_t replica_revision = 0;
  std::uint64_t stale_revision = 0;  // a consumer that stopped polling after 10 keyframes
  std::size_t updates = 0;
  test::StreamEvent event;
  while (stream.next(event)) {
    for (Mesher* mesher : {&bounded, &unbounded}) {
      switch (event.kind) {
        case test::StreamEvent::Kind::kKeyframe:
          mesher->integrateKeyframe(event.keyframe);
          break;
        case test::StreamEvent::Kind::kRemovePoints:
          mesher->removePoints(event.points);
          break;
        case test::StreamEvent::Kind::kRemoveKeyframe:
          mesher->removeKeyframe(event.removed);
          break;
      }
    }
    ++updates;
    ASSERT_EQ(bounded.revision(), unbounded.revision()) << "the history bound must not change the map";
    const SurfaceDelta delta = bounded.changesSince(replica_revision);
    ASSERT_TRUE(delta.complete) << "update " << updates << ": the newest revision is always kept";
    for (const FaceKey& removed : delta.removed) {
      const auto it = std::lower_bound(replica.begin(), replica.end(), removed);
      ASSERT_TRUE(it != replica.end() && *it == removed) << "update " << updates;
      replica.erase(it);
    }
    for (const SurfaceFace& added : delta.added) {
      replica.insert(std::lower_bound(replica.begin(), replica.end(), added.key), added.key);
    }
    replica_revision = delta.to_revision;
    if (stream.counts().keyframes == 10 && stale_revision == 0) stale_revision = bounded.revision();
  }
  EXPECT_EQ(replica, keysOf(bounded.surfaceFaces()));
  EXPECT_EQ(keysOf(bounded.surfaceFaces()), keysOf(unbounded.surfaceFaces()));

  // The bytes, not the revision count, made the stale consumer's revision too old.
  const std::uint64_t now = bounded.revision();
  ASSERT_GT(stale_revision, 0u);
  ASSERT_LT(now - stale_revision, Mesher::kSurfaceHistoryRevisions);
  const std::uint64_t oldest = oldestKept(bounded);
  EXPECT_GT(oldest, stale_revision);
  EXPECT_LT(oldest, now) << "some history is kept";
  EXPECT_TRUE(unbounded.changesSince(0).complete);
  const SurfaceDelta too_old = bounded.changesSince(stale_revision);
  EXPECT_FALSE(too_old.complete);
  EXPECT_EQ(too_old.from_revision, stale_revision);
  EXPECT_EQ(too_old.to_revision, now);
  EXPECT_TRUE(too_old.removed.empty() && too_old.added.empty() && too_old.touched_vertices.empty());
  // The unbounded mesher still has that history; the bounded one holds less memory for it.
  EXPECT_TRUE(unbounded.changesSince(stale_revision).complete);
  EXPECT_GT(unbounded.size().index_bytes, bounded.size().index_bytes + (std::size_t{1} << 20));
  // Where the bounded history is complete, it equals the full one.
  EXPECT_EQ(keysOf(bounded.changesSince(oldest).added), keysOf(unbounded.changesSince(oldest).added));
  EXPECT_EQ(bounded.changesSince(oldest).removed, unbounded.changesSince(oldest).removed);

  // A checkpoint keeps the bound and the same history.
  std::stringstream file;
  saveCheckpoint(bounded, file);
  const LoadedCheckpoint loaded = loadCheckpoint(file, "bounded.tmckpt");
  EXPECT_EQ(loaded.mesher.config().surface_history_max_bytes, std::size_t{1} << 20);
  EXPECT_EQ(oldestKept(loaded.mesher), oldest);
  EXPECT_FALSE(loaded.mesher.changesSince(stale_revision).complete);
  std::printf("[ history ] %zu updates, %llu revisions; 1 MiB bound keeps the last %llu; index bytes %zu "
              "(bounded) vs %zu (unbounded)\n",
              updates, static_cast<unsigned long long>(now), static_cast<unsigned long long>(now - oldest),
              bounded.size().index_bytes, unbounded.size().index_bytes);
}

}  // namespace
}  // namespace terramesh::mesher
