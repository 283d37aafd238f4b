// Surface deltas are exact: replaying Mesher::changesSince after every update onto a face map gives
// exactly extractMesh() (faces, winding, positions, vertex keys) and surfaceFaces() (observation
// counts, refreshed through facesAround(touched_vertices)), on KITTI 00, a synthetic street and
// analytic scenes with moving and removed points, in every mode. So does replaying
// unconfirmedChangesSince onto a copy of unconfirmedPoints().
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <variant>

#include "datasets/slam_simulation.h"
#include "datasets/stream_reader.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"
#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

using FaceMap = std::map<FaceKey, SurfaceFace>;

const MesherMode kModes[] = {MesherMode::kProposed, MesherMode::kLitvinov13, MesherMode::kRomanoni15};

std::string describe(const VertexKey& key) {
  return (key.steiner ? "steiner " : "point ") + std::to_string(key.value);
}

std::string describe(const FaceKey& key) {
  return "face (" + describe(key.sorted[0]) + ", " + describe(key.sorted[1]) + ", " +
         describe(key.sorted[2]) + ")";
}

/// The faces of an extracted mesh, keyed and rotated like the mesher's SurfaceFace (smallest key
/// first, winding kept); rays are left 0. Fails if the vertex keys are missing or inconsistent.
FaceMap facesOfMesh(const TriangleMesh& mesh) {
  FaceMap faces;
  EXPECT_EQ(mesh.vertex_keys.size(), mesh.vertices.size());
  if (mesh.vertex_keys.size() != mesh.vertices.size()) return faces;
  EXPECT_EQ(std::set<VertexKey>(mesh.vertex_keys.begin(), mesh.vertex_keys.end()).size(),
            mesh.vertex_keys.size())
      << "two vertices share a key";
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    EXPECT_EQ(mesh.is_steiner[v] != 0, mesh.vertex_keys[v].steiner) << "vertex " << v;
  }
  for (const auto& triangle : mesh.faces) {
    std::size_t first = 0;
    for (std::size_t k = 1; k < 3; ++k) {
      if (mesh.vertex_keys[triangle[k]] < mesh.vertex_keys[triangle[first]]) first = k;
    }
    SurfaceFace face;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = triangle[(first + k) % 3];
      face.vertices[k] = mesh.vertex_keys[v];
      face.positions_W[k] = mesh.vertices[v];
      face.touches_steiner = face.touches_steiner || mesh.is_steiner[v] != 0;
    }
    face.key = FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    EXPECT_TRUE(faces.emplace(face.key, face).second) << describe(face.key) << " twice";
  }
  return faces;
}

FaceMap toMap(const std::vector<SurfaceFace>& faces) {
  FaceMap map;
  for (const SurfaceFace& face : faces) map.emplace(face.key, face);
  EXPECT_EQ(map.size(), faces.size()) << "repeated face keys";
  return map;
}

/// Same faces with the same winding, positions and Steiner flags (and rays and what lies behind,
/// if asked).
::testing::AssertionResult sameFaces(const FaceMap& actual, const FaceMap& expected, bool rays) {
  if (actual.size() != expected.size()) {
    return ::testing::AssertionFailure() << actual.size() << " faces, expected " << expected.size();
  }
  for (auto a = actual.begin(), e = expected.begin(); a != actual.end(); ++a, ++e) {
    const SurfaceFace& x = a->second;
    const SurfaceFace& y = e->second;
    if (a->first != e->first || x.key != a->first) {
      return ::testing::AssertionFailure() << describe(a->first) << " where " << describe(e->first)
                                           << " was expected";
    }
    if (x.vertices != y.vertices) return ::testing::AssertionFailure() << describe(x.key) << ": winding differs";
    if (x.positions_W != y.positions_W) {
      return ::testing::AssertionFailure() << describe(x.key) << ": positions differ";
    }
    if (x.touches_steiner != y.touches_steiner) {
      return ::testing::AssertionFailure() << describe(x.key) << ": touches_steiner differs";
    }
    if (rays && x.rays != y.rays) {
      return ::testing::AssertionFailure() << describe(x.key) << ": " << x.rays << " rays, expected " << y.rays;
    }
    if (rays && (x.back_crossings != y.back_crossings || x.back_depth != y.back_depth)) {
      return ::testing::AssertionFailure() << describe(x.key) << ": " << x.back_crossings << " rays behind, "
                                           << x.back_depth << " deep, expected " << y.back_crossings << ", "
                                           << y.back_depth;
    }
  }
  return ::testing::AssertionSuccess();
}

/// A consumer's copy of the surface, kept up to date from deltas only.
struct Replica {
  FaceMap faces;
  std::uint64_t revision = 0;

  /// Applies `delta` (erase removed, insert added) and refreshes the counts around the touched
  /// vertices. Fails on a delta inconsistent with the copy.
  void apply(const Mesher& mesher, const SurfaceDelta& delta) {
    ASSERT_TRUE(delta.complete);
    ASSERT_EQ(delta.from_revision, revision);
    ASSERT_TRUE(std::is_sorted(delta.touched_vertices.begin(), delta.touched_vertices.end()));
    ASSERT_TRUE(std::adjacent_find(delta.touched_vertices.begin(), delta.touched_vertices.end()) ==
                delta.touched_vertices.end());
    auto touched = [&delta](const VertexKey& v) {
      return std::binary_search(delta.touched_vertices.begin(), delta.touched_vertices.end(), v);
    };
    for (const FaceKey& key : delta.removed) {
      ASSERT_EQ(faces.erase(key), 1u) << describe(key) << " removed but absent at revision " << revision;
      for (const VertexKey& v : key.sorted) ASSERT_TRUE(touched(v)) << describe(key);
    }
    for (const SurfaceFace& face : delta.added) {
      ASSERT_TRUE(faces.emplace(face.key, face).second) << describe(face.key) << " added but present";
      for (const VertexKey& v : face.vertices) ASSERT_TRUE(touched(v)) << describe(face.key);
    }
    for (const SurfaceFace& face : mesher.facesAround(delta.touched_vertices)) {
      const auto it = faces.find(face.key);
      ASSERT_TRUE(it != faces.end()) << describe(face.key) << " around a touched vertex is unknown";
      it->second.rays = face.rays;
      it->second.back_crossings = face.back_crossings;
      it->second.back_depth = face.back_depth;
    }
    revision = delta.to_revision;
  }
};

/// Checks the replica against the mesher after an update.
void expectMatches(const Mesher& mesher, const Replica& replica, const std::string& where) {
  ASSERT_EQ(replica.revision, mesher.revision()) << where;
  const FaceMap extracted = facesOfMesh(mesher.extractMesh());
  ASSERT_TRUE(sameFaces(replica.faces, extracted, false)) << where << " (against extractMesh)";
  const FaceMap current = toMap(mesher.surfaceFaces());
  ASSERT_TRUE(sameFaces(replica.faces, current, true)) << where << " (against surfaceFaces)";
}

/// A consumer's copy of the unconfirmed points, kept up to date from unconfirmedChangesSince
/// (the whole set when the cursor is not answered).
struct UnconfirmedReplica {
  std::map<PointId, UnconfirmedPoint> points;
  UnconfirmedCursor cursor;

  void follow(const Mesher& mesher) {
    const UnconfirmedChanges changes = mesher.unconfirmedChangesSince(cursor);
    if (!changes.complete) {
      points.clear();
      for (const UnconfirmedPoint& p : mesher.unconfirmedPoints()) points[p.id] = p;
    } else {
      for (const PointId id : changes.gone) points.erase(id);
      for (const UnconfirmedPoint& p : changes.waiting) points[p.id] = p;
    }
    cursor = changes.cursor;
  }
  ::testing::AssertionResult matches(const Mesher& mesher) const {
    const std::vector<UnconfirmedPoint> now = mesher.unconfirmedPoints();
    if (now.size() != points.size()) {
      return ::testing::AssertionFailure() << points.size() << " unconfirmed points, the mesher has " << now.size();
    }
    for (const UnconfirmedPoint& p : now) {
      const auto it = points.find(p.id);
      if (it == points.end() || it->second.position_W != p.position_W || it->second.views != p.views) {
        return ::testing::AssertionFailure() << "point " << p.id.value << " missing or stale";
      }
    }
    return ::testing::AssertionSuccess();
  }
};

/// Replays deltas after every update; every 5 updates also replays one delta spanning the last 4
/// updates onto an older copy, as a consumer that skipped updates would. The unconfirmed points
/// are replayed the same way.
class DeltaChecker {
 public:
  explicit DeltaChecker(Mesher& mesher) : mesher_(mesher) {}

  void afterUpdate(const std::string& where) {
    ++updates_;
    const std::uint64_t before = replica_.revision;
    ASSERT_LE(mesher_.revision(), before + 1) << where << ": one revision per update at most";
    const SurfaceDelta delta = mesher_.changesSince(before);
    ASSERT_EQ(delta.to_revision, mesher_.revision());
    if (mesher_.revision() == before) {
      ASSERT_TRUE(delta.empty()) << where;
    }
    added_ += delta.added.size();
    removed_ += delta.removed.size();
    replica_.apply(mesher_, delta);
    if (::testing::Test::HasFatalFailure()) return;
    expectMatches(mesher_, replica_, where);
    unconfirmed_.follow(mesher_);
    ASSERT_TRUE(unconfirmed_.matches(mesher_)) << where << " (unconfirmed points)";
    if (updates_ % 5 == 1) {
      stale_ = replica_;
      stale_unconfirmed_ = unconfirmed_;
    }
    if (updates_ % 5 == 0) {
      const SurfaceDelta chained = mesher_.changesSince(stale_.revision);
      stale_.apply(mesher_, chained);
      if (::testing::Test::HasFatalFailure()) return;
      ASSERT_TRUE(sameFaces(stale_.faces, replica_.faces, true)) << where << " (delta over 4 updates)";
      ASSERT_TRUE(mesher_.unconfirmedChangesSince(stale_unconfirmed_.cursor).complete) << where;
      stale_unconfirmed_.follow(mesher_);
      ASSERT_TRUE(stale_unconfirmed_.matches(mesher_)) << where << " (unconfirmed points over 4 updates)";
      ++stale_checks_;
    }
  }

  std::size_t added() const { return added_; }
  std::size_t removed() const { return removed_; }
  std::size_t staleChecks() const { return stale_checks_; }

 private:
  Mesher& mesher_;
  Replica replica_;
  Replica stale_;
  UnconfirmedReplica unconfirmed_;
  UnconfirmedReplica stale_unconfirmed_;
  std::size_t updates_ = 0;
  std::size_t added_ = 0;
  std::size_t removed_ = 0;
  std::size_t stale_checks_ = 0;
};

AxisAlignedBox boundsOf(const std::vector<datasets::StreamEvent>& events) {
  AxisAlignedBox box{Eigen::Vector3d::Constant(1e300), Eigen::Vector3d::Constant(-1e300)};
  for (const datasets::StreamEvent& event : events) {
    const auto* keyframe = std::get_if<Keyframe>(&event);
    if (keyframe == nullptr) continue;
    box.min_W = box.min_W.cwiseMin(keyframe->position_W_C);
    box.max_W = box.max_W.cwiseMax(keyframe->position_W_C);
    for (const PointObservation& o : keyframe->observations) {
      box.min_W = box.min_W.cwiseMin(o.position_W);
      box.max_W = box.max_W.cwiseMax(o.position_W);
    }
  }
  return box;
}

void replayStream(const datasets::SlamStream& stream, MesherConfig config) {
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = boundsOf(stream.events);
  datasets::applyMeshingAdvice(stream, config);
  Mesher mesher(config);
  DeltaChecker checker(mesher);
  for (std::size_t i = 0; i < stream.events.size(); ++i) {
    datasets::applyEvent(mesher, stream.events[i]);
    checker.afterUpdate(std::string(toString(config.mode())) + ", event " + std::to_string(i));
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(checker.added(), 1000u) << "the stream must build a real surface";
  EXPECT_GT(checker.removed(), 100u) << "and change it";
  EXPECT_GE(checker.staleChecks(), 3u);
  EXPECT_GT(mesher.revision(), stream.events.size() / 2);
}

TEST(SurfaceDeltaTest, ReplayMatchesExtractMeshOnKitti00InEveryMode) {
  const std::filesystem::path path =
      std::string(TERRAMESH_SHARED_DIR) + "/data/kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json";
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  const datasets::SlamStream stream = datasets::readAnyStream(path);
  for (MesherMode mode : kModes) {
    MesherConfig config = MesherConfig::forMode(mode);
    config.metres_per_unit = 16.589;  // as `terramesh mesh --metres-per-unit 16.589` (docs/accuracy.md)
    replayStream(stream, config);
    if (HasFatalFailure()) return;
  }
}

TEST(SurfaceDeltaTest, ReplayMatchesExtractMeshOnASyntheticStreetInEveryMode) {
  datasets::StreetSceneConfig street;
  street.length_m = 60;
  street.seed = 3;
  const datasets::SyntheticScene scene = datasets::buildStreetScene(street);
  const datasets::TriangleBvh bvh(scene.ground_truth.mesh);
  datasets::SlamSimulationConfig slam = datasets::kittiLikeSlamConfig();
  slam.keyframe_every_frames = 1;      // 75 keyframes over 60 m
  slam.new_points_per_keyframe = 50;   // a sparser map keeps the test short
  slam.loop_closure_drift_m = 0.5;     // keyframes re-sent with corrected poses
  const datasets::SimulatedSlam simulated = datasets::simulateSlam(scene, bvh, slam);
  ASSERT_GT(simulated.stats.keyframes, 70u);
  ASSERT_GT(simulated.stats.keyframe_events, simulated.stats.keyframes);
  for (MesherMode mode : kModes) {
    replayStream(simulated.stream, MesherConfig::forMode(mode));
    if (HasFatalFailure()) return;
  }
}

MesherConfig roomConfig(MesherMode mode, const std::vector<Keyframe>& keyframes) {
  MesherConfig config = MesherConfig::forMode(mode);
  config.steiner_step_m = 4.0;  // rooms of a few metres need a finer grid than streets
  if (!config.incremental_steiner_grid) {
    std::vector<datasets::StreamEvent> events(keyframes.begin(), keyframes.end());
    config.fixed_grid_bounds_W = boundsOf(events);
  }
  return config;
}

TEST(SurfaceDeltaTest, ReplayMatchesWithMovingAndRemovedPointsAndKeyframes) {
  test::SceneOptions options;
  options.keyframes = 20;
  const test::AnalyticScene scene = test::boxRoomScene(options);
  const std::vector<Keyframe> keyframes = test::withMovingEstimates(scene.keyframes, 0.3, 5);
  for (MesherMode mode : kModes) {
    Mesher mesher(roomConfig(mode, keyframes));
    DeltaChecker checker(mesher);
    const std::string name = toString(mode);
    std::size_t removed_points = 0;
    for (std::size_t k = 0; k < keyframes.size(); ++k) {
      mesher.integrateKeyframe(keyframes[k]);
      checker.afterUpdate(name + ", keyframe " + std::to_string(k));
      if (HasFatalFailure()) return;
      if (k % 3 == 2) {
        std::vector<PointId> doomed;
        for (const PointObservation& o : keyframes[k].observations) {
          if (o.point.value % 11 == k % 11) doomed.push_back(o.point);
        }
        removed_points += mesher.removePoints(doomed).removed_points;
        checker.afterUpdate(name + ", points removed after keyframe " + std::to_string(k));
        if (HasFatalFailure()) return;
      }
      if (k == 12 || k == 15) {
        mesher.removeKeyframe(keyframes[k - 6].id);
        checker.afterUpdate(name + ", keyframe removed after keyframe " + std::to_string(k));
        if (HasFatalFailure()) return;
      }
    }
    EXPECT_GT(removed_points, 0u) << name;
    EXPECT_GT(checker.removed(), 100u) << name;
  }
}

/// A mesher over the plane scene plus a keyframe (id 1000) that observes one point or nothing,
/// so each re-send changes that point's rays: one revision per update.
struct TogglingScene {
  TogglingScene() : mesher(roomConfig(MesherMode::kProposed, {})) {
    test::SceneOptions options;
    options.keyframes = 12;
    scene = test::planeScene(options);
    for (const Keyframe& keyframe : scene.keyframes) mesher.integrateKeyframe(keyframe);
    toggle.id = KeyframeId{1000};
    toggle.position_W_C = scene.keyframes.front().position_W_C;
    toggle.rotation_W_C = scene.keyframes.front().rotation_W_C;
    seen = scene.keyframes.front().observations.front();
  }
  UpdateStats step(bool observe) {
    toggle.observations.clear();
    if (observe) toggle.observations.push_back(seen);
    return mesher.integrateKeyframe(toggle);
  }

  test::AnalyticScene scene;
  Mesher mesher;
  Keyframe toggle;
  PointObservation seen;
};

TEST(SurfaceDeltaTest, StaleFutureAndForgottenRevisions) {
  TogglingScene toggling;
  Mesher& mesher = toggling.mesher;
  const std::uint64_t start = mesher.revision();
  ASSERT_GT(start, 0u);
  EXPECT_TRUE(mesher.changesSince(start).empty());
  EXPECT_THROW(mesher.changesSince(start + 1), std::invalid_argument);

  // A toggle changes the rays of one point: it is touched.
  toggling.step(true);
  ASSERT_EQ(mesher.revision(), start + 1);
  const SurfaceDelta one = mesher.changesSince(start);
  EXPECT_TRUE(std::binary_search(one.touched_vertices.begin(), one.touched_vertices.end(),
                                 VertexKey::point(toggling.seen.point)));

  // Toggle until the copy taken now is exactly as old as the history kept.
  Replica replica;
  replica.faces = toMap(mesher.surfaceFaces());
  replica.revision = mesher.revision();
  for (std::uint64_t i = 1; i <= Mesher::kSurfaceHistoryRevisions; ++i) {
    toggling.step(i % 2 == 0);
    ASSERT_EQ(mesher.revision(), replica.revision + i) << "every toggle is a revision";
  }
  const SurfaceDelta oldest = mesher.changesSince(replica.revision);
  ASSERT_TRUE(oldest.complete);
  EXPECT_FALSE(oldest.touched_vertices.empty());
  replica.apply(mesher, oldest);
  ASSERT_FALSE(HasFatalFailure());
  expectMatches(mesher, replica, "after the toggles");

  toggling.step(false);
  const std::uint64_t now = mesher.revision();
  EXPECT_TRUE(mesher.changesSince(now - Mesher::kSurfaceHistoryRevisions).complete);
  for (std::uint64_t from : {std::uint64_t{0}, start, now - Mesher::kSurfaceHistoryRevisions - 1}) {
    const SurfaceDelta forgotten = mesher.changesSince(from);
    EXPECT_FALSE(forgotten.complete) << from;
    EXPECT_FALSE(forgotten.empty());
    EXPECT_EQ(forgotten.from_revision, from);
    EXPECT_EQ(forgotten.to_revision, now);
    EXPECT_TRUE(forgotten.removed.empty() && forgotten.added.empty() && forgotten.touched_vertices.empty());
  }
  EXPECT_THROW(mesher.changesSince(now + 1), std::invalid_argument);
}

TEST(SurfaceDeltaTest, UnconfirmedCursorsOfAnotherMesherOrTooOldAreNotAnswered) {
  TogglingScene toggling;
  Mesher& mesher = toggling.mesher;
  const UnconfirmedCursor start = mesher.unconfirmedCursor();
  EXPECT_TRUE(mesher.unconfirmedChangesSince(start).complete);
  EXPECT_FALSE(mesher.unconfirmedChangesSince(UnconfirmedCursor{}).complete) << "a default cursor is no mesher's";
  TogglingScene other;
  EXPECT_FALSE(mesher.unconfirmedChangesSince(other.mesher.unconfirmedCursor()).complete) << "another mesher's";
  UnconfirmedCursor future = start;
  ++future.revision;
  EXPECT_FALSE(mesher.unconfirmedChangesSince(future).complete);
  for (int i = 0; i < 256; ++i) toggling.step(i % 2 == 0);
  EXPECT_TRUE(mesher.unconfirmedChangesSince(start).complete) << "256 updates are kept";
  toggling.step(true);
  const UnconfirmedChanges forgotten = mesher.unconfirmedChangesSince(start);
  EXPECT_FALSE(forgotten.complete) << "257 are not";
  EXPECT_TRUE(forgotten.waiting.empty() && forgotten.gone.empty());
  EXPECT_TRUE(mesher.unconfirmedChangesSince(forgotten.cursor).complete);
}

TEST(SurfaceDeltaTest, RaysCountStoredRaysAtTheVerticesAndCrossingsInFrontAndBehind) {
  test::SceneOptions options;
  options.keyframes = 16;
  const test::AnalyticScene scene = test::corridorScene(options);
  const MesherConfig config = roomConfig(MesherMode::kProposed, scene.keyframes);
  Mesher mesher(config);
  for (const Keyframe& keyframe : scene.keyframes) mesher.integrateKeyframe(keyframe);

  // Brute force: a point has one stored ray per keyframe observing it within range.
  std::map<std::uint64_t, std::uint32_t> rays_at;
  std::map<std::uint64_t, Eigen::Vector3d> position_of;
  for (const Keyframe& keyframe : scene.keyframes) {
    for (const PointObservation& o : keyframe.observations) {
      const double distance = (o.position_W - keyframe.position_W_C).norm();
      if (distance > 0 && distance <= config.maxCameraDistanceUnits()) ++rays_at[o.point.value];
      position_of[o.point.value] = o.position_W;
    }
  }
  // Crossings of the O-cell on each facet, found by the facet's corner positions.
  using Corners = std::array<double, 9>;
  auto corners = [](std::array<Eigen::Vector3d, 3> p) {
    std::sort(p.begin(), p.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    Corners c{};
    for (std::size_t i = 0; i < 9; ++i) c[i] = p[i / 3][static_cast<Eigen::Index>(i % 3)];
    return c;
  };
  // ... and of the cell behind it, with that cell's fourth vertex.
  std::map<Corners, std::uint32_t> crossings_in_front;
  std::map<Corners, std::pair<std::uint32_t, Eigen::Vector3d>> behind;
  for (const CellVisibility& cell : mesher.cellVisibility()) {
    for (std::size_t skip = 0; skip < 4; ++skip) {
      std::array<Eigen::Vector3d, 3> facet;
      for (std::size_t i = 0, n = 0; i < 4; ++i) {
        if (i != skip) facet[n++] = cell.vertices_W[i];
      }
      // Only surface facets are looked up.
      if (cell.outside) {
        crossings_in_front[corners(facet)] += cell.crossings;
      } else {
        behind[corners(facet)] = {cell.crossings, cell.vertices_W[skip]};
      }
    }
  }

  const std::vector<SurfaceFace> faces = mesher.surfaceFaces();
  ASSERT_GT(faces.size(), 200u);
  std::size_t steiner_faces = 0, observed_faces = 0, faces_with_rays_behind = 0;
  for (const SurfaceFace& face : faces) {
    std::uint32_t expected = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      const VertexKey& v = face.vertices[k];
      if (v.steiner) continue;
      ASSERT_TRUE(position_of.count(v.value)) << describe(v);
      EXPECT_EQ(face.positions_W[k], position_of[v.value]) << describe(v);
      expected += rays_at[v.value];
    }
    const auto front = crossings_in_front.find(corners(face.positions_W));
    ASSERT_TRUE(front != crossings_in_front.end()) << describe(face.key);
    expected += front->second;
    EXPECT_EQ(face.rays, expected) << describe(face.key);
    const auto back = behind.find(corners(face.positions_W));
    const std::uint32_t back_crossings = back == behind.end() ? 0 : back->second.first;  // none: infinite
    EXPECT_EQ(face.back_crossings, back_crossings) << describe(face.key);
    if (back_crossings > 0) {
      const Eigen::Vector3d& a = face.positions_W[0];
      const Eigen::Vector3d n = (face.positions_W[1] - a).cross(face.positions_W[2] - a).normalized();
      EXPECT_NEAR(face.back_depth, std::abs(n.dot(back->second.second - a)), 1e-12) << describe(face.key);
      ++faces_with_rays_behind;
    } else {
      EXPECT_EQ(face.back_depth, 0.0) << describe(face.key);
    }
    const bool steiner = std::any_of(face.vertices.begin(), face.vertices.end(),
                                     [](const VertexKey& v) { return v.steiner; });
    EXPECT_EQ(face.touches_steiner, steiner);
    steiner_faces += steiner;
    observed_faces += face.rays > 0;
  }
  EXPECT_GT(observed_faces, faces.size() / 2);
  EXPECT_LT(steiner_faces, faces.size());
  EXPECT_GT(faces_with_rays_behind, 0u) << "the check above must see some";

  // The Steiner flags agree with extractMesh, face by face.
  const FaceMap extracted = facesOfMesh(mesher.extractMesh());
  EXPECT_TRUE(sameFaces(toMap(faces), extracted, false));
}

TEST(SurfaceDeltaTest, FaceKeysIgnoreVertexOrder) {
  const VertexKey a = VertexKey::point(PointId{7});
  const VertexKey b = VertexKey::steinerNode(-3, 0, 5);
  const VertexKey c = VertexKey::point(PointId{2});
  const FaceKey key = FaceKey::of(a, b, c);
  EXPECT_EQ(key, FaceKey::of(b, c, a));
  EXPECT_EQ(key, FaceKey::of(c, a, b));
  EXPECT_EQ(key.sorted[0], c);
  EXPECT_EQ(key.sorted[1], a);
  EXPECT_EQ(key.sorted[2], b);  // points before Steiner nodes
  EXPECT_NE(VertexKey::steinerNode(1, 0, 0), VertexKey::steinerNode(0, 1, 0));
  EXPECT_NE(VertexKey::steinerNode(0, 0, 0), VertexKey::point(PointId{VertexKey::steinerNode(0, 0, 0).value}));
}

}  // namespace
}  // namespace terramesh::mesher
