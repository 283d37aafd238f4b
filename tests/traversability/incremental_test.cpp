// Oracle tests: after any sequence of apply(), the layers equal reset() on the same surface,
// bit for bit. Deltas come from random edits of a hand-made surface and from the mesher
// (Mesher::changesSince) while it meshes analytic scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "mesher/mesher.h"
#include "test_support/traversability_scenes.h"
#include "traversability/layer_registry.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

using mesher::FaceKey;
using mesher::SurfaceFace;
using FaceMap = std::map<FaceKey, SurfaceFace>;

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

/// Every registry layer of every face equal (NaN equal to NaN), and the class and Steiner flag;
/// reports the first difference.
::testing::AssertionResult sameLayers(const LayeredMesh& a, const LayeredMesh& b) {
  if (a.face_keys != b.face_keys) return ::testing::AssertionFailure() << "different faces";
  for (std::size_t f = 0; f < a.layers.size(); ++f) {
    const FaceLayers& x = a.layers[f];
    const FaceLayers& y = b.layers[f];
    if (x.face_class != y.face_class || x.steiner != y.steiner) {
      return ::testing::AssertionFailure() << "face " << f << " of " << a.layers.size() << ": class "
                                           << int(x.face_class) << "/" << int(y.face_class) << " steiner "
                                           << x.steiner << "/" << y.steiner;
    }
    for (const LayerInfo& layer : faceLayerRegistry()) {
      const double u = layer.get(x), v = layer.get(y);
      if (!((std::isnan(u) && std::isnan(v)) || u == v)) {
        return ::testing::AssertionFailure() << "face " << f << " of " << a.layers.size() << ": " << layer.name
                                             << " " << u << "/" << v;
      }
    }
  }
  return ::testing::AssertionSuccess();
}

std::vector<SurfaceFace> facesOf(const FaceMap& map) {
  std::vector<SurfaceFace> faces;
  for (const auto& [key, face] : map) faces.push_back(face);
  return faces;
}

/// A height-field surface whose vertex heights and face ray counts the test edits.
class EditableSurface {
 public:
  EditableSurface() : mesh_(test::heightFieldMesh(-5, 5, -5, 5, 0.25, [](double, double) { return 0.0; })) {
    for (std::size_t f = 0; f < mesh_.faces.size(); ++f) rays_.push_back(10);
    crossings_.assign(mesh_.faces.size(), 4);
    sides_.assign(mesh_.faces.size(), mesher::view_side::kFront);
    back_.assign(mesh_.faces.size(), 0);
    depth_.assign(mesh_.faces.size(), 0.0);
    present_.assign(mesh_.faces.size(), true);
  }

  FaceMap faces() const {
    FaceMap map;
    for (std::size_t f = 0; f < mesh_.faces.size(); ++f) {
      if (present_[f]) map.emplace(keyOf(f), face(f));
    }
    return map;
  }

  /// One random edit: raise or lower the vertices in a disc (a bump, a pit, a block), cut or
  /// restore a patch, or change the ray counts of a patch (whether rays cross the space in front
  /// of its faces and behind them, and which side of them the cameras saw). Returns the delta
  /// from before.
  mesher::SurfaceDelta edit(std::mt19937& rng) {
    std::uniform_real_distribution<double> coord(-5, 5), unit(0, 1);
    const Eigen::Vector2d centre(coord(rng), coord(rng));
    const double radius = 0.3 + 1.2 * unit(rng);
    const int kind = static_cast<int>(rng() % 3);
    mesher::SurfaceDelta delta;
    std::vector<bool> hit(mesh_.faces.size(), false);
    const double dz = unit(rng) < 0.5 ? 0.6 * unit(rng) : -0.3 * unit(rng);
    std::vector<bool> moved(mesh_.vertices.size(), false);
    for (std::size_t v = 0; v < mesh_.vertices.size(); ++v) {
      if ((mesh_.vertices[v].head<2>() - centre).norm() < radius) moved[v] = true;
    }
    for (std::size_t f = 0; f < mesh_.faces.size(); ++f) {
      for (std::uint32_t v : mesh_.faces[f]) hit[f] = hit[f] || moved[v];
    }
    if (kind == 0) {
      for (std::size_t v = 0; v < moved.size(); ++v) {
        if (moved[v]) mesh_.vertices[v].z() += dz;
      }
    }
    for (std::size_t f = 0; f < mesh_.faces.size(); ++f) {
      if (!hit[f]) continue;
      if (present_[f]) delta.removed.push_back(keyOf(f));
      if (kind == 1) present_[f] = !present_[f];
      if (kind == 2) {
        rays_[f] = static_cast<std::uint32_t>(rng() % 6);
        crossings_[f] = std::min(rays_[f], static_cast<std::uint32_t>(rng() % 3));
        sides_[f] = static_cast<std::uint8_t>(rng() % 4);
        back_[f] = static_cast<std::uint32_t>(rng() % 5);
        depth_[f] = back_[f] > 0 ? 0.5 * unit(rng) : 0.0;
      }
      if (present_[f]) delta.added.push_back(face(f));
    }
    return delta;
  }

 private:
  FaceKey keyOf(std::size_t f) const {
    const auto& t = mesh_.faces[f];
    return FaceKey::of(mesher::VertexKey{t[0], false}, mesher::VertexKey{t[1], false}, mesher::VertexKey{t[2], false});
  }
  SurfaceFace face(std::size_t f) const {
    SurfaceFace face;
    for (int i = 0; i < 3; ++i) {
      face.vertices[i] = mesher::VertexKey{mesh_.faces[f][i], false};
      face.positions_W[i] = mesh_.vertices[mesh_.faces[f][i]];
    }
    face.key = keyOf(f);
    face.rays = rays_[f];
    face.front_crossings = crossings_[f];
    face.view_sides = sides_[f];
    face.back_crossings = back_[f];
    face.back_depth = depth_[f];
    return face;
  }

  mesher::TriangleMesh mesh_;
  std::vector<std::uint32_t> rays_, crossings_, back_;
  std::vector<double> depth_;
  std::vector<std::uint8_t> sides_;
  std::vector<bool> present_;
};

TEST(IncrementalTest, RandomEditsEqualFullRecomputation) {
  for (const char* robot : {"small_wheeled", "legged"}) {
    const RobotProfile profile = loadRobotProfile(kRobots / (std::string(robot) + ".yaml"));
    EditableSurface surface;
    TraversabilityMap map(profile, MapFrame{});
    map.reset(facesOf(surface.faces()));
    std::mt19937 rng(11);
    std::size_t lethal_seen = 0, unknown_seen = 0, uncertain_seen = 0, interpolated_seen = 0, behind_seen = 0;
    for (int step = 0; step < 25; ++step) {
      const LayerUpdateStats stats = map.apply(surface.edit(rng), {});
      EXPECT_LE(stats.faces_recomputed, stats.faces_total);
      TraversabilityMap fresh(profile, MapFrame{});
      fresh.reset(facesOf(surface.faces()));
      const LayeredMesh expected = fresh.snapshot();
      ASSERT_TRUE(sameLayers(map.snapshot(), expected)) << robot << " after edit " << step;
      for (const FaceLayers& l : expected.layers) {
        lethal_seen += l.face_class == FaceClass::kLethal;
        unknown_seen += l.face_class == FaceClass::kUnknown;
        uncertain_seen += l.face_class == FaceClass::kUncertain;
        interpolated_seen += l.face_class != FaceClass::kUnknown && l.evidence == Evidence::kInterpolated;
        behind_seen += (l.reasons & reason::kSeenFromBehind) != 0;
      }
    }
    EXPECT_GT(lethal_seen, 0u) << "the edits must create lethal faces for the test to mean anything";
    EXPECT_GT(unknown_seen, 0u);
    EXPECT_GT(uncertain_seen, 0u);
    EXPECT_GT(interpolated_seen, 0u);
    EXPECT_GT(behind_seen, 0u);
  }
}

TEST(IncrementalTest, FacesReaddedWithTheSameGeometryAreNotChanges) {
  const RobotProfile profile = loadRobotProfile(kRobots / "small_wheeled.yaml");
  EditableSurface surface;
  FaceMap faces = surface.faces();
  TraversabilityMap map(profile, MapFrame{});
  map.reset(facesOf(faces));
  const auto expectEqualsFull = [&](const char* what) {
    TraversabilityMap fresh(profile, MapFrame{});
    fresh.reset(facesOf(faces));
    EXPECT_TRUE(sameLayers(map.snapshot(), fresh.snapshot())) << what;
  };
  // Every face removed and re-added unchanged (mesher churn): nothing to recompute.
  mesher::SurfaceDelta churn;
  for (const auto& [key, face] : faces) {
    churn.removed.push_back(key);
    churn.added.push_back(face);
  }
  LayerUpdateStats stats = map.apply(churn, {});
  EXPECT_EQ(stats.faces_readded_unchanged, faces.size());
  EXPECT_EQ(stats.faces_recomputed, 0u);
  EXPECT_EQ(stats.faces_total, faces.size());
  expectEqualsFull("after churn");

  // Re-added with a new observation count only: the face is re-judged (now unknown), its
  // neighbours' local layers are not recomputed.
  SurfaceFace& first = faces.begin()->second;
  first.rays = 0;
  stats = map.apply(mesher::SurfaceDelta{0, 0, true, {first.key}, {first}, {}}, {});
  EXPECT_EQ(stats.faces_readded_unchanged, 1u);
  EXPECT_GE(stats.faces_recomputed, 1u);
  expectEqualsFull("after a ray count change");
  EXPECT_EQ(map.snapshot().layers.front().face_class, FaceClass::kUnknown);

  // Re-added with the same rays but none crossing the space in front of it any more: the face's
  // evidence becomes interpolated, which the faces standing on it must see too.
  SurfaceFace& second = std::next(faces.begin(), 40)->second;
  ASSERT_GT(second.front_crossings, 0u);
  second.front_crossings = 0;
  stats = map.apply(mesher::SurfaceDelta{0, 0, true, {second.key}, {second}, {}}, {});
  EXPECT_EQ(stats.faces_readded_unchanged, 1u);
  EXPECT_GT(stats.faces_recomputed, 1u);
  expectEqualsFull("after the crossings vanished");
  // ... and back, reported through the faces around touched vertices instead.
  second.front_crossings = 3;
  stats = map.apply(mesher::SurfaceDelta{0, 0, true, {}, {}, {}}, {second});
  EXPECT_GT(stats.faces_recomputed, 1u);
  expectEqualsFull("after the crossings came back");

  // Re-added seen only from behind: uncertain, as a full computation says; and back, through the
  // faces around touched vertices.
  SurfaceFace& third = std::next(faces.begin(), 80)->second;
  ASSERT_EQ(third.view_sides, mesher::view_side::kFront);
  third.view_sides = mesher::view_side::kBehind;
  stats = map.apply(mesher::SurfaceDelta{0, 0, true, {third.key}, {third}, {}}, {});
  EXPECT_EQ(stats.faces_readded_unchanged, 1u);
  expectEqualsFull("after the views went behind");
  const auto layersOfThird = [&] {
    const LayeredMesh now = map.snapshot();
    const auto at = std::find(now.face_keys.begin(), now.face_keys.end(), third.key);
    EXPECT_NE(at, now.face_keys.end());
    return now.layers.at(static_cast<std::size_t>(at - now.face_keys.begin()));
  };
  EXPECT_EQ(layersOfThird().face_class, FaceClass::kUncertain);
  EXPECT_TRUE(layersOfThird().reasons & reason::kSeenFromBehind);
  third.view_sides = mesher::view_side::kFront | mesher::view_side::kBehind;
  map.apply(mesher::SurfaceDelta{0, 0, true, {}, {}, {}}, {third});
  expectEqualsFull("after a view from in front");
  EXPECT_EQ(layersOfThird().face_class, FaceClass::kFree);

  // Rays seen under it, 0.4 m deep (a lid): uncertain; and gone again, through the faces around
  // touched vertices.
  third.back_crossings = static_cast<std::uint32_t>(profile.min_rays);
  third.back_depth = 0.4;
  map.apply(mesher::SurfaceDelta{0, 0, true, {}, {}, {}}, {third});
  expectEqualsFull("after rays behind it");
  EXPECT_EQ(layersOfThird().face_class, FaceClass::kUncertain);
  EXPECT_EQ(layersOfThird().evidence, Evidence::kInterpolated);
  third.back_crossings = 0;
  third.back_depth = 0;
  map.apply(mesher::SurfaceDelta{0, 0, true, {}, {}, {}}, {third});
  expectEqualsFull("after the rays behind it were gone");
  EXPECT_EQ(layersOfThird().face_class, FaceClass::kFree);

  // The same key with a vertex moved by a nanometre is a real change.
  SurfaceFace& last = faces.rbegin()->second;
  last.positions_W[0].z() += 1e-9;
  stats = map.apply(mesher::SurfaceDelta{0, 0, true, {last.key}, {last}, {}}, {});
  EXPECT_EQ(stats.faces_readded_unchanged, 0u);
  EXPECT_GT(stats.faces_recomputed, 1u);
  expectEqualsFull("after a vertex moved");
}

TEST(IncrementalTest, CeilingMovingOverAFloorEqualsFullRecomputation) {
  // Multi-level: an upper floor over the lower one; edits below must not disturb the upper floor
  // beyond what a full recomputation gives.
  RobotProfile profile = loadRobotProfile(kRobots / "small_wheeled.yaml");
  mesher::TriangleMesh lower = test::heightFieldMesh(-3, 3, -3, 3, 0.25, [](double, double) { return 0.0; });
  test::appendMesh(lower, test::horizontalQuad(-1, 1, -1, 1, 0.45, true));
  std::vector<SurfaceFace> faces;
  for (std::size_t f = 0; f < lower.faces.size(); ++f) {
    SurfaceFace face;
    for (int i = 0; i < 3; ++i) {
      face.vertices[i] = mesher::VertexKey{lower.faces[f][i], false};
      face.positions_W[i] = lower.vertices[lower.faces[f][i]];
    }
    face.key = FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    face.rays = 5;
    face.front_crossings = 5;
    faces.push_back(face);
  }
  TraversabilityMap map(profile, MapFrame{});
  map.reset(faces);
  // Raise the ceiling above the robot: the faces under it become free, then lower it again.
  for (const double z : {0.8, 0.45, 0.3}) {
    mesher::SurfaceDelta delta;
    for (SurfaceFace& face : faces) {
      if (face.positions_W[0].z() < 0.01) continue;
      delta.removed.push_back(face.key);
      for (auto& p : face.positions_W) p.z() = z;
      delta.added.push_back(face);
    }
    map.apply(delta, {});
    TraversabilityMap fresh(profile, MapFrame{});
    fresh.reset(faces);
    ASSERT_TRUE(sameLayers(map.snapshot(), fresh.snapshot())) << "ceiling at " << z;
  }
}

TEST(IncrementalTest, ChangesOutsideAFacesHeightWindowDoNotRecomputeIt) {
  // Two floors 8 m apart (beyond the clearance search and every height band): a bump on the upper
  // floor recomputes only upper faces, and the map still equals a full recomputation. A map that
  // recomputed every face within the footprint's horizontal reach would recompute lower faces too.
  const RobotProfile profile = loadRobotProfile(kRobots / "small_wheeled.yaml");
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.25, [](double, double) { return 0.0; });
  const std::size_t lower_faces = mesh.faces.size();
  test::appendMesh(mesh, test::heightFieldMesh(-3, 3, -3, 3, 0.25, [](double, double) { return 8.0; }));
  const std::size_t upper_faces = mesh.faces.size() - lower_faces;
  const auto faceOf = [&](std::size_t f) {
    SurfaceFace face;
    for (int i = 0; i < 3; ++i) {
      face.vertices[i] = mesher::VertexKey{mesh.faces[f][i], false};
      face.positions_W[i] = mesh.vertices[mesh.faces[f][i]];
    }
    face.key = FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    face.rays = 5;
    face.front_crossings = 5;
    return face;
  };
  std::vector<SurfaceFace> faces;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) faces.push_back(faceOf(f));
  TraversabilityMap map(profile, MapFrame{});
  map.reset(faces);
  TraversabilityMap upper_only(profile, MapFrame{});
  upper_only.reset(std::vector<SurfaceFace>(faces.begin() + static_cast<std::ptrdiff_t>(lower_faces), faces.end()));
  mesher::SurfaceDelta delta;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (mesh.vertices[v].z() > 4.0 && mesh.vertices[v].head<2>().norm() < 1.0) mesh.vertices[v].z() += 0.3;
  }
  for (std::size_t f = lower_faces; f < mesh.faces.size(); ++f) {
    const SurfaceFace face = faceOf(f);
    if (face.positions_W == faces[f].positions_W) continue;
    delta.removed.push_back(face.key);
    delta.added.push_back(face);
    faces[f] = face;
  }
  ASSERT_FALSE(delta.added.empty());
  const LayerUpdateStats stats = map.apply(delta, {});
  const LayerUpdateStats upper_stats = upper_only.apply(delta, {});
  EXPECT_GT(upper_stats.faces_recomputed, delta.added.size());
  EXPECT_LE(upper_stats.faces_recomputed, upper_faces);
  EXPECT_EQ(stats.faces_recomputed, upper_stats.faces_recomputed) << "lower faces were recomputed";
  TraversabilityMap fresh(profile, MapFrame{});
  fresh.reset(faces);
  const LayeredMesh expected = fresh.snapshot();
  EXPECT_TRUE(sameLayers(map.snapshot(), expected));
  std::size_t lethal = 0;
  for (const FaceLayers& l : expected.layers) lethal += l.face_class == FaceClass::kLethal;
  EXPECT_GT(lethal, 0u) << "the bump's rim must be lethal for the inflation to be exercised";
}

/// The faces of `mesh` with vertex keys first_vertex + index (Steiner keys if `steiner`).
std::vector<SurfaceFace> surfaceFaces(const mesher::TriangleMesh& mesh, std::uint32_t first_vertex, bool steiner) {
  std::vector<SurfaceFace> faces;
  for (const auto& t : mesh.faces) {
    SurfaceFace face;
    for (int i = 0; i < 3; ++i) {
      face.vertices[i] = mesher::VertexKey{first_vertex + t[i], steiner};
      face.positions_W[i] = mesh.vertices[t[i]];
    }
    face.key = FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    face.touches_steiner = steiner;
    face.rays = steiner ? 0 : 5;
    face.front_crossings = face.rays;
    faces.push_back(face);
  }
  return faces;
}

TEST(IncrementalTest, WallsAppearingMovingAndVanishingEqualFullRecomputation) {
  // Vertical walls (faces heightAt cannot sample, never ground) are obstacles inside the footprint
  // of the floor faces around them: adding, moving, lowering and removing one must recompute
  // exactly the floor faces whose footprint it enters or leaves. A Steiner wall is no obstacle.
  // On the 1.5 m grid every floor face is larger than both footprints and judged at several points
  // (up to the footprint's radius from its centroid): the walls reach farther.
  for (const double spacing : {0.25, 1.5}) {
    for (const char* robot : {"small_wheeled", "legged"}) {
      const bool fine = spacing < 1;
      const RobotProfile profile = loadRobotProfile(kRobots / (std::string(robot) + ".yaml"));
      FaceMap faces;
      const double half = fine ? 3 : 6;
      for (const SurfaceFace& f :
           surfaceFaces(test::heightFieldMesh(-half, half, -half, half, spacing, [](double, double) { return 0.0; }), 0,
                        false)) {
        faces.emplace(f.key, f);
      }
      TraversabilityMap map(profile, MapFrame{});
      map.reset(facesOf(faces));
      // Each step replaces the faces of wall `id` (keys from vertex 100000 + 100 id) by `mesh`.
      std::map<int, std::vector<FaceKey>> walls;
      const auto setWall = [&](int id, const mesher::TriangleMesh& mesh, bool steiner) {
        mesher::SurfaceDelta delta;
        delta.complete = true;
        for (const FaceKey& key : walls[id]) {
          delta.removed.push_back(key);
          faces.erase(key);
        }
        walls[id].clear();
        for (const SurfaceFace& f : surfaceFaces(mesh, 100000 + 100 * static_cast<std::uint32_t>(id), steiner)) {
          delta.added.push_back(f);
          faces.emplace(f.key, f);
          walls[id].push_back(f.key);
        }
        return map.apply(delta, {});
      };
      const auto expectEqualsFull = [&](const std::string& what) {
        TraversabilityMap fresh(profile, MapFrame{});
        fresh.reset(facesOf(faces));
        const LayeredMesh expected = fresh.snapshot();
        EXPECT_TRUE(sameLayers(map.snapshot(), expected)) << robot << ": " << what;
        std::size_t lethal_floor = 0;
        for (std::size_t f = 0; f < expected.layers.size(); ++f) {
          const auto& t = expected.mesh.faces[f];
          const bool floor = expected.mesh.vertices[t[0]].z() == 0 && expected.mesh.vertices[t[1]].z() == 0 &&
                             expected.mesh.vertices[t[2]].z() == 0;
          lethal_floor += floor && expected.layers[f].face_class == FaceClass::kLethal;
        }
        return lethal_floor;
      };
      // The floor's own border is lethal (the footprint hangs over the end): count relative to it.
      const std::size_t border = expectEqualsFull("bare floor");
      setWall(0, test::thinWall(0.1, -1, 0.1, 1, 0, 1.0), false);
      const std::size_t with_wall = expectEqualsFull("wall added");
      if (fine) {
        EXPECT_GT(with_wall, border) << robot << ": the floor beside the wall is lethal";
      }
      setWall(1, test::thinWall(-1.3, -1, -1.3, 1, 0, 1.0), true);
      expectEqualsFull("Steiner wall added");
      setWall(0, test::thinWall(0.6, -1.2, 0.9, 1, 0, 1.0), false);
      expectEqualsFull("wall moved");
      setWall(0, test::thinWall(0.6, -1.2, 0.9, 1, 0, 0.1), false);
      EXPECT_EQ(expectEqualsFull("wall lowered below max_step"), border) << robot;
      setWall(1, test::thinWall(-1.3, -1, -1.3, 1, 0, 1.0), false);
      const std::size_t measured = expectEqualsFull("Steiner wall measured");
      if (fine) {
        EXPECT_GT(measured, border) << robot;
      }
      // A wall between one and two radii from a large face blocked at its centroid by another
      // changes how many of its points collide (on the coarse grid, small_wheeled: the faces with
      // centroids at x = 1 collide with the first wall at 4 of their 9 points, free; with both at
      // all 9, lethal).
      setWall(0, test::thinWall(0.7, -2, 0.7, 2, 0, 1.0), false);
      expectEqualsFull("wall 0.3 m from centroids");
      setWall(2, test::thinWall(1.5, -2, 1.5, 2, 0, 1.0), false);
      expectEqualsFull("second wall 0.5 m from them");
      setWall(2, mesher::TriangleMesh{}, false);
      expectEqualsFull("second wall removed");
      setWall(2, mesher::TriangleMesh{}, false);
      setWall(1, mesher::TriangleMesh{}, false);
      setWall(0, mesher::TriangleMesh{}, false);
      EXPECT_EQ(expectEqualsFull("walls removed"), border) << robot;
    }
  }
}

/// The scene's keyframes, then the same poses again in reverse order as new keyframes (a drive back
/// over the same ground): the second pass re-observes the surface, so new rays end on existing
/// vertices and cross the free cells in front of existing faces, changing the observation count of
/// faces that stay in place.
std::vector<mesher::Keyframe> thereAndBack(const std::vector<mesher::Keyframe>& keyframes) {
  std::vector<mesher::Keyframe> out = keyframes;
  std::uint64_t next_id = 0;
  for (const mesher::Keyframe& k : keyframes) next_id = std::max<std::uint64_t>(next_id, k.id.value + 1);
  for (auto it = keyframes.rbegin(); it != keyframes.rend(); ++it) {
    mesher::Keyframe back = *it;
    back.id.value = next_id++;
    out.push_back(back);
  }
  return out;
}

/// Meshes the keyframes one by one, brings the map up to date with TraversabilityMap::update (what
/// `terramesh mesh --robot` does) and compares every layer of every face, `rays` included, with a
/// full recomputation from the mesher's current faces after every keyframe. update() rebuilds
/// exactly when the delta replaces at least half of the map's faces; `rebuilds` counts those.
void streamScene(const std::vector<mesher::Keyframe>& keyframes, const RobotProfile& profile,
                 std::size_t* rebuilds_out = nullptr) {
  mesher::MesherConfig config;
  config.steiner_step_m = 4.0;
  mesher::Mesher mesher(config);
  TraversabilityMap map(profile, MapFrame{});
  std::uint64_t revision = mesher.revision();
  std::size_t updates = 0, known = 0, reobserved = 0, rebuilds = 0;
  for (const mesher::Keyframe& keyframe : keyframes) {
    mesher.integrateKeyframe(keyframe);
    const mesher::SurfaceDelta delta = mesher.changesSince(revision);
    const std::size_t before = map.faceCount();
    const bool large = before > 0 && 2 * (delta.added.size() + delta.removed.size()) >= before;
    const LayerUpdateStats stats = map.update(mesher, revision);
    EXPECT_EQ(stats.full_rebuild, large) << "keyframe " << keyframe.id.value << ": " << delta.added.size()
                                         << " added, " << delta.removed.size() << " removed of " << before;
    rebuilds += stats.full_rebuild ? 1 : 0;
    revision = mesher.revision();
    reobserved += stats.faces_reobserved;
    ++updates;
    // From scratch with the same unconfirmed points (update() reads them from the mesher).
    TraversabilityMap fresh(profile, MapFrame{});
    fresh.setUnconfirmedPoints(mesher.unconfirmedPoints());
    fresh.reset(mesher.surfaceFaces());
    const LayeredMesh expected = fresh.snapshot();
    ASSERT_TRUE(sameLayers(map.snapshot(), expected)) << "after keyframe " << keyframe.id.value;
    known = 0;
    for (const FaceLayers& l : expected.layers) known += l.face_class != FaceClass::kUnknown;
  }
  EXPECT_GT(known, 20u) << "the scene must produce measured faces";
  EXPECT_EQ(updates, keyframes.size());
  // Faces whose count changed while they stayed in place: without their fresh counts the `rays`
  // layer (and the known/unknown class that depends on it) would go stale.
  EXPECT_GT(reobserved, 0u) << "the stream must re-observe faces for the test to mean anything";
  // Most updates must take the incremental path for the comparison to test it.
  EXPECT_LT(2 * rebuilds, updates);
  if (rebuilds_out) *rebuilds_out = rebuilds;
}

TEST(IncrementalTest, MesherDeltasOnACurbEqualFullRecomputation) {
  test::SceneOptions options;
  options.keyframes = 12;
  options.density_per_m2 = 3.0;
  streamScene(test::stepScene(0.15, options).keyframes, loadRobotProfile(kRobots / "small_wheeled.yaml"));
}

TEST(IncrementalTest, MesherDeltasUnderALowCeilingEqualFullRecomputation) {
  test::SceneOptions options;
  options.keyframes = 12;
  options.density_per_m2 = 3.0;
  streamScene(test::lowCeilingScene(0.8, options).keyframes, loadRobotProfile(kRobots / "legged.yaml"));
}

TEST(IncrementalTest, RevisitedCurbEqualsFullRecomputationRaysIncluded) {
  // The regression of `rays` going stale in `terramesh mesh --robot` (the checkpoint/resume
  // comparison found 457 of 2714 faces differing from a full recomputation).
  test::SceneOptions options;
  options.keyframes = 8;
  options.density_per_m2 = 3.0;
  streamScene(thereAndBack(test::stepScene(0.15, options).keyframes), loadRobotProfile(kRobots / "small_wheeled.yaml"));
}

TEST(IncrementalTest, AKeyframeReplacingHalfTheMapRebuildsItAndEqualsFullRecomputation) {
  // A sparse first look at the curb (a tenth of the first keyframe's points), then the stream as
  // it was: the second keyframe fills the same ground in, redrawing most of the surface (as each
  // LiDAR scan redraws the map around it), and update() rebuilds rather than re-judging nearly
  // every footprint one change at a time.
  test::SceneOptions options;
  options.keyframes = 12;
  options.density_per_m2 = 3.0;
  std::vector<mesher::Keyframe> keyframes = test::stepScene(0.15, options).keyframes;
  mesher::Keyframe sparse = keyframes.front();
  sparse.id.value = 1000;
  sparse.observations.clear();
  for (std::size_t i = 0; i < keyframes.front().observations.size(); i += 10) {
    sparse.observations.push_back(keyframes.front().observations[i]);
  }
  keyframes.insert(keyframes.begin(), sparse);
  std::size_t rebuilds = 0;
  streamScene(keyframes, loadRobotProfile(kRobots / "small_wheeled.yaml"), &rebuilds);
  EXPECT_GE(rebuilds, 1u);
}

TEST(IncrementalTest, IncompleteDeltaIsRejected) {
  TraversabilityMap map(RobotProfile{}, MapFrame{});
  mesher::SurfaceDelta delta;
  delta.complete = false;
  EXPECT_THROW(map.apply(delta, {}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::traversability
