// Faces the 2-manifold keeps over space that rays saw as free. A level one is a lid (over a pit
// whose rim and floor are both on the surface): neither it nor the faces around its vertices,
// under which the same void may reach, is free ground. A steep one is no measured wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <vector>

#include "evidence_faces.h"
#include "test_support/traversability_scenes.h"
#include "traversability/layer_registry.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

TEST(EvidenceTest, ALidThatRaysSawUnderIsNeverFree) {
  // A dense floor at 0; over the square |x - 1| < 0.5, |y| < 0.5 rays crossed the cell behind
  // the faces, 0.4 m deep (a pit whose rim and floor are both on the surface, closed by a lid the
  // 2-manifold keeps). The lid is no measured ground: a 0.4 m drop (limit 0.18 m) may lie under
  // it, so it and every footprint that reaches it are uncertain; farther away the floor is free.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const auto lid = [&](std::size_t f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    return std::abs(c.x() - 1) < 0.5 && std::abs(c.y()) < 0.5;
  };
  const auto withRaysBehind = [&](std::uint32_t crossings) {
    std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!lid(f)) continue;
      faces[f].back_crossings = crossings;
      faces[f].back_depth = 0.4;
    }
    return layersOf(faces, profile);
  };
  const std::vector<FaceLayers> layers = withRaysBehind(static_cast<std::uint32_t>(profile.min_rays));
  std::size_t lids = 0, near = 0, far = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    const double outside = std::max(std::abs(c.x() - 1), std::abs(c.y())) - 0.5;  // to the lid's edge
    if (lid(f)) {
      ++lids;
      EXPECT_EQ(layers[f].evidence, Evidence::kInterpolated);
      EXPECT_GE(layers[f].height_uncertainty_m, 0.4f);
      EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain);
    } else if (outside < r - 0.1 && std::abs(c.y()) < 0.4) {
      ++near;
      EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << "at " << c.transpose();
      EXPECT_TRUE(layers[f].reasons & reason::kWorstCaseRelief) << layers[f].reasons;
    } else if (outside > r + 0.1 && std::abs(c.x()) < 2.5 && std::abs(c.y()) < 2.5) {
      ++far;
      EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "at " << c.transpose();
    }
  }
  EXPECT_GT(lids, 150u);
  EXPECT_GT(near, 50u);
  EXPECT_GT(far, 500u);
  // Fewer rays behind than the profile trusts (a point's noise): measured, and free.
  const std::vector<FaceLayers> noise = withRaysBehind(static_cast<std::uint32_t>(profile.min_rays - 1));
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!lid(f)) continue;
    EXPECT_EQ(noise[f].evidence, Evidence::kMeasured);
    EXPECT_EQ(noise[f].face_class, FaceClass::kFree);
  }
}

/// Horizontal distance from p to triangle f of mesh (0 inside it).
double distanceToFace(const mesher::TriangleMesh& mesh, std::size_t f, const Eigen::Vector2d& p) {
  std::array<Eigen::Vector2d, 3> v;
  for (int k = 0; k < 3; ++k) v[static_cast<std::size_t>(k)] = mesh.vertices[mesh.faces[f][static_cast<std::size_t>(k)]].head<2>();
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  bool positive = true, negative = true;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector2d& a = v[k];
    const Eigen::Vector2d e = v[(k + 1) % 3] - a;
    const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * e - p).norm());
    const double side = cross(e, p - a);
    positive = positive && side >= 0;
    negative = negative && side <= 0;
  }
  return positive || negative ? 0.0 : best;
}

TEST(EvidenceTest, TheVoidUnderALidMayReachUnderTheFacesAroundIt) {
  // A floor at 0 meshed from points 1.5 m apart (SLAM density); rays crossed the cell behind one
  // level face, 0.4 m deep. Where the pit ends between the rim points its lid spans and the ground
  // points beyond them, nothing shows: the faces around the lid's vertices may hide the same 0.4 m
  // drop (limit 0.18 m) and are uncertain, even where a footprint at their centroid does not reach
  // the lid; faces beyond them that no footprint of theirs reaches stay free.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const mesher::TriangleMesh mesh = test::heightFieldMesh(-6, 6, -6, 6, 1.5, [](double, double) { return 0.0; });
  std::size_t lid = mesh.faces.size();
  for (std::size_t f = 0; f < mesh.faces.size() && lid == mesh.faces.size(); ++f) {
    if (distanceToFace(mesh, f, Eigen::Vector2d(0.2, 0.3)) == 0.0) lid = f;
  }
  ASSERT_LT(lid, mesh.faces.size());
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  faces[lid].back_crossings = static_cast<std::uint32_t>(profile.min_rays);
  faces[lid].back_depth = 0.4;
  const std::vector<FaceLayers> layers = layersOf(faces, profile);
  const auto sharesVertex = [&](std::size_t f) {
    for (const auto a : mesh.faces[f]) {
      for (const auto b : mesh.faces[lid]) {
        if (a == b) return true;
      }
    }
    return false;
  };
  std::vector<std::size_t> around;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (f != lid && sharesVertex(f)) around.push_back(f);
  }
  EXPECT_EQ(layers[lid].face_class, FaceClass::kUncertain);
  std::size_t beyond_footprint = 0, far = 0;
  for (std::size_t f : around) {
    const Eigen::Vector2d c = centroid(mesh, f).head<2>();
    EXPECT_EQ(layers[f].evidence, Evidence::kMeasured) << "face " << f;
    EXPECT_GE(layers[f].height_uncertainty_m, 0.4f) << "face " << f;
    EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << "at " << c.transpose();
    EXPECT_TRUE(layers[f].reasons & reason::kWorstCaseRelief) << layers[f].reasons;
    // Without the lid's depth around its vertices, these would be free: their footprint misses it.
    if (distanceToFace(mesh, lid, c) > r + 0.05) ++beyond_footprint;
  }
  EXPECT_GE(around.size(), 9u);
  EXPECT_GT(beyond_footprint, 3u);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector2d c = centroid(mesh, f).head<2>();
    if (std::max(std::abs(c.x()), std::abs(c.y())) > 4.5) continue;  // near the map's edge
    double nearest = distanceToFace(mesh, lid, c);
    for (std::size_t g : around) nearest = std::min(nearest, distanceToFace(mesh, g, c));
    if (nearest <= r + 0.05) continue;
    ++far;
    EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "at " << c.transpose();
    EXPECT_LT(layers[f].height_uncertainty_m, 0.1f);
  }
  EXPECT_GT(far, 10u);
  // A void the robot can step down into (0.15 m, limit 0.18 m) leaves the faces around the lid as
  // they were: those whose footprint misses the lid are free.
  faces[lid].back_depth = 0.15;
  const std::vector<FaceLayers> shallow = layersOf(faces, profile);
  for (std::size_t f : around) {
    const Eigen::Vector2d c = centroid(mesh, f).head<2>();
    EXPECT_LT(shallow[f].height_uncertainty_m, 0.1f) << "face " << f;
    if (distanceToFace(mesh, lid, c) > r + 0.05) {
      EXPECT_EQ(shallow[f].face_class, FaceClass::kFree) << "at " << c.transpose();
    }
  }
}

/// A floor at 0 meshed from points 1.5 m apart, and a face hanging from its vertex at the origin
/// (the hinge), facing down, to two points `drop` below the floor at x = 1 (y = +-0.4): the last
/// of `faces`, with `crossings` rays through the cell under it and the keyframes' `view_sides`.
struct FoldedFloor {
  mesher::TriangleMesh floor = test::heightFieldMesh(-6, 6, -6, 6, 1.5, [](double, double) { return 0.0; });
  std::uint32_t hinge = 0;

  FoldedFloor() {
    for (std::uint32_t v = 0; v < floor.vertices.size(); ++v) {
      if (floor.vertices[v].norm() < floor.vertices[hinge].norm()) hinge = v;
    }
  }
  /// The floor and a fold from the hinge down by `drop`, whose two low vertices are undersides of
  /// driven ground if `undersides`.
  std::vector<mesher::SurfaceFace> faces(double drop, std::uint32_t crossings, std::uint8_t view_sides,
                                         bool undersides = false) const {
    mesher::TriangleMesh folded = floor;
    const auto low = static_cast<std::uint32_t>(folded.vertices.size());
    folded.vertices.emplace_back(1.0, 0.4, -drop);
    folded.vertices.emplace_back(1.0, -0.4, -drop);
    folded.faces.push_back({hinge, low, low + 1});  // wound to face down
    std::vector<mesher::SurfaceFace> out = facesOf(folded, 4);
    out.back().front_crossings = crossings;
    out.back().view_sides = view_sides;
    out.back().underside_vertices = undersides ? 2 : 0;
    return out;
  }
  /// Whether floor face f has the hinge as a vertex.
  bool atHinge(std::size_t f) const {
    const auto& t = floor.faces[f];
    return t[0] == hinge || t[1] == hinge || t[2] == hinge;
  }
  /// Whether floor face f lies over the fold: it holds a point of the fold's inside.
  bool overFold(std::size_t f) const {
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.7, 0.05), Eigen::Vector2d(0.7, -0.05)}) {
      if (distanceToFace(floor, f, p) == 0.0) return true;
    }
    return false;
  }
};

TEST(EvidenceTest, GroundOverAFoldRaysCrossedUnderIsNotFree) {
  // The fold hangs 0.3 m below the floor and rays crossed the space under it, seen only from
  // above (a pit's wall, or the mesh spanning a pit's corner at the rim's height). The faces at
  // its vertex over it are a crust over free space whose depth nothing measured: uncertain (a
  // possible drop deeper than the 0.18 m step), not free; the other faces at its vertex do not
  // take that depth. Faces no footprint of theirs reaches stay free.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const FoldedFloor scene;
  ASSERT_LT(scene.floor.vertices[scene.hinge].norm(), 1e-9);
  const std::vector<FaceLayers> layers = layersOf(scene.faces(0.3, 4, mesher::view_side::kBehind), profile);
  ASSERT_GT(layers.back().slope_deg, 150.0f) << "the fold must face down";
  const std::size_t floor_faces = scene.floor.faces.size();
  std::size_t crust = 0, beside = 0, far = 0;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector2d c = centroid(scene.floor, f).head<2>();
    if (scene.atHinge(f) && scene.overFold(f)) {
      ++crust;
      EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << "at " << c.transpose();
      EXPECT_TRUE(layers[f].reasons & reason::kWorstCaseRelief) << layers[f].reasons;
      EXPECT_GE(layers[f].height_uncertainty_m, 0.3f) << "at " << c.transpose();
      EXPECT_EQ(layers[f].evidence, Evidence::kMeasured) << "at " << c.transpose();
    } else if (scene.atHinge(f)) {
      ++beside;
      EXPECT_LT(layers[f].height_uncertainty_m, 0.1f) << "at " << c.transpose();
    } else if (std::max(std::abs(c.x()), std::abs(c.y())) <= 4.5) {  // away from the map's edge
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t g = 0; g < floor_faces; ++g) {
        if (scene.atHinge(g) && scene.overFold(g)) nearest = std::min(nearest, distanceToFace(scene.floor, g, c));
      }
      if (nearest <= r + 0.05) continue;
      ++far;
      EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "at " << c.transpose();
    }
  }
  EXPECT_GE(crust, 1u);
  EXPECT_GE(beside, 4u);
  EXPECT_GT(far, 10u);
}

TEST(EvidenceTest, NoFoldWithoutRaysUnderItFromAbove) {
  // No ray crossed the space under the face, it drops within the points' noise (0.05 m, 3 cm
  // noise), a keyframe saw it from below (an underside: a deck's, whose matter was seen from
  // both sides), or it hangs down to the underside of driven ground (a deck's slab the drive put
  // there, 0.12 m: the underside depth and noise; seen from above only, with rays from the level
  // beneath crossing under it): no fold of free space. The faces at its vertex are as free as the
  // rest.
  const RobotProfile profile = smallWheeled();
  const FoldedFloor scene;
  const std::uint8_t both = mesher::view_side::kFront | mesher::view_side::kBehind;
  const std::uint8_t above = mesher::view_side::kBehind;
  for (const auto& [drop, crossings, sides, undersides] :
       {std::tuple<double, std::uint32_t, std::uint8_t, bool>{0.3, 0, 0, false},
        {0.05, 4, 0, false},
        {0.3, 4, mesher::view_side::kFront, false},
        {0.3, 4, both, false},
        {0.12, 4, above, true},
        {0.3, 4, above, true}}) {
    const std::vector<FaceLayers> layers = layersOf(scene.faces(drop, crossings, sides, undersides), profile);
    std::size_t checked = 0;
    for (std::size_t f = 0; f < scene.floor.faces.size(); ++f) {
      if (!scene.atHinge(f)) continue;
      ++checked;
      EXPECT_EQ(layers[f].face_class, FaceClass::kFree)
          << "drop " << drop << ", crossings " << crossings << ", views " << int(sides)
          << ", undersides " << undersides;
      EXPECT_LT(layers[f].height_uncertainty_m, 0.1f);
    }
    EXPECT_GE(checked, 6u);
  }
}

TEST(EvidenceTest, AFoldKeptCurrentEqualsFullRecomputation) {
  // Rays come to cross under the fold (its counts re-read), a keyframe sees it from below and no
  // longer does, then it goes: each state as a full computation of it.
  const RobotProfile profile = smallWheeled();
  const FoldedFloor scene;
  std::vector<mesher::SurfaceFace> faces = scene.faces(0.3, 0, 0);
  mesher::SurfaceFace fold = faces.back();
  TraversabilityMap map(profile, MapFrame{});
  map.reset(faces);
  const auto expectAsFull = [&](const char* what) {
    const std::map<mesher::FaceKey, FaceLayers> full = layersByKey(faces, profile);
    const std::map<mesher::FaceKey, FaceLayers> kept = layersByKey(map);
    ASSERT_EQ(kept.size(), full.size()) << what;
    for (const auto& [key, layers] : full) {
      const FaceLayers& k = kept.at(key);
      EXPECT_EQ(k.face_class, layers.face_class) << what;
      for (const LayerInfo& layer : faceLayerRegistry()) {
        const double u = layer.get(k), v = layer.get(layers);
        EXPECT_TRUE((std::isnan(u) && std::isnan(v)) || u == v) << what << ": " << layer.name << " " << u << "/" << v;
      }
    }
  };
  const auto recount = [&](std::uint32_t crossings, std::uint8_t view_sides, const char* what) {
    fold.front_crossings = crossings;
    fold.view_sides = view_sides;
    faces.back() = fold;
    map.apply(mesher::SurfaceDelta{0, 0, true, {}, {}, {}}, {fold});
    expectAsFull(what);
  };
  recount(4, 0, "after rays crossed under the fold");
  recount(4, mesher::view_side::kFront, "after a keyframe saw the fold from below");
  recount(4, 0, "after the view from below was gone");
  faces.pop_back();
  map.apply(mesher::SurfaceDelta{0, 0, true, {fold.key}, {}, {}}, {});
  expectAsFull("after the fold went");
}

TEST(EvidenceTest, AWallWithRaysBehindItIsUncertainNotLethal) {
  // A 2 m wall over a floor, with rays through the space in front of it. With at least min_rays
  // rays through the cell behind it as well, the space it closes off was seen free: it is a
  // membrane the 2-manifold keeps, not a measured wall, so it is uncertain (a guessed wall) and
  // the floor beside it, whose footprint meets it, is uncertain too, not lethal. With fewer (a
  // point's noise) it is a measured wall: lethal, both.
  const RobotProfile profile = smallWheeled();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  test::appendMesh(mesh, test::thinWall(0, -2, 0, 2, 0, 2.0));
  const auto near_floor = [&](std::size_t f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    return f < floor_faces && std::abs(c.x()) < 0.2 && std::abs(c.y()) < 1.5;
  };
  const auto min_rays = static_cast<std::uint32_t>(profile.min_rays);
  for (const std::uint32_t behind : {min_rays, min_rays - 1}) {
    std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
    for (std::size_t f = floor_faces; f < faces.size(); ++f) {
      faces[f].back_crossings = behind;
      faces[f].back_depth = 0.5;
    }
    const std::vector<FaceLayers> layers = layersOf(faces, profile);
    const bool seen_behind = behind >= min_rays;
    const FaceClass want = seen_behind ? FaceClass::kUncertain : FaceClass::kLethal;
    std::size_t floors = 0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      if (f >= floor_faces) {
        EXPECT_EQ(layers[f].face_class, want) << "wall face, rays behind " << behind;
        EXPECT_EQ(layers[f].evidence, seen_behind ? Evidence::kInterpolated : Evidence::kMeasured);
        EXPECT_TRUE(layers[f].reasons & (seen_behind ? reason::kGuessedWall : reason::kTooSteep))
            << "wall face, rays behind " << behind << ": reasons " << layers[f].reasons;
      } else if (near_floor(f)) {
        ++floors;
        EXPECT_EQ(layers[f].face_class, want) << "floor beside the wall, rays behind " << behind;
        if (seen_behind) {
          EXPECT_TRUE(layers[f].reasons & reason::kPossibleObstacle) << layers[f].reasons;
        }
      }
    }
    EXPECT_GT(floors, 20u);
  }
}

}  // namespace
}  // namespace terramesh::traversability
