// Where a sparsely measured obstacle may extend: along its face and behind it, never towards its
// front (the rays that measured it crossed that space), and over driven ground never into the
// strip the robot's body swept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "evidence_faces.h"
#include "test_support/traversability_scenes.h"
#include "traversability/layer_registry.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

/// A one-sided vertical wall in the plane x = x0 from y0 to y1, `height` tall, facing +x (its
/// front), as two triangles (sparse: four points).
mesher::TriangleMesh wallFacingPlusX(double x0, double y0, double y1, double height) {
  mesher::TriangleMesh wall;
  wall.vertices = {{x0, y0, 0}, {x0, y1, 0}, {x0, y1, height}, {x0, y0, height}};
  wall.faces = {{0, 1, 2}, {0, 2, 3}};
  return wall;
}

/// The classes of the floor faces (the first `floor_faces` of `mesh`) centred within 0.025 m of
/// (x, y).
std::vector<FaceClass> floorClassesAt(const mesher::TriangleMesh& mesh, const std::vector<FaceLayers>& layers,
                                      std::size_t floor_faces, double x, double y) {
  std::vector<FaceClass> classes;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (std::abs(c.x() - x) < 0.025 && std::abs(c.y() - y) < 0.025) classes.push_back(layers[f].face_class);
  }
  return classes;
}

TEST(ObstacleExtensionTest, AMeasuredWallMayExtendAlongItselfAndBehindItNotTowardsItsFront) {
  // A 1.5 m wall along x = 0 for -5 < y < 0, facing +x, measured by four points: it may extend
  // max_obstacle_extension_m past its free end and behind it. The floor in front, where a robot's
  // footprint stays clear of the wall by less than that, is free; the floor behind it at the
  // same distance and beyond the free end is uncertain, for the wall's possible extension alone.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const double cap = profile.evidence.max_obstacle_extension_m;
  ASSERT_GT(cap, 0.2);
  mesher::TriangleMesh mesh = test::heightFieldMesh(-4, 4, -6, 4, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  test::appendMesh(mesh, wallFacingPlusX(0, -5, 0, 1.5));
  const std::vector<FaceLayers> layers = layersOf(facesOf(mesh, 4), profile);
  const double gap = r + 0.5 * cap;  // from the wall to the footprint's centre
  const auto expectAt = [&](double x, double y, FaceClass want, const char* where) {
    std::size_t judged = 0;
    for (std::size_t f = 0; f < floor_faces; ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      if (std::abs(c.x() - x) >= 0.025 || std::abs(c.y() - y) >= 0.025) continue;
      ++judged;
      EXPECT_EQ(layers[f].face_class, want) << where << " at (" << c.x() << ", " << c.y() << ")";
      if (want == FaceClass::kUncertain) {
        EXPECT_EQ(layers[f].reasons, reason::kObstacleExtension) << where;
      }
    }
    EXPECT_GT(judged, 0u) << where;
  };
  expectAt(gap, -2.45, FaceClass::kFree, "in front of the wall");
  expectAt(-gap, -2.45, FaceClass::kUncertain, "behind the wall");
  expectAt(0.05, gap, FaceClass::kUncertain, "beyond its free end");
  // Beyond what it may extend to, front and back alike.
  expectAt(-(r + cap + 0.15), -2.45, FaceClass::kFree, "far behind the wall");
}

TEST(ObstacleExtensionTest, ASlantedFaceMayNotExtendPastItsFootEither) {
  // A measured face rising at 25 degrees (steeper than small_wheeled's 20, not a wall) from the
  // floor at x = 0 up to 0.7 m at x = -1.5, for -5 < y < 0, descending towards +x (its front).
  // Its part in the body starts 0.39 m behind its foot; extended every way it would reach 0.11 m
  // past the foot, over floor the rays that measured the face crossed. It extends towards its
  // front only down to its foot, along itself past its free end as a wall does.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const double cap = profile.evidence.max_obstacle_extension_m;
  const double rise = 1.5 * std::tan(25.0 * M_PI / 180.0);
  const double body_from_foot = profile.max_step_m / std::tan(25.0 * M_PI / 180.0);
  ASSERT_GT(body_from_foot, 0.3);
  ASSERT_GT(cap - body_from_foot, 0.08);  // every way, past the foot
  mesher::TriangleMesh mesh = test::heightFieldMesh(-4, 4, -6, 4, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  mesher::TriangleMesh slant;
  slant.vertices = {{0, -5, 0}, {0, 0, 0}, {-1.5, 0, rise}, {-1.5, -5, rise}};
  slant.faces = {{0, 1, 2}, {0, 2, 3}};
  test::appendMesh(mesh, slant);
  const std::vector<FaceLayers> layers = layersOf(facesOf(mesh, 4), profile);
  const auto classAt = [&](double x, double y) { return floorClassesAt(mesh, layers, floor_faces, x, y); };
  // The footprint's edge 0.05 m past the foot: clear of the face, within the old disc.
  for (const FaceClass got : classAt(r + 0.05, -2.45)) EXPECT_EQ(got, FaceClass::kFree) << "in front of its foot";
  // Beyond its free end, as close: the face may continue along itself.
  for (const FaceClass got : classAt(0.05, 0.5 * cap + r)) EXPECT_EQ(got, FaceClass::kUncertain) << "past its end";
  EXPECT_FALSE(classAt(r + 0.05, -2.45).empty());
  EXPECT_FALSE(classAt(0.05, 0.5 * cap + r).empty());
}

TEST(ObstacleExtensionTest, ATiltedTopWhollyInTheBodyMayExtendEveryWay) {
  // The top of something, tilted 25 degrees (steeper than small_wheeled's 20) down towards +x:
  // 0.48 m up at x = -0.6, 0.2 m at x = 0, both within the body; its sides unmeasured. It ends where
  // its points end, and what holds it up may stand past its low edge: the floor in front of that
  // edge, within its extension, is not free; beyond that it is.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const double cap = profile.evidence.max_obstacle_extension_m;
  const double low = 0.2, high = low + 0.6 * std::tan(25.0 * M_PI / 180.0);
  ASSERT_GT(low, profile.max_step_m);
  ASSERT_LT(high, profile.min_clearance_m);
  mesher::TriangleMesh mesh = test::heightFieldMesh(0.1, 4, -6, 4, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  mesher::TriangleMesh top;
  top.vertices = {{0, -5, low}, {0, 0, low}, {-0.6, 0, high}, {-0.6, -5, high}};
  top.faces = {{0, 1, 2}, {0, 2, 3}};  // facing up, and towards +x
  test::appendMesh(mesh, top);
  const std::vector<FaceLayers> layers = layersOf(facesOf(mesh, 4), profile);
  const std::vector<FaceClass> near = floorClassesAt(mesh, layers, floor_faces, r + 0.5 * cap, -2.45);
  const std::vector<FaceClass> far = floorClassesAt(mesh, layers, floor_faces, r + cap + 0.15, -2.45);
  for (const FaceClass got : near) EXPECT_EQ(got, FaceClass::kUncertain) << "within its extension";
  for (const FaceClass got : far) EXPECT_EQ(got, FaceClass::kFree) << "beyond its extension";
  EXPECT_FALSE(near.empty());
  EXPECT_FALSE(far.empty());
}

TEST(ObstacleExtensionTest, OnDrivenGroundAnObstacleMayExtendOnlyBeyondTheStripTheBodySwept) {
  // A driven strip (|y| <= the robot's radius, the drive along y = 0) and, beyond it, a measured
  // 0.4 m wall across the drive's direction (x = 0, 0.6 < y < 3) whose free end points at the
  // strip: it may extend 0.5 m along itself, into the strip, where the robot's body swept. With
  // the drive's poses that part is contradicted: the strip's faces whose footprint stays inside
  // it are free, those whose footprint reaches past the side towards the wall are not. Without
  // the poses the strip is unknown and the extension counts everywhere.
  const RobotProfile profile = smallWheeled();
  const double half = profile.footprint_radius_m;
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  test::appendMesh(mesh, wallFacingPlusX(0, 0.6, 3, 0.4));
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  driveAlongX(faces, floor_faces, half);
  for (const bool with_poses : {false, true}) {
    const std::map<mesher::FaceKey, FaceLayers> layers =
        layersByKey(faces, profile, with_poses ? basesAlongX(mesh) : DrivePoseLookup{});
    std::size_t inside = 0, reaching = 0;
    for (std::size_t f = 0; f < floor_faces; ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      if (faces[f].driven_vertices != 3 || std::abs(c.x()) > 0.1) continue;
      const FaceLayers& got = layers.at(faces[f].key);
      if (c.y() < -0.03 && c.y() > -0.2) {
        // The footprint stays on the strip's side of its +y edge, and within the extension's reach.
        ++inside;
        EXPECT_EQ(got.face_class, with_poses ? FaceClass::kFree : FaceClass::kUncertain)
            << "poses " << with_poses << " at (" << c.x() << ", " << c.y() << ")";
      } else if (c.y() > 0.1 && c.y() < 0.24) {
        // The footprint reaches past that edge, not to the wall itself.
        ++reaching;
        EXPECT_EQ(got.face_class, FaceClass::kUncertain) << "poses " << with_poses << " at (" << c.x() << ", " << c.y() << ")";
        EXPECT_TRUE(got.reasons & reason::kObstacleExtension) << "poses " << with_poses;
      }
    }
    EXPECT_GT(inside, 4u);
    EXPECT_GT(reaching, 4u);
  }
}

TEST(ObstacleExtensionTest, AFaceTheDriveCrossedIsJudgedWhereTheDriveStoodOnIt) {
  // A strip driven along y = 0 whose samples lie on four rails (y = +-0.12 and +-0.34, a car's
  // layout): the faces between the inner rails straddle the drive's centre line, with centroids
  // 0.04 m off it. The wall of the test above, beyond the strip, may extend to within 0.04 m of the
  // strip's side. Centred on such a centroid the footprint would reach 0.04 m past the side; the
  // drive put the robot on the centre line there, and judged there it stays inside the strip: free.
  // Faces between the outer rails do not reach the centre line: they are judged at their centroid,
  // and stay uncertain where their footprint reaches the wall's extension.
  const RobotProfile profile = smallWheeled();
  const double half = profile.footprint_radius_m;
  const std::vector<double> ys = {-3, -2, -1, -0.6, -half, -0.12, 0.12, half, 0.6, 1, 2, 3};
  mesher::TriangleMesh mesh;
  for (int i = 0; i <= 12; ++i) {
    for (const double y : ys) mesh.vertices.emplace_back(-3 + 0.5 * i, y, 0);
  }
  const auto at = [&](int i, std::size_t j) {
    return static_cast<std::uint32_t>(static_cast<std::size_t>(i) * ys.size() + j);
  };
  for (int i = 0; i < 12; ++i) {
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      mesh.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  const std::size_t floor_faces = mesh.faces.size();
  test::appendMesh(mesh, wallFacingPlusX(0, 0.6, 3, 0.4));
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  driveAlongX(faces, floor_faces, half);
  const std::map<mesher::FaceKey, FaceLayers> layers = layersByKey(faces, profile, basesAlongX(mesh));
  std::size_t crossed = 0, beside = 0;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (faces[f].driven_vertices != 3 || c.x() < -0.5 || c.x() > 0) continue;
    const FaceLayers& got = layers.at(faces[f].key);
    if (std::abs(c.y()) < 0.1) {
      ++crossed;
      EXPECT_EQ(got.face_class, FaceClass::kFree) << "at (" << c.x() << ", " << c.y() << ")";
    } else if (c.y() > 0.12) {
      ++beside;
      EXPECT_EQ(got.face_class, FaceClass::kUncertain) << "at (" << c.x() << ", " << c.y() << ")";
      EXPECT_TRUE(got.reasons & reason::kObstacleExtension);
    }
  }
  EXPECT_EQ(crossed, 2u);
  EXPECT_EQ(beside, 2u);
}

TEST(ObstacleExtensionTest, AChangedObstacleRejudgesOnlyTheFacesWithinTheReachOfItsOwnExtension) {
  // A post 0.1 m wide may extend only obstacle_extension times that beyond itself. Adding it
  // re-judges the floor faces whose footprint, grown by that, can meet it: not every face within
  // the reach of the largest extension (max_obstacle_extension_m). The map still equals a full
  // recomputation. (The post is lower than max_step_m and seen by too few rays to be lethal
  // itself; the inflation, which re-ranges the faces around any face added, reaches no farther
  // than the footprint here: the faces recomputed are the faces re-judged.)
  RobotProfile profile = smallWheeled();
  profile.inflation_radius_m = profile.inscribed_radius_m;
  ASSERT_LT(profile.inflation_radius_m, profile.footprintCircumradiusM());
  const double r = profile.footprintCircumradiusM();
  const double cap = profile.evidence.max_obstacle_extension_m;
  const double own = std::min(profile.evidence.obstacle_extension * 0.1, cap);
  ASSERT_LT(own + 0.2, cap);
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  TraversabilityMap map(profile, MapFrame{});
  map.reset(facesOf(mesh, 4));
  test::appendMesh(mesh, wallFacingPlusX(0.03, -0.05, 0.05, 0.5 * profile.max_step_m));
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  for (std::size_t f = floor_faces; f < faces.size(); ++f) faces[f].rays = faces[f].front_crossings = 0;
  mesher::SurfaceDelta delta;
  delta.added.assign(faces.begin() + static_cast<std::ptrdiff_t>(floor_faces), faces.end());
  const LayerUpdateStats stats = map.apply(delta, {});
  // Floor faces whose centroid lies within `reach` of the post (x = 0.03, |y| <= 0.05).
  const auto within = [&](double reach) {
    std::size_t count = 0;
    for (std::size_t f = 0; f < floor_faces; ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      count += std::hypot(c.x() - 0.03, std::max(0.0, std::abs(c.y()) - 0.05)) <= reach ? 1 : 0;
    }
    return count;
  };
  EXPECT_GT(stats.faces_recomputed, within(r));
  EXPECT_LE(stats.faces_recomputed, within(r + own + 0.01) + delta.added.size());
  EXPECT_LT(stats.faces_recomputed, within(r + cap - 0.1));
  const std::map<mesher::FaceKey, FaceLayers> fresh = layersByKey(faces, profile);
  const std::map<mesher::FaceKey, FaceLayers> updated = layersByKey(map);
  ASSERT_EQ(updated.size(), fresh.size());
  for (const auto& [key, want] : fresh) {
    const FaceLayers& got = updated.at(key);
    EXPECT_EQ(got.face_class, want.face_class);
    for (const LayerInfo& layer : faceLayerRegistry()) {
      const double u = layer.get(got), v = layer.get(want);
      EXPECT_TRUE((std::isnan(u) && std::isnan(v)) || u == v) << layer.name;
    }
  }
}

}  // namespace
}  // namespace terramesh::traversability
