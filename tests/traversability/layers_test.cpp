// Layers on small hand-made meshes whose geometry is exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

#include "test_support/traversability_scenes.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

RobotProfile smallWheeled() { return loadRobotProfile(kRobots / "small_wheeled.yaml"); }

LayeredMesh compute(const mesher::TriangleMesh& mesh, const RobotProfile& profile) {
  return TraversabilityMap::computeForMesh(mesh, profile, MapFrame{}, 10);
}

Eigen::Vector3d centroid(const LayeredMesh& map, std::size_t f) {
  const auto& t = map.mesh.faces[f];
  return (map.mesh.vertices[t[0]] + map.mesh.vertices[t[1]] + map.mesh.vertices[t[2]]) / 3.0;
}

/// Indices of the faces whose centroid satisfies `pick`.
template <class Pick>
std::vector<std::size_t> facesWhere(const LayeredMesh& map, Pick pick) {
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    if (pick(centroid(map, f))) faces.push_back(f);
  }
  return faces;
}

TEST(LayersTest, RampOfKnownSlope) {
  for (double slope : {5.0, 15.0, 30.0}) {
    const double t = std::tan(slope * M_PI / 180.0);
    const LayeredMesh map = compute(test::heightFieldMesh(-3, 3, -3, 3, 0.25, [t](double x, double) { return t * x; }),
                                    smallWheeled());
    for (std::size_t f = 0; f < map.layers.size(); ++f) {
      ASSERT_NEAR(map.layers[f].slope_deg, slope, 1e-3) << "face " << f;
    }
    // Away from the border, a plane has no step, no roughness and full contact.
    const auto inner = facesWhere(map, [](const Eigen::Vector3d& c) { return c.head<2>().cwiseAbs().maxCoeff() < 2.0; });
    ASSERT_FALSE(inner.empty());
    // (Faces steeper than max_slope measure their step as the height range around them.)
    for (std::size_t f : inner) {
      if (slope < 20) {
        ASSERT_LT(map.layers[f].step_m, 1e-6) << slope;
      }
      ASSERT_LT(map.layers[f].roughness_m, 1e-6) << slope;
      ASSERT_EQ(map.layers[f].contact, 1.0f) << slope;
      ASSERT_EQ(map.layers[f].face_class, slope < 20 ? FaceClass::kFree : FaceClass::kLethal) << slope;
    }
  }
}

TEST(LayersTest, FlatFloorCostsNothingAndItsBorderHasLowContact) {
  const RobotProfile profile = smallWheeled();
  const LayeredMesh map = compute(test::heightFieldMesh(-5, 5, -5, 5, 0.25, [](double, double) { return 0.0; }), profile);
  const double margin = profile.footprintCircumradiusM() + profile.inflation_radius_m + 0.3;
  std::size_t inner = 0;
  for (std::size_t f = 0; f < map.layers.size(); ++f) {
    const Eigen::Vector3d c = centroid(map, f);
    const double to_border = 5.0 - c.head<2>().cwiseAbs().maxCoeff();
    const FaceLayers& l = map.layers[f];
    if (to_border > margin) {
      ++inner;
      EXPECT_EQ(l.face_class, FaceClass::kFree);
      EXPECT_LT(l.cost, 1e-6);
      EXPECT_TRUE(std::isinf(l.clearance_m));
      EXPECT_TRUE(std::isinf(l.lethal_distance_m));
    }
    if (to_border < 0.1) {
      EXPECT_LT(l.contact, 0.7) << "the footprint hangs over the end of the map";
    } else if (to_border < profile.footprintCircumradiusM() - 0.05) {
      EXPECT_LT(l.contact, 1.0) << to_border;
    }
  }
  EXPECT_GT(inner, 100u);
}

struct StepResult {
  float min_step = 1e9f, max_step = 0;
  std::size_t lethal = 0, faces = 0;
};

StepResult nearStep(double height) {
  const LayeredMesh map = compute(
      test::heightFieldMesh(-3, 3, -3, 3, 0.1, [height](double, double y) { return y > -1e-9 ? height : 0.0; }),
      smallWheeled());
  StepResult r;
  for (std::size_t f : facesWhere(map, [](const Eigen::Vector3d& c) { return std::abs(c.x()) < 1.5 && std::abs(c.y()) < 0.2; })) {
    if (map.layers[f].slope_deg < 1) {  // the levels: risers' steps are judged from a tilted plane
      r.min_step = std::min(r.min_step, map.layers[f].step_m);
      r.max_step = std::max(r.max_step, map.layers[f].step_m);
    }
    r.lethal += map.layers[f].face_class == FaceClass::kLethal;
    ++r.faces;
  }
  return r;
}

TEST(LayersTest, CurbIsAPassableStepLedgeIsNot) {
  const StepResult curb = nearStep(0.15);
  ASSERT_GT(curb.faces, 0u);
  // The riser is 0.1 m wide: riser samples at mid height tilt the level's plane a little.
  EXPECT_NEAR(curb.min_step, 0.15f, 0.015);
  EXPECT_NEAR(curb.max_step, 0.15f, 0.001);
  EXPECT_EQ(curb.lethal, 0u) << "a 0.15 m curb is passable for small_wheeled";
  const StepResult ledge = nearStep(0.4);
  EXPECT_NEAR(ledge.min_step, 0.4f, 0.04);
  EXPECT_NEAR(ledge.max_step, 0.4f, 0.04);
  EXPECT_EQ(ledge.lethal, ledge.faces) << "a 0.4 m ledge is not";
}

TEST(LayersTest, LowCeilingMakesTheFloorUnderItLethal) {
  for (const bool steiner_ceiling : {false, true}) {
    for (const double ceiling : {0.4, 2.0}) {
      mesher::TriangleMesh mesh = test::heightFieldMesh(-4, 4, -4, 4, 0.25, [](double, double) { return 0.0; });
      const std::size_t floor_vertices = mesh.vertices.size();
      test::appendMesh(mesh, test::horizontalQuad(-1, 1, -1, 1, ceiling, true));
      mesh.is_steiner.assign(mesh.vertices.size(), 0);
      for (std::size_t v = floor_vertices; v < mesh.vertices.size(); ++v) mesh.is_steiner[v] = steiner_ceiling;
      const LayeredMesh map = compute(mesh, smallWheeled());
      const auto under = facesWhere(map, [](const Eigen::Vector3d& c) { return c.z() < 0.01 && c.head<2>().cwiseAbs().maxCoeff() < 0.9; });
      ASSERT_FALSE(under.empty());
      for (std::size_t f : under) {
        const FaceLayers& l = map.layers[f];
        if (steiner_ceiling) {
          EXPECT_TRUE(std::isnan(l.clearance_m)) << "unknown, not low";
          EXPECT_NE(l.face_class, FaceClass::kLethal);
        } else {
          EXPECT_NEAR(l.clearance_m, ceiling, 1e-5);
          EXPECT_EQ(l.face_class == FaceClass::kLethal, ceiling < 0.5) << ceiling;
        }
      }
      for (std::size_t f : facesWhere(map, [](const Eigen::Vector3d& c) { return c.z() < 0.01 && c.head<2>().cwiseAbs().minCoeff() > 1.1; })) {
        EXPECT_TRUE(std::isinf(map.layers[f].clearance_m));
      }
    }
  }
}

TEST(LayersTest, TwoFloorsAreJudgedEachOnItsOwn) {
  // A lower floor and, over half of it, a 0.3 m slab whose top is an upper floor 2.8 m up: nothing
  // may assume one height per (x, y).
  mesher::TriangleMesh mesh = test::heightFieldMesh(-6, 6, -6, 6, 0.25, [](double, double) { return 0.0; });
  mesher::TriangleMesh underside = test::heightFieldMesh(-6, 0, -6, 6, 0.25, [](double, double) { return 2.5; });
  for (auto& face : underside.faces) std::swap(face[1], face[2]);  // facing down
  test::appendMesh(mesh, underside);
  test::appendMesh(mesh, test::heightFieldMesh(-6, 0, -6, 6, 0.25, [](double, double) { return 2.8; }));
  const LayeredMesh map = compute(mesh, smallWheeled());
  const auto interior = [](const Eigen::Vector3d& c, double x0, double x1) {
    return c.x() > x0 && c.x() < x1 && std::abs(c.y()) < 3.5;
  };
  const auto lower = facesWhere(map, [&](const Eigen::Vector3d& c) { return c.z() < 0.01 && interior(c, -3.5, -1.5); });
  const auto upper = facesWhere(map, [&](const Eigen::Vector3d& c) { return c.z() > 2.79 && interior(c, -3.5, -1.5); });
  const auto edge = facesWhere(map, [&](const Eigen::Vector3d& c) { return c.z() > 2.79 && interior(c, -0.1, 0.0); });
  ASSERT_FALSE(lower.empty());
  ASSERT_FALSE(upper.empty());
  ASSERT_FALSE(edge.empty());
  for (std::size_t f : lower) {
    ASSERT_NEAR(map.layers[f].clearance_m, 2.5, 1e-5);
    ASSERT_EQ(map.layers[f].face_class, FaceClass::kFree);
    ASSERT_LT(map.layers[f].step_m, 1e-6);
  }
  for (std::size_t f : upper) {
    ASSERT_TRUE(std::isinf(map.layers[f].clearance_m));
    ASSERT_EQ(map.layers[f].face_class, FaceClass::kFree);
    ASSERT_LT(map.layers[f].step_m, 1e-6);
    ASSERT_EQ(map.layers[f].contact, 1.0f);
  }
  for (std::size_t f : edge) {
    ASSERT_LT(map.layers[f].contact, 0.7f) << "the upper floor ends over a 2.8 m drop";
    ASSERT_EQ(map.layers[f].face_class, FaceClass::kLethal);
  }
}

TEST(LayersTest, FacesWithoutRaysOrTouchingSteinerAreUnknown) {
  const mesher::TriangleMesh mesh = test::heightFieldMesh(-2, 2, -2, 2, 0.5, [](double, double) { return 0.0; });
  std::vector<mesher::SurfaceFace> faces;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    mesher::SurfaceFace face;
    for (int i = 0; i < 3; ++i) {
      face.vertices[i] = mesher::VertexKey{mesh.faces[f][i], f == 1 && i == 0};
      face.positions_W[i] = mesh.vertices[mesh.faces[f][i]];
    }
    face.touches_steiner = f == 1;
    face.key = mesher::FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    face.rays = f == 0 ? 0 : (f == 2 ? 2 : 10);
    faces.push_back(face);
  }
  RobotProfile profile = smallWheeled();
  TraversabilityMap map(profile, MapFrame{});
  map.reset(faces);
  const LayeredMesh snapshot = map.snapshot();
  std::map<mesher::FaceKey, FaceLayers> by_key;
  for (std::size_t f = 0; f < snapshot.layers.size(); ++f) by_key[snapshot.face_keys[f]] = snapshot.layers[f];
  EXPECT_EQ(by_key.at(faces[0].key).face_class, FaceClass::kUnknown) << "seen by no ray";
  EXPECT_TRUE(std::isnan(by_key.at(faces[0].key).cost));
  EXPECT_EQ(by_key.at(faces[1].key).face_class, FaceClass::kUnknown) << "touches a Steiner vertex";
  EXPECT_TRUE(by_key.at(faces[1].key).steiner);
  EXPECT_EQ(by_key.at(faces[2].key).face_class, FaceClass::kUnknown) << "2 rays < min_rays 3";
  EXPECT_NE(by_key.at(faces[3].key).face_class, FaceClass::kUnknown);
  EXPECT_EQ(by_key.at(faces[3].key).rays, 10u);
}

TEST(LayersTest, FootprintOverALedgeOrAHoleLosesContact) {
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  // A plateau ending at x = 0 with a 1 m drop, and the same plateau over nothing (a hole).
  for (const bool drop : {true, false}) {
    mesher::TriangleMesh mesh = test::heightFieldMesh(-4, 0, -3, 3, 0.1, [](double, double) { return 0.0; });
    if (drop) test::appendMesh(mesh, test::heightFieldMesh(0, 3, -3, 3, 0.1, [](double, double) { return -1.0; }));
    const LayeredMesh map = compute(mesh, profile);
    std::size_t edge = 0;
    for (std::size_t f : facesWhere(map, [](const Eigen::Vector3d& c) { return c.z() > -0.5 && std::abs(c.y()) < 2.0; })) {
      const double x = centroid(map, f).x();
      const FaceLayers& l = map.layers[f];
      EXPECT_EQ(l.slope_deg, 0.0f);
      if (x > -0.1) {
        ++edge;
        EXPECT_LT(l.contact, 0.7f) << "at x = " << x;
        EXPECT_EQ(l.face_class, FaceClass::kLethal);
      } else if (x > -r + 0.05) {
        EXPECT_LT(l.contact, 1.0f) << "at x = " << x;
      } else if (x < -r - 0.1 && x > -3.0) {
        EXPECT_EQ(l.contact, 1.0f) << "at x = " << x;
      }
    }
    EXPECT_GT(edge, 0u);
  }
}

TEST(LayersTest, RectangleFootprintContactDependsOnHeading) {
  // A 2 m wide strip, 30 m long, over nothing: the car fits along it, not across.
  const RobotProfile car = loadRobotProfile(kRobots / "car.yaml");
  const LayeredMesh map = compute(test::heightFieldMesh(-15, 15, -1, 1, 0.2, [](double, double) { return 0.0; }), car);
  const auto middle = facesWhere(map, [](const Eigen::Vector3d& c) { return std::abs(c.x()) < 1 && std::abs(c.y()) < 0.2; });
  ASSERT_FALSE(middle.empty());
  for (std::size_t f : middle) {
    EXPECT_EQ(map.layers[f].contact_best, 1.0f);
    EXPECT_LT(map.layers[f].contact, 0.6f);
    EXPECT_EQ(map.layers[f].face_class, FaceClass::kFree) << "the car fits along the strip";
  }
  // A 1.5 m wide strip: the 1.8 m wide car fits at no heading.
  const LayeredMesh narrow =
      compute(test::heightFieldMesh(-15, 15, -0.75, 0.75, 0.15, [](double, double) { return 0.0; }), car);
  const auto narrow_middle =
      facesWhere(narrow, [](const Eigen::Vector3d& c) { return std::abs(c.x()) < 1 && std::abs(c.y()) < 0.2; });
  ASSERT_FALSE(narrow_middle.empty());
  for (std::size_t f : narrow_middle) EXPECT_EQ(narrow.layers[f].face_class, FaceClass::kLethal);
}

TEST(LayersTest, RectangleBesideALedgeFitsAlongItNotAcrossIt) {
  // A 0.4 m ledge at y = 0 (the legged robot climbs 0.3 m): 1.1 x 0.5 m, circumradius 0.6 m.
  const RobotProfile legged = loadRobotProfile(kRobots / "legged.yaml");
  const LayeredMesh map = compute(
      test::heightFieldMesh(-4, 4, -3, 3, 0.1, [](double, double y) { return y > -1e-9 ? 0.4 : 0.0; }), legged);
  std::size_t beside = 0, at = 0, lost_contact = 0;
  for (std::size_t f : facesWhere(map, [](const Eigen::Vector3d& c) { return std::abs(c.x()) < 2; })) {
    const double y = centroid(map, f).y();
    const FaceLayers& l = map.layers[f];
    if (std::abs(y) < 0.15) {
      ++at;
      EXPECT_EQ(l.face_class, FaceClass::kLethal) << "at y = " << y << ": every heading crosses the ledge";
    } else if (std::abs(y) > 0.4 && std::abs(y) < 0.55) {
      // Within the circumradius (a disc would reach the ledge), beyond half the width.
      ++beside;
      EXPECT_EQ(l.face_class, FaceClass::kFree) << "at y = " << y << ": fits along the ledge";
      EXPECT_LT(l.step_m, 1e-6) << "the step of the heading that fits";
      EXPECT_EQ(l.contact_best, 1.0f);
      lost_contact += l.contact < 1.0f;  // turned across the ledge, the footprint reaches past it
    }
  }
  EXPECT_GT(at, 0u);
  EXPECT_GT(beside, 0u);
  EXPECT_GT(lost_contact, 0u);
}

/// Floor faces (level, at z = 0) whose centroid satisfies `pick`.
template <class Pick>
std::vector<std::size_t> floorFacesWhere(const LayeredMesh& map, Pick pick) {
  return facesWhere(map, [&](const Eigen::Vector3d& c) { return std::abs(c.z()) < 1e-9 && pick(c); });
}

TEST(LayersTest, DiscRobotDoesNotFitBesideATallWallWithFloorOnBothSides) {
  // A thin 2 m wall along x = 0 over a floor that continues on both sides: every footprint sample
  // finds floor, but a 0.34 m disc centred closer than 0.34 m to the wall collides with it (the
  // ground truth's rule: surface between max_step and the robot's height inside the footprint).
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  for (const double wall_m : {2.0, 0.3, 0.15}) {
    for (const bool steiner_wall : {false, true}) {
      mesher::TriangleMesh mesh = test::heightFieldMesh(-4, 4, -4, 4, 0.1, [](double, double) { return 0.0; });
      const std::size_t floor_vertices = mesh.vertices.size();
      test::appendMesh(mesh, test::thinWall(0, -2, 0, 2, 0, wall_m));
      mesh.is_steiner.assign(mesh.vertices.size(), 0);
      for (std::size_t v = floor_vertices; v < mesh.vertices.size(); ++v) mesh.is_steiner[v] = steiner_wall;
      const LayeredMesh map = compute(mesh, profile);
      // Taller than max_step (0.18 m): inside the body; a measured wall blocks, an invented one not.
      const bool blocks = wall_m > profile.max_step_m && !steiner_wall;
      std::size_t near = 0, far = 0, beside = 0;
      const double extension =
          std::min(profile.evidence.obstacle_extension * 4.0, profile.evidence.max_obstacle_extension_m);
      for (std::size_t f : floorFacesWhere(map, [](const Eigen::Vector3d& c) { return std::abs(c.y()) < 1.5; })) {
        const double x = std::abs(centroid(map, f).x());
        const FaceLayers& l = map.layers[f];
        if (x < r - 0.04) {
          ++near;
          EXPECT_EQ(l.face_class == FaceClass::kLethal, blocks)
              << "wall " << wall_m << " m, steiner " << steiner_wall << ", face " << x << " m from it";
          if (blocks) {
            // The wall counts as a step of its height inside the body (capped at the robot's height).
            EXPECT_NEAR(l.step_m, std::min(wall_m, profile.min_clearance_m), 1e-5) << "wall " << wall_m << " m";
          }
        } else if (x > r + 0.04 && x < 2.0) {
          // A measured wall of four points (4 m triangles) may extend: the footprint keeps clear of
          // that margin too (uncertain there); an invented one only makes the faces it meets uncertain.
          const double margin = blocks ? extension : 0.0;
          if (x > r + margin + 0.04) {
            ++far;
            EXPECT_EQ(l.face_class, FaceClass::kFree) << "wall " << wall_m << " m, face " << x << " m from it";
          } else if (x < r + margin - 0.04) {
            ++beside;
            EXPECT_EQ(l.face_class, FaceClass::kUncertain) << "wall " << wall_m << " m, face " << x << " m from it";
          }
        }
      }
      EXPECT_GT(near, 20u);
      EXPECT_GT(far, 20u);
      if (blocks) EXPECT_GT(beside, 20u);
    }
  }
}

TEST(LayersTest, CarBetweenTwoWallsFitsOnlyAlongThem) {
  // Thin 2 m walls along y = +-w/2 over a floor that continues beyond them: in a 2.4 m corridor
  // the 4.8 x 1.8 m car fits only parallel to the walls, and only within 0.3 m of the middle; in
  // a 1.7 m corridor it fits nowhere. Beside the corridor (outside), it fits along the wall.
  // The walls' possible extension (EvidenceModel, tested in evidence_test.cpp) is off: this is
  // the body and heading logic alone.
  RobotProfile car = loadRobotProfile(kRobots / "car.yaml");
  car.evidence.obstacle_extension = 0;
  for (const double width : {2.4, 1.7}) {
    mesher::TriangleMesh mesh = test::heightFieldMesh(-12, 12, -6, 6, 0.2, [](double, double) { return 0.0; });
    test::appendMesh(mesh, test::thinWall(-10, 0.5 * width, 10, 0.5 * width, 0, 2));
    test::appendMesh(mesh, test::thinWall(-10, -0.5 * width, 10, -0.5 * width, 0, 2));
    const LayeredMesh map = compute(mesh, car);
    std::size_t middle = 0, off_middle = 0, outside = 0;
    for (std::size_t f : floorFacesWhere(map, [](const Eigen::Vector3d& c) { return std::abs(c.x()) < 3; })) {
      const double y = std::abs(centroid(map, f).y());
      const FaceLayers& l = map.layers[f];
      if (y < 0.5 * width - 0.9 - 0.05) {
        ++middle;
        EXPECT_EQ(l.face_class, FaceClass::kFree) << "corridor " << width << " m, y " << y << ": fits along it";
        EXPECT_EQ(l.contact_best, 1.0f);
        EXPECT_LT(l.step_m, 1e-6) << "the heading that fits has no step";
      } else if (y > 0.5 * width - 0.9 + 0.05 && y < 0.5 * width - 0.05) {
        ++off_middle;
        EXPECT_EQ(l.face_class, FaceClass::kLethal) << "corridor " << width << " m, y " << y;
      } else if (y > 0.5 * width + 0.95 && y < 3.3) {
        ++outside;
        EXPECT_EQ(l.face_class, FaceClass::kFree) << "corridor " << width << " m, outside at y " << y;
      }
    }
    EXPECT_EQ(middle > 0, width > 2.0);
    EXPECT_GT(off_middle, 10u);
    EXPECT_GT(outside, 10u);
  }
}

TEST(LayersTest, LargeFloorFaceBesideAPostIsNotLethalAsAWhole) {
  // A 4 x 4 m floor of two triangles (8 m^2 each, far larger than the 0.36 m^2 disc) and a 1 m
  // post 0.2 m from one triangle's centroid: a disc centred at the centroid collides, but not at
  // most points of the triangle, so the triangle is not lethal as a whole (it was before
  // 2026-12-01, judged at its centroid only). Walled in on all four sides at 0.3 m from the
  // centroid, the disc collides at every point: lethal. A finely meshed floor around the same
  // post stays lethal within the disc's radius of it.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const Eigen::Vector2d c(-2.0 / 3, -2.0 / 3);  // the centroid of the triangle (-2,-2) (2,-2) (-2,2)
  for (const bool caged : {false, true}) {
    mesher::TriangleMesh mesh;
    mesh.vertices = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
    mesh.faces = {{0, 1, 3}, {1, 2, 3}};
    if (caged) {
      const double h = 0.3;
      test::appendMesh(mesh, test::thinWall(c.x() - h, c.y() - h, c.x() + h, c.y() - h, 0, 1));
      test::appendMesh(mesh, test::thinWall(c.x() + h, c.y() - h, c.x() + h, c.y() + h, 0, 1));
      test::appendMesh(mesh, test::thinWall(c.x() + h, c.y() + h, c.x() - h, c.y() + h, 0, 1));
      test::appendMesh(mesh, test::thinWall(c.x() - h, c.y() + h, c.x() - h, c.y() - h, 0, 1));
    } else {
      test::appendMesh(mesh, test::thinWall(c.x() + 0.15, c.y(), c.x() + 0.25, c.y(), 0, 1));
    }
    const LayeredMesh map = compute(mesh, profile);
    const auto big = floorFacesWhere(map, [&](const Eigen::Vector3d& p) { return (p.head<2>() - c).norm() < 1e-9; });
    ASSERT_EQ(big.size(), 1u);
    const FaceLayers& l = map.layers[big[0]];
    // Not caged: the post blocks the disc at the centroid only, so the face is not lethal as a
    // whole, but not free either (a robot there may meet the post): uncertain.
    EXPECT_EQ(l.face_class, caged ? FaceClass::kLethal : FaceClass::kUncertain) << "caged " << caged;
    if (caged) {
      EXPECT_NEAR(l.step_m, std::min(1.0, profile.min_clearance_m), 1e-5) << "the walls' top, capped at the body";
    } else {
      EXPECT_LT(l.step_m, 1e-6) << "the post does not count";
    }
  }
  {
    // The car (4.8 x 1.8 m, 8.64 m^2) on a 15 x 15 m floor of two triangles (112.5 m^2 each): a
    // post 0.3 m from a centroid blocks every heading there, not at most of the triangle's points.
    mesher::TriangleMesh mesh;
    mesh.vertices = {{-7.5, -7.5, 0}, {7.5, -7.5, 0}, {7.5, 7.5, 0}, {-7.5, 7.5, 0}};
    mesh.faces = {{0, 1, 3}, {1, 2, 3}};
    const Eigen::Vector2d cc(-2.5, -2.5);
    test::appendMesh(mesh, test::thinWall(cc.x() + 0.25, cc.y(), cc.x() + 0.35, cc.y(), 0, 1));
    const LayeredMesh map = compute(mesh, loadRobotProfile(kRobots / "car.yaml"));
    const auto big = floorFacesWhere(map, [&](const Eigen::Vector3d& p) { return (p.head<2>() - cc).norm() < 1e-9; });
    ASSERT_EQ(big.size(), 1u);
    EXPECT_EQ(map.layers[big[0]].face_class, FaceClass::kUncertain) << "car";
  }
  mesher::TriangleMesh fine = test::heightFieldMesh(-2, 2, -2, 2, 0.1, [](double, double) { return 0.0; });
  test::appendMesh(fine, test::thinWall(c.x() + 0.15, c.y(), c.x() + 0.25, c.y(), 0, 1));
  const LayeredMesh map = compute(fine, profile);
  const Eigen::Vector2d post(c.x() + 0.2, c.y());
  std::size_t near = 0;
  for (std::size_t f : floorFacesWhere(map, [&](const Eigen::Vector3d& p) { return (p.head<2>() - post).norm() < r - 0.1; })) {
    ++near;
    EXPECT_EQ(map.layers[f].face_class, FaceClass::kLethal);
  }
  EXPECT_GT(near, 10u);
}

TEST(LayersTest, SamplesOnSteinerFacesAreNoData) {
  // A measured floor beside an unmeasured (Steiner) patch whose closing faces rise to a 0.87 m
  // lattice vertex (the mesher's "tent"): footprint samples landing on the patch count neither as
  // support nor as a step, so the measured floor around it costs nothing (until 2026-12-01 it read
  // the tent as a 0.35-0.4 m step). Where the footprint meets the tent within the body's height,
  // the space there was never observed free: uncertain, never lethal.
  const RobotProfile profile = smallWheeled();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  mesh.is_steiner.assign(mesh.vertices.size(), 0);
  const auto inPatch = [](const Eigen::Vector3d& v) { return v.x() > -1e-9 && std::abs(v.y()) < 1.0 + 1e-9; };
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!inPatch(mesh.vertices[v])) continue;
    mesh.is_steiner[v] = 1;
    // A tent: 0.87 m at (1, 0), down to the floor along the patch's border.
    const Eigen::Vector3d& p = mesh.vertices[v];
    mesh.vertices[v].z() = 0.87 * std::max(0.0, 1.0 - std::max(std::abs(p.x() - 1.0), std::abs(p.y())));
  }
  const LayeredMesh map = compute(mesh, profile);
  const double r = profile.footprintCircumradiusM();
  std::size_t beside = 0, clear = 0;
  for (std::size_t f : floorFacesWhere(map, [](const Eigen::Vector3d& c) {
         return c.x() < -0.05 && c.x() > -1.0 && std::abs(c.y()) < 0.8;
       })) {
    const FaceLayers& l = map.layers[f];
    if (l.face_class == FaceClass::kUnknown) continue;  // touching the patch
    ++beside;
    EXPECT_NE(l.face_class, FaceClass::kLethal) << "at x = " << centroid(map, f).x();
    EXPECT_LT(l.step_m, 1e-6);
    EXPECT_EQ(l.contact, 1.0f);
    if (centroid(map, f).x() < -r - 0.02) {
      ++clear;
      EXPECT_EQ(l.face_class, FaceClass::kFree) << "at x = " << centroid(map, f).x();
      EXPECT_LT(l.cost, 0.05f);
    }
  }
  EXPECT_GT(beside, 50u);
  EXPECT_GT(clear, 30u);
}

/// Brute-force geodesic distances: Dijkstra over faces sharing an edge, from the lethal faces.
std::vector<double> referenceDistances(const LayeredMesh& map) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> edges;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = map.mesh.faces[f][i], b = map.mesh.faces[f][(i + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  }
  std::vector<double> d(map.layers.size(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::size_t f = 0; f < d.size(); ++f) {
    if (map.layers[f].face_class == FaceClass::kLethal) queue.emplace(d[f] = 0.0, f);
  }
  while (!queue.empty()) {
    const auto [df, f] = queue.top();
    queue.pop();
    if (df > d[f]) continue;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = map.mesh.faces[f][i], b = map.mesh.faces[f][(i + 1) % 3];
      for (std::size_t g : edges[{std::min(a, b), std::max(a, b)}]) {
        const double nd = df + (centroid(map, f) - centroid(map, g)).norm();
        if (nd < d[g]) queue.emplace(d[g] = nd, g);
      }
    }
  }
  return d;
}

TEST(LayersTest, InflationDecaysWithGeodesicDistance) {
  RobotProfile profile = smallWheeled();
  profile.inflation_radius_m = 1.5;
  // A flat floor with a 1 m high block in the middle: its sides and top are lethal.
  const LayeredMesh map = compute(
      test::heightFieldMesh(-4, 4, -4, 4, 0.2, [](double x, double y) { return std::max(std::abs(x), std::abs(y)) < 0.5 ? 1.0 : 0.0; }),
      profile);
  const std::vector<double> reference = referenceDistances(map);
  std::size_t decaying = 0;
  for (std::size_t f = 0; f < map.layers.size(); ++f) {
    const FaceLayers& l = map.layers[f];
    if (reference[f] <= profile.inflation_radius_m) {
      ASSERT_NEAR(l.lethal_distance_m, reference[f], 1e-5) << "face " << f;
    } else {
      ASSERT_TRUE(std::isinf(l.lethal_distance_m)) << "face " << f << " reference " << reference[f];
    }
    const double to_border = 4.0 - centroid(map, f).head<2>().cwiseAbs().maxCoeff();
    if (l.face_class != FaceClass::kFree || to_border < 2.5) continue;
    const double d = l.lethal_distance_m;
    if (d <= profile.inscribed_radius_m) {
      EXPECT_EQ(l.cost, 1.0f);
    } else if (d <= profile.inflation_radius_m) {
      ++decaying;
      const double expected = std::exp(-profile.cost_scaling_factor * (d - profile.inscribed_radius_m));
      EXPECT_NEAR(l.cost, expected, 1e-5) << "flat floor: the inflation term dominates, at d = " << d;
    } else {
      EXPECT_LT(l.cost, 1e-6);
    }
  }
  EXPECT_GT(decaying, 50u);
}

}  // namespace
}  // namespace terramesh::traversability
