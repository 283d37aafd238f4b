// Where the drive began: a driven face's footprint that reaches past it over space nobody carved
// (no face above the sample, or the first one facing up: matter the rays never reached) is judged
// as over unknown ground, as a measured face's is over closing geometry: free while the part beyond
// is within what min_support tolerates, uncertain past that, never lethal. A drop the map shows
// (a floor deeper than the footprint's band under a lid over carved space) still fails its support.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <vector>

#include "evidence_faces.h"
#include "test_support/traversability_scenes.h"

namespace terramesh::traversability {
namespace {

/// The classes of the driven floor's faces (the first `floor_faces`) by centroid distance from
/// the drive's start (x = 0), in three groups.
struct StartClasses {
  std::vector<FaceClass> at_start;  ///< centroid x < 0.05: over 30 % of the disc lies beyond x = 0
  std::vector<FaceClass> near;      ///< 0.05 <= x < 0.2
  std::vector<FaceClass> inside;    ///< 0.2 <= x < 0.5: under 30 % of the disc lies beyond
};

StartClasses classesNearStart(const mesher::TriangleMesh& mesh, std::size_t floor_faces,
                              const std::map<mesher::FaceKey, FaceLayers>& layers,
                              const std::vector<mesher::SurfaceFace>& faces) {
  StartClasses out;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (std::abs(c.y()) > 0.5) continue;  // the strip's middle, away from its sides
    const FaceClass k = layers.at(faces[f].key).face_class;
    if (c.x() < 0.05) {
      out.at_start.push_back(k);
    } else if (c.x() < 0.2) {
      out.near.push_back(k);
    } else if (c.x() < 0.5) {
      out.inside.push_back(k);
    }
  }
  return out;
}

std::size_t countOf(const std::vector<FaceClass>& classes, FaceClass k) {
  return static_cast<std::size_t>(std::count(classes.begin(), classes.end(), k));
}

TEST(DriveStartTest, AFootprintOverUncarvedSpaceIsUnknownGroundButADropTheMapShowsIsNoSupport) {
  const RobotProfile profile = smallWheeled();  // a 0.34 m disc, min_support 0.7, band 0.5 m down
  // The drive's strip: a floor at z = 0 from x = 0 (where the drive began) to x = 3, every vertex
  // driven, the drive along y = 0. Behind it (x < 0): nothing, a drop, or a deck.
  const mesher::TriangleMesh strip_mesh =
      test::heightFieldMesh(0, 3, -1, 1, 0.1, [](double, double) { return 0.0; });
  const std::size_t floor_faces = strip_mesh.faces.size();
  // A carved drop: a measured floor 1 m lower (deeper than the footprint's band) under the lid
  // that closes the space the rays carved over it (facing down).
  mesher::TriangleMesh drop_mesh = strip_mesh;
  test::appendMesh(drop_mesh, test::heightFieldMesh(-2, -0.001, -1, 1, 0.1, [](double, double) { return -1.0; }));
  test::appendMesh(drop_mesh, test::horizontalQuad(-2, -0.001, -1, 1, 2.0, true));
  // An uncarved slab: only the top of a deck 3 m up (facing up) lies behind the start, as in a
  // garage whose first camera looked away from the floor behind it.
  mesher::TriangleMesh deck_mesh = strip_mesh;
  test::appendMesh(deck_mesh, test::horizontalQuad(-2, -0.001, -1, 1, 3.0, false));
  const auto facesWithDrive = [&](const mesher::TriangleMesh& mesh) {
    std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
    for (std::size_t f = 0; f < floor_faces; ++f) faces[f].driven_vertices = 3;
    return faces;
  };
  const std::vector<mesher::SurfaceFace> strip = facesWithDrive(strip_mesh);
  const std::vector<mesher::SurfaceFace> drop = facesWithDrive(drop_mesh);
  const std::vector<mesher::SurfaceFace> deck = facesWithDrive(deck_mesh);
  const DrivePoseLookup poses = basesAlongX(drop_mesh);

  // Beyond the map and under the deck: never lethal; uncertain where more than min_support
  // tolerates lies behind the start, free farther in.
  const std::map<mesher::FaceKey, FaceLayers> alone = layersByKey(strip, profile, poses);
  const std::map<mesher::FaceKey, FaceLayers> with_deck = layersByKey(deck, profile, poses);
  for (const auto* layers : {&alone, &with_deck}) {
    const StartClasses unseen = classesNearStart(strip_mesh, floor_faces, *layers, strip);
    ASSERT_GE(unseen.at_start.size(), 8u);
    ASSERT_GE(unseen.inside.size(), 8u);
    for (const std::vector<FaceClass>* group : {&unseen.at_start, &unseen.near, &unseen.inside}) {
      EXPECT_EQ(countOf(*group, FaceClass::kLethal), 0u);
    }
    EXPECT_EQ(countOf(unseen.at_start, FaceClass::kUncertain), unseen.at_start.size());
    EXPECT_EQ(countOf(unseen.inside, FaceClass::kFree), unseen.inside.size());
  }

  // Over the carved drop: the footprint at the start lacks support.
  const std::map<mesher::FaceKey, FaceLayers> with_drop = layersByKey(drop, profile, poses);
  const StartClasses dropped = classesNearStart(strip_mesh, floor_faces, with_drop, strip);
  EXPECT_EQ(countOf(dropped.at_start, FaceClass::kLethal), dropped.at_start.size());
  EXPECT_EQ(countOf(dropped.inside, FaceClass::kFree), dropped.inside.size());

  // Incrementally as in a full computation: the drop comes, then goes. Its faces lie outside the
  // strip's ground band, so only the columns they fill tell the strip's faces about them.
  TraversabilityMap map(profile, MapFrame{});
  map.setDrivePoses(poses);
  map.reset(strip);
  const std::vector<mesher::SurfaceFace> behind(drop.begin() + static_cast<std::ptrdiff_t>(floor_faces), drop.end());
  map.apply(deltaOf(behind, false), {});
  expectLayersMatch(map, with_drop, "the drop added");
  map.apply(deltaOf(behind, true), {});
  expectLayersMatch(map, alone, "the drop removed");
}

}  // namespace
}  // namespace terramesh::traversability
