// Layers on small hand-made meshes whose geometry is exact.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <queue>

#include "test_support/traversability_scenes.h"
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
