// The evidence behind each face and the uncertain class: what sparse maps get wrong (a slab edge
// interpolated into a ramp, an unobserved wall, the free end of a sparsely measured wall, a
// footprint over unknown ground) is never called free, and unobserved geometry is never lethal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "evidence_faces.h"
#include "test_support/traversability_scenes.h"
#include "traversability/layer_registry.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

TEST(EvidenceTest, EveryFaceCarriesItsEvidenceAndHeightBound) {
  const RobotProfile profile = smallWheeled();
  const EvidenceModel& m = profile.evidence;
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.5, [](double, double) { return 0.0; });
  mesh.is_steiner.assign(mesh.vertices.size(), 0);
  mesh.is_steiner[0] = 1;  // a corner vertex: the faces around it close the map
  // Faces with an odd index: no ray crossed the space in front of them.
  const auto faces = facesOf(mesh, 4, [](std::size_t f) { return f % 2 == 1; });
  const std::vector<FaceLayers> layers = layersOf(faces, profile);
  const double span = 0.5 * std::sqrt(2.0);  // the cells' diagonal is each triangle's longest horizontal edge
  std::size_t steiner = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const FaceLayers& l = layers[f];
    if (faces[f].touches_steiner) {
      ++steiner;
      EXPECT_EQ(l.evidence, Evidence::kInterpolated);
      EXPECT_TRUE(std::isinf(l.height_uncertainty_m));
      EXPECT_EQ(l.face_class, FaceClass::kUnknown);
      EXPECT_TRUE(l.reasons & reason::kClosingGeometry) << l.reasons;
    } else if (f % 2 == 1) {
      EXPECT_EQ(l.evidence, Evidence::kInterpolated);
      EXPECT_NEAR(l.height_uncertainty_m, m.point_noise_m + m.relief_per_m_unobserved * span, 1e-6);
    } else {
      EXPECT_EQ(l.evidence, Evidence::kMeasured);
      EXPECT_NEAR(l.height_uncertainty_m, m.point_noise_m + m.relief_per_m_observed * span, 1e-6);
    }
  }
  EXPECT_GT(steiner, 0u);
  // Seen by fewer rays than the profile asks: unknown, and why.
  RobotProfile demanding = profile;
  demanding.min_rays = 11;  // facesOf gives every face 10
  for (const FaceLayers& l : layersOf(faces, demanding)) {
    EXPECT_EQ(l.face_class, FaceClass::kUnknown);
    EXPECT_TRUE(l.reasons & reason::kFewRays) << l.reasons;
  }
  // Every vertex a driven-ground sample: driven evidence, with the mounting's uncertainty.
  const std::vector<FaceLayers> driven = layersOf(facesOf(mesh, 0, {}, 3), profile);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (faces[f].touches_steiner) continue;
    EXPECT_EQ(driven[f].evidence, Evidence::kDriven);
    EXPECT_FLOAT_EQ(driven[f].height_uncertainty_m, static_cast<float>(m.driven_uncertainty_m));
  }
}

TEST(EvidenceTest, SlabEdgeInterpolatedIntoARampIsUncertainNeverFree) {
  // A 0.40 m slab edge (step limit 0.18 m) at x = 0, seen only at vertices 1.5 m apart: the faces
  // spanning the edge rise 0.4 m in 1.5 m, a 15 degree "ramp" under the robot's 20 degree limit.
  const RobotProfile profile = smallWheeled();
  const auto slab = [](double x, double) { return x > 0.1 ? 0.4 : 0.0; };
  const mesher::TriangleMesh sparse = test::heightFieldMesh(-6, 6, -6, 6, 1.5, slab);
  const auto spans_edge = [&](std::size_t f) {
    const double x = centroid(sparse, f).x();
    return x > 0 && x < 1.5 && std::abs(centroid(sparse, f).y()) < 4;
  };
  // Nobody observed the spans across the edge: a step may hide there.
  const auto faces = facesOf(sparse, 4, spans_edge);
  const std::vector<FaceLayers> layers = layersOf(faces, profile);
  std::size_t judged = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!spans_edge(f)) continue;
    ++judged;
    EXPECT_LT(layers[f].slope_deg, profile.max_slope_deg) << "the interpolated ramp looks drivable";
    EXPECT_EQ(layers[f].evidence, Evidence::kInterpolated);
    EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << "face " << f;
    EXPECT_TRUE(layers[f].reasons & reason::kPossibleStep) << "face " << f << ": reasons " << layers[f].reasons;
    EXPECT_FLOAT_EQ(layers[f].cost, static_cast<float>(profile.evidence.uncertain_cost));
  }
  EXPECT_GT(judged, 4u);
  // With rays over them too: no measured point beyond the spans confirms their plane, so they are
  // still a possible step.
  const std::vector<FaceLayers> observed = layersOf(facesOf(sparse, 4), profile);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!spans_edge(f)) continue;
    EXPECT_EQ(observed[f].evidence, Evidence::kMeasured);
    EXPECT_EQ(observed[f].face_class, FaceClass::kUncertain) << "observed face " << f;
  }
  // Measured densely, the same edge is a step: lethal where the footprint straddles it.
  const mesher::TriangleMesh dense = test::heightFieldMesh(-3, 3, -3, 3, 0.1, slab);
  const std::vector<FaceLayers> measured = layersOf(facesOf(dense, 4), profile);
  std::size_t lethal = 0;
  for (std::size_t f = 0; f < dense.faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(dense, f);
    if (std::abs(c.x() - 0.05) < 0.1 && std::abs(c.y()) < 2) {
      EXPECT_NE(measured[f].face_class, FaceClass::kFree) << "at x = " << c.x();
      lethal += measured[f].face_class == FaceClass::kLethal;
      // A lethal face says which lethal rule holds, and only lethal rules.
      if (measured[f].face_class == FaceClass::kLethal) {
        EXPECT_NE(measured[f].reasons & (reason::kTooSteep | reason::kNoHeadingFits), 0) << "at x = " << c.x();
        EXPECT_EQ(measured[f].reasons & ~(reason::kTooSteep | reason::kNoHeadingFits | reason::kLowClearance), 0);
      }
    }
  }
  EXPECT_GT(lethal, 10u);
}

TEST(EvidenceTest, OnDrivenGroundBridgesAreContradictedButWallsPlacedLaterCount) {
  // A driven strip (every vertex a driven sample) for |y| < 1 and measured floor beyond. A slanted
  // face from the strip's edge up to 1 m at y = 2.5 (the mesh bridging the road to a car roof)
  // passes through the body volume the robot swept: contradicted on the strip. A vertical 1 m wall
  // across the strip (an obstacle placed later) still blocks the robot there.
  const RobotProfile profile = smallWheeled();
  for (const bool wall : {false, true}) {
    mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
    const std::size_t floor_faces = mesh.faces.size();
    mesher::TriangleMesh bridge;
    bridge.vertices = {{-3, 0.2, 0}, {3, 0.2, 0}, {3, 2.5, 1.0}, {-3, 2.5, 1.0}};
    bridge.faces = {{0, 1, 2}, {0, 2, 3}};
    test::appendMesh(mesh, bridge);
    // The later wall as its points show it: 0.25 m tiles (on driven ground, a face supports an
    // obstacle only near its vertices: evidence.obstacle_support_m).
    for (double y = -1.0; wall && y < 1.0 - 1e-9; y += 0.25) {
      for (double z = 0.0; z < 1.0 - 1e-9; z += 0.25) test::appendMesh(mesh, test::thinWall(1.0, y, 1.0, y + 0.25, z, z + 0.25));
    }
    std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
    for (std::size_t f = 0; f < floor_faces; ++f) {
      bool on_strip = true;
      for (const auto& p : faces[f].positions_W) on_strip = on_strip && std::abs(p.y()) <= 1.0 + 1e-9;
      faces[f].driven_vertices = on_strip ? 3 : 0;
    }
    faces[floor_faces].driven_vertices = 2;  // the bridge is anchored on the strip's samples
    faces[floor_faces + 1].driven_vertices = 1;
    const std::vector<FaceLayers> layers = layersOf(faces, profile);
    std::size_t strip = 0, blocked = 0;
    for (std::size_t f = 0; f < floor_faces; ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      if (faces[f].driven_vertices != 3 || c.y() < 0 || c.y() > 0.5 || std::abs(c.x()) > 2.5) continue;
      EXPECT_EQ(layers[f].evidence, Evidence::kDriven);
      if (wall && std::abs(c.x() - 1.0) < 0.2) {
        ++blocked;
        EXPECT_EQ(layers[f].face_class, FaceClass::kLethal) << "beside the later wall at x " << c.x();
      } else if (!wall || std::abs(c.x() - 1.0) > profile.footprintCircumradiusM() + 0.55) {  // past its extension
        ++strip;
        EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "wall " << wall << " at (" << c.x() << ", " << c.y() << ")";
      }
    }
    EXPECT_GT(strip, 50u);
    if (wall) {
      EXPECT_GT(blocked, 10u);
    }
    // The bridge itself, steep and on driven samples: a span the drive contradicts and no
    // observation supports, so interpolated and uncertain (a guessed wall), not lethal by itself.
    for (const std::size_t f : {floor_faces, floor_faces + 1}) {
      EXPECT_EQ(layers[f].evidence, Evidence::kInterpolated) << f;
      EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << f;
      EXPECT_TRUE(layers[f].reasons & reason::kGuessedWall) << layers[f].reasons;
    }
    // The later wall's own faces (SLAM points only) are measured and lethal.
    for (std::size_t f = floor_faces + 2; wall && f < faces.size(); ++f) {
      EXPECT_EQ(layers[f].evidence, Evidence::kMeasured) << f;
      EXPECT_EQ(layers[f].face_class, FaceClass::kLethal) << f;
    }
  }
}

TEST(EvidenceTest, ABridgeFromTheUndersideOfADrivenDeckIsContradictedToo) {
  // A driven strip on a deck (|y| < 0.5, z = 0) whose undersides lie 0.1 m below it, and measured
  // deck beyond. The mesh bridges the underside at the strip's edge to a point 1 m up at y = 2.5
  // (the deck's wall, a parked car): a slanted face whose only measured vertex is that point. The
  // drive put its other vertices there, so the span is no measured obstacle: a guessed wall
  // (uncertain, never free), and the strip beside it stays free, up to its edge.
  const RobotProfile profile = smallWheeled();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  mesher::TriangleMesh bridge;
  bridge.vertices = {{-3, 0.5, -0.1}, {3, 0.5, -0.1}, {3, 2.5, 1.0}, {-3, 2.5, 1.0}};
  bridge.faces = {{0, 1, 2}, {0, 2, 3}};
  test::appendMesh(mesh, bridge);
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  for (std::size_t f = 0; f < floor_faces; ++f) {
    bool on_strip = true;
    for (const auto& p : faces[f].positions_W) on_strip = on_strip && std::abs(p.y()) <= 0.5 + 1e-9;
    faces[f].driven_vertices = on_strip ? 3 : 0;
  }
  faces[floor_faces].underside_vertices = 2;
  faces[floor_faces + 1].underside_vertices = 1;
  const std::vector<FaceLayers> layers = layersOf(faces, profile);
  for (const std::size_t f : {floor_faces, floor_faces + 1}) {
    EXPECT_EQ(layers[f].evidence, Evidence::kInterpolated) << f;
    EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << f;
    EXPECT_TRUE(layers[f].reasons & reason::kGuessedWall) << layers[f].reasons;
  }
  std::size_t strip = 0;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (faces[f].driven_vertices != 3 || std::abs(c.x()) > 2.5) continue;
    ++strip;
    EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "at (" << c.x() << ", " << c.y() << ")";
  }
  EXPECT_GT(strip, 100u);
}

TEST(EvidenceTest, OnDrivenGroundOnlyTheSupportedPartsOfALongFaceAreObstacles) {
  // A 6 m tall face rising steeply (73 deg) from y = 0.7 and leaning over the strip (the mesh
  // spanning from a point at the road's edge to a facade point metres up): its part inside the
  // body of a robot at y ~ 0.3 is 3 m from every vertex. Over measured floor it is an obstacle;
  // over driven floor the robot's body swept that volume and nothing measured supports it there.
  // Tiles of it 0.25 m across (points all along it) block the strip again, and so does the long
  // face when its vertices are taken to support 100 m.
  for (const int variant : {0, 1, 2, 3}) {  // 0: measured floor, 1: driven, 2: driven, tiled, 3: driven, 100 m
    RobotProfile profile = smallWheeled();
    if (variant == 3) profile.evidence.obstacle_support_m = 100;
    mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
    const std::size_t floor_faces = mesh.faces.size();
    const auto at = [](double x, double h) { return Eigen::Vector3d(x, 0.7 - 0.3 * h, h); };
    mesher::TriangleMesh lean;
    if (variant != 2) {
      lean.vertices = {at(-3, 0), at(3, 0), at(0, 6)};
      lean.faces = {{0, 1, 2}};
    } else {
      for (double x = -3; x < 3 - 1e-9; x += 0.25) {
        for (double h = 0; h < 1.0 - 1e-9; h += 0.25) {
          const auto base = static_cast<std::uint32_t>(lean.vertices.size());
          for (const Eigen::Vector3d& p : {at(x, h), at(x + 0.25, h), at(x + 0.25, h + 0.25), at(x, h + 0.25)}) {
            lean.vertices.push_back(p);
          }
          lean.faces.push_back({base, base + 1, base + 2});
          lean.faces.push_back({base, base + 2, base + 3});
        }
      }
    }
    test::appendMesh(mesh, lean);
    std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
    for (std::size_t f = 0; f < floor_faces && variant > 0; ++f) {
      bool on_strip = true;
      for (const auto& p : faces[f].positions_W) on_strip = on_strip && std::abs(p.y()) <= 1.0 + 1e-9;
      faces[f].driven_vertices = on_strip ? 3 : 0;
    }
    const std::vector<FaceLayers> layers = layersOf(faces, profile);
    std::size_t judged = 0;
    for (std::size_t f = 0; f < floor_faces; ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      if (c.y() < 0.25 || c.y() > 0.4 || std::abs(c.x()) > 1.0) continue;
      ++judged;
      if (variant == 1) {
        EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "driven, at (" << c.x() << ", " << c.y() << ")";
      } else {
        EXPECT_NE(layers[f].face_class, FaceClass::kFree) << "variant " << variant << " at (" << c.x() << ", " << c.y() << ")";
      }
    }
    EXPECT_GT(judged, 20u);
  }
}

TEST(EvidenceTest, OnDrivenGroundAVertexBesideTheStripSupportsNothingInsideIt) {
  // A driven strip (|y| <= 0.34, the drive along y = 0) under a measured face that faces down at
  // 45 degrees: from a point 0.45 m up beside the strip (y 0.45, 0.11 m beyond its side: a SLAM
  // outlier, or the top of a rock) to floor points on the centre line. The corner that point
  // supports reaches y 0.19, into the strip. The robot's body swept the strip with that point
  // already there, so only the part beyond the side counts: faces just across the centre line
  // (their footprint reaches y 0.19-0.31) are free, those nearer the side are not. A point
  // standing inside the strip (y 0.25, placed later) supports its corner there whole.
  const RobotProfile profile = smallWheeled();
  for (const double point_y : {0.45, 0.25}) {
    mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
    const std::size_t floor_faces = mesh.faces.size();
    mesher::TriangleMesh lid;
    lid.vertices = {{0, point_y, 0.45}, {0.6, 0, 0}, {-0.6, 0, 0}};  // facing down
    lid.faces = {{0, 1, 2}};
    test::appendMesh(mesh, lid);
    std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
    driveAlongX(faces, floor_faces, 0.34);
    const std::map<mesher::FaceKey, FaceLayers> layers = layersByKey(faces, profile, basesAlongX(mesh));
    EXPECT_EQ(layers.at(faces[floor_faces].key).evidence, Evidence::kMeasured);
    std::size_t far_half = 0, near_side = 0;
    for (std::size_t f = 0; f < floor_faces; ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      if (faces[f].driven_vertices != 3 || std::abs(c.x()) > 0.3) continue;
      const FaceLayers& got = layers.at(faces[f].key);
      if (c.y() > -0.15 && c.y() < -0.03) {
        ++far_half;
        EXPECT_EQ(got.face_class == FaceClass::kFree, point_y > 0.34)
            << "point at y " << point_y << ", face at (" << c.x() << ", " << c.y() << "), reasons " << got.reasons;
      } else if (c.y() > 0.1) {
        ++near_side;
        EXPECT_NE(got.face_class, FaceClass::kFree)
            << "point at y " << point_y << ", face at (" << c.x() << ", " << c.y() << ")";
      }
    }
    EXPECT_GT(far_half, 8u);
    EXPECT_GT(near_side, 8u);
  }
}

TEST(EvidenceTest, OnDrivenGroundSlantedFacesCountBeyondTheStripTheBodySwept) {
  // A driven strip (|y| <= 0.3, the drive along y = 0) and two measured slanted faces: one
  // floating over the strip in the body's volume (the robot drove through it: contradicted), one
  // rising at 45 degrees from y = 0.3, facing the strip (its part inside the body lies at y
  // 0.48-0.8, beyond the strip's side at the robot's radius). Without the drive's poses the drive
  // contradicts both wholly; with them, the faces of the strip whose footprint reaches beyond its
  // side to the second face are not free,
  // those on the far half still are. Incrementally the same as a full computation, also when
  // driven ground under the floating face goes.
  const RobotProfile profile = smallWheeled();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  mesher::TriangleMesh slanted;
  slanted.vertices = {{-3, -0.1, 0.3}, {3, -0.1, 0.3}, {3, 0.1, 0.45}, {-3, 0.1, 0.45},
                      {-3, 0.3, 0.0}, {3, 0.3, 0.0}, {3, 1.3, 1.0}, {-3, 1.3, 1.0}};
  slanted.faces = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  test::appendMesh(mesh, slanted);
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  driveAlongX(faces, floor_faces, 0.3);
  const DrivePoseLookup poses = basesAlongX(mesh);
  const auto classes = [&](const std::vector<mesher::SurfaceFace>& input, bool with_poses) {
    return layersByKey(input, profile, with_poses ? poses : DrivePoseLookup{});
  };
  for (const bool with_poses : {false, true}) {
    const std::map<mesher::FaceKey, FaceLayers> layers = classes(faces, with_poses);
    std::size_t far_half = 0, near_side = 0;
    for (std::size_t f = 0; f < floor_faces; ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      if (faces[f].driven_vertices != 3 || std::abs(c.x()) > 2.0) continue;
      const FaceClass got = layers.at(faces[f].key).face_class;
      if (c.y() < 0) {
        ++far_half;
        EXPECT_EQ(got, FaceClass::kFree) << "poses " << with_poses << " at (" << c.x() << ", " << c.y() << ")";
      } else if (c.y() > 0.2) {
        ++near_side;
        EXPECT_EQ(got == FaceClass::kFree, !with_poses) << "poses " << with_poses << " at (" << c.x() << ", " << c.y() << ")";
      }
    }
    EXPECT_GT(far_half, 200u);
    EXPECT_GT(near_side, 50u);
  }
  // The strip ends at x = 2.5 (its driven ground beyond goes): the faces whose footprint reaches
  // past the end meet the floating face there.
  mesher::SurfaceDelta strip_end{0, 0, true, {}, {}, {}};
  std::vector<mesher::SurfaceFace> rest;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (f < floor_faces && faces[f].driven_vertices == 3 && c.x() > 2.5) {
      strip_end.removed.push_back(faces[f].key);
    } else {
      rest.push_back(faces[f]);
    }
  }
  ASSERT_EQ(strip_end.removed.size(), 5u * 6u * 2u);
  TraversabilityMap map(profile, MapFrame{});
  map.setDrivePoses(poses);
  map.reset(faces);
  map.apply(strip_end, {});
  const std::map<mesher::FaceKey, FaceLayers> full = classes(rest, true);
  const LayeredMesh snapshot = map.snapshot();
  ASSERT_EQ(snapshot.layers.size(), full.size());
  std::size_t changed = 0;
  const std::map<mesher::FaceKey, FaceLayers> before = classes(faces, true);
  for (std::size_t f = 0; f < snapshot.layers.size(); ++f) {
    const FaceLayers& want = full.at(snapshot.face_keys[f]);
    EXPECT_EQ(snapshot.layers[f].face_class, want.face_class) << "face " << f;
    EXPECT_EQ(snapshot.layers[f].step_m, want.step_m) << "face " << f;
    changed += before.at(snapshot.face_keys[f]).face_class != want.face_class ? 1 : 0;
  }
  EXPECT_GT(changed, 0u) << "the strip's end changes some class (else the incremental check tests nothing)";
}

TEST(EvidenceTest, OnDrivenGroundTheStripEndsAlongTheDriveNotAtItsSides) {
  // The driven faces need not reach the strip's sides (|y| <= 0.34, the robot's radius): here they
  // cover |y| <= 0.1, the mesh's own faces the rest, as where a SLAM point on the road holds them.
  // A measured face rising at 45 degrees from y = -0.3 passes through the body inside the strip
  // (0.18-0.5 m up at y -0.12 to 0.2) and no higher than the clearance beyond it: the robot drove
  // through it. Whether the strip is over driven ground is judged along the drive (abreast of the
  // part's corners, on the centre line), so the face is contradicted and the strip stays free;
  // where the drive ends (x > 2.5 here), the same face blocks (and within a footprint and the
  // extension of that end, x > 1.5).
  const RobotProfile profile = smallWheeled();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  mesher::TriangleMesh slanted;
  slanted.vertices = {{-3, -0.3, 0.0}, {3, -0.3, 0.0}, {3, 0.9, 1.2}, {-3, 0.9, 1.2}};
  slanted.faces = {{0, 1, 2}, {0, 2, 3}};
  test::appendMesh(mesh, slanted);
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  driveAlongX(faces, floor_faces, 0.1);
  for (std::size_t f = 0; f < floor_faces; ++f) {
    if (centroid(mesh, f).x() > 2.5) faces[f].driven_vertices = 0;
  }
  const std::map<mesher::FaceKey, FaceLayers> layers = layersByKey(faces, profile, basesAlongX(mesh));
  std::size_t on_drive = 0, past_end = 0;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (std::abs(c.y()) > 0.1) continue;
    const FaceClass got = layers.at(faces[f].key).face_class;
    if (std::abs(c.x()) < 1.5 && faces[f].driven_vertices == 3) {
      ++on_drive;
      EXPECT_EQ(got, FaceClass::kFree) << "at (" << c.x() << ", " << c.y() << ")";
    } else if (c.x() > 2.6 && c.x() < 2.9) {
      ++past_end;
      EXPECT_NE(got, FaceClass::kFree) << "at (" << c.x() << ", " << c.y() << ")";
    }
  }
  EXPECT_GT(on_drive, 100u);
  EXPECT_GT(past_end, 5u);
}

TEST(EvidenceTest, AnUnobservedWallIsUncertainNotLethal) {
  // A 2 m wall over a floor: measured, it is lethal and so is the floor beside it; with no ray
  // through the space in front of its faces it is only a possible wall: uncertain, both.
  const RobotProfile profile = smallWheeled();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = mesh.faces.size();
  test::appendMesh(mesh, test::thinWall(0, -2, 0, 2, 0, 2.0));
  const auto wall = [&](std::size_t f) { return f >= floor_faces; };
  const auto near_floor = [&](std::size_t f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    return !wall(f) && std::abs(c.x()) < 0.2 && std::abs(c.y()) < 1.5;
  };
  for (const bool observed : {true, false}) {
    const std::vector<FaceLayers> layers =
        layersOf(facesOf(mesh, 4, [&](std::size_t f) { return !observed && wall(f); }), profile);
    std::size_t walls = 0, floors = 0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const FaceClass want = observed ? FaceClass::kLethal : FaceClass::kUncertain;
      if (wall(f)) {
        ++walls;
        EXPECT_EQ(layers[f].face_class, want) << "wall face, observed " << observed;
        EXPECT_TRUE(layers[f].reasons & (observed ? reason::kTooSteep : reason::kGuessedWall))
            << "wall face, observed " << observed << ": reasons " << layers[f].reasons;
      } else if (near_floor(f)) {
        ++floors;
        EXPECT_EQ(layers[f].face_class, want) << "floor beside the wall, observed " << observed;
        if (!observed) {
          EXPECT_TRUE(layers[f].reasons & reason::kPossibleObstacle) << layers[f].reasons;
        }
      }
    }
    EXPECT_EQ(walls, 4u);
    EXPECT_GT(floors, 20u);
  }
}

/// The class of the floor faces whose centroid lies within 0.025 m of (x, y) (each axis).
TEST(EvidenceTest, TheFreeEndOfASparselyMeasuredWallKeepsTheFootprintClear) {
  // A measured 1.5 m wall along x = 0 for y < 0 ending at y = 0. As two triangles (four points:
  // sparse) it may extend up to max_obstacle_extension_m beyond its end: the floor there is
  // uncertain for a robot that would reach it, free beyond. Measured as many short triangles
  // (0.1 m apart), the margin is small: free right beyond the footprint.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  const double cap = profile.evidence.max_obstacle_extension_m;
  for (const bool sparse : {true, false}) {
    mesher::TriangleMesh mesh = test::heightFieldMesh(-4, 4, -6, 4, 0.1, [](double, double) { return 0.0; });
    const std::size_t floor_faces = mesh.faces.size();
    if (sparse) {
      test::appendMesh(mesh, test::thinWall(0, -5, 0, 0, 0, 1.5));
    } else {
      for (double y = -5; y < -1e-9; y += 0.1) test::appendMesh(mesh, test::thinWall(0, y, 0, y + 0.1, 0, 1.5));
    }
    const std::vector<FaceLayers> layers = layersOf(facesOf(mesh, 4), profile);
    ASSERT_GT(cap, 0.2);
    const double margin = sparse ? cap : profile.evidence.obstacle_extension * 0.1;
    // Beyond the free end, on the wall's line: within the footprint of the end it collides.
    const std::vector<FaceClass> at_end = floorClassesAt(mesh, floor_faces, layers, 0.05, 0.5 * r);
    EXPECT_FALSE(at_end.empty());
    for (FaceClass c : at_end) EXPECT_EQ(c, FaceClass::kLethal) << "sparse " << sparse;
    // Where only the sparse wall's possible extension reaches.
    const double between = r + 0.1 + 0.5 * (cap - 0.1);
    const std::vector<FaceClass> middle = floorClassesAt(mesh, floor_faces, layers, 0.05, between);
    EXPECT_FALSE(middle.empty());
    for (FaceClass c : middle) {
      EXPECT_EQ(c, sparse ? FaceClass::kUncertain : FaceClass::kFree) << "sparse " << sparse << " at y " << between;
    }
    if (sparse) {
      for (std::size_t f = 0; f < floor_faces; ++f) {
        const Eigen::Vector3d c = centroid(mesh, f);
        if (std::abs(c.x() - 0.05) < 0.025 && std::abs(c.y() - between) < 0.025) {
          EXPECT_EQ(layers[f].reasons, reason::kObstacleExtension) << "only the wall's possible extension";
        }
      }
    }
    const double beyond = r + margin + 0.1;
    const std::vector<FaceClass> far = floorClassesAt(mesh, floor_faces, layers, 0.05, beyond);
    EXPECT_FALSE(far.empty());
    for (FaceClass c : far) EXPECT_EQ(c, FaceClass::kFree) << "sparse " << sparse << " at y " << beyond;
  }
}

TEST(EvidenceTest, AFootprintOverTooMuchUnknownGroundIsUncertain) {
  // A measured floor for x < 0 and closing geometry for x > 0: a robot centred 0.1 m from the
  // boundary has a third of its footprint over ground nobody measured. As reconstructed, the known
  // part supports it; in the worst case the unknown part does not (min_support 0.7).
  const RobotProfile profile = smallWheeled();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -3, 3, 0.1, [](double, double) { return 0.0; });
  mesh.is_steiner.assign(mesh.vertices.size(), 0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) mesh.is_steiner[v] = mesh.vertices[v].x() > 1e-9;
  const std::vector<FaceLayers> layers = layersOf(facesOf(mesh, 4), profile);
  std::size_t near = 0, far = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (std::abs(c.y()) > 2 || layers[f].face_class == FaceClass::kUnknown) continue;
    if (c.x() > -0.12) {
      ++near;
      EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << "at x " << c.x();
      EXPECT_TRUE(layers[f].reasons & reason::kWorstCaseRelief) << "at x " << c.x() << ": " << layers[f].reasons;
      EXPECT_GE(layers[f].contact, static_cast<float>(profile.min_support)) << "the known part supports it";
    } else if (c.x() < -profile.footprintCircumradiusM() - 0.05 && c.x() > -2.5) {
      ++far;
      EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "at x " << c.x();
    }
  }
  EXPECT_GT(near, 20u);
  EXPECT_GT(far, 100u);
}

TEST(EvidenceTest, AFootprintThatReachesAPossibleStepIsUncertain) {
  // Dense floor at 0 for x < 0 and at 0.4 m for x > 1.5, joined only by faces nobody observed
  // that span the 1.5 m between (a 0.4 m step, limit 0.18 m, may stand anywhere on them). A robot
  // centred up to its radius before the span, on measured floor, may meet that step: uncertain,
  // although the interpolated heights it samples there rise less than a step. Farther away: free.
  const RobotProfile profile = smallWheeled();
  const double r = profile.footprintCircumradiusM();
  mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 0, -3, 3, 0.1, [](double, double) { return 0.0; });
  test::appendMesh(mesh, test::heightFieldMesh(1.5, 4.5, -3, 3, 0.1, [](double, double) { return 0.4; }));
  const std::size_t floor_faces = mesh.faces.size();
  mesher::TriangleMesh span;
  for (double y = -3; y < 3 - 1e-9; y += 0.5) {
    const auto base = static_cast<std::uint32_t>(span.vertices.size());
    span.vertices.insert(span.vertices.end(), {{0, y, 0}, {1.5, y, 0.4}, {1.5, y + 0.5, 0.4}, {0, y + 0.5, 0}});
    span.faces.push_back({base, base + 1, base + 2});
    span.faces.push_back({base, base + 2, base + 3});
  }
  test::appendMesh(mesh, span);
  const auto faces = facesOf(mesh, 4, [&](std::size_t f) { return f >= floor_faces; });
  const std::vector<FaceLayers> layers = layersOf(faces, profile);
  std::size_t near = 0, far = 0;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (std::abs(c.y()) > 2 || c.x() > 0) continue;
    if (c.x() > -r + 0.1) {
      ++near;
      EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << "at x " << c.x();
      EXPECT_EQ(layers[f].reasons, reason::kWorstCaseRelief) << "at x " << c.x();
    } else if (c.x() < -r - 0.1 && c.x() > -2.5) {
      ++far;
      EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "at x " << c.x();
    }
  }
  EXPECT_GT(near, 50u);
  EXPECT_GT(far, 500u);
  // The span itself: possible steps, uncertain, with the whole rise as their height bound.
  for (std::size_t f = floor_faces; f < mesh.faces.size(); ++f) {
    EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain);
    EXPECT_GE(layers[f].height_uncertainty_m, 0.4f);
  }
}

}  // namespace
}  // namespace terramesh::traversability
