// Over the sensor of the drive: beside the strip a robot taller than its sensor swept, no ray looks
// higher than the sensor (rays run from it down to the ground), so the closing geometry there (a
// lid where the carving stopped) is no possible obstacle for a driven face. Below the sensor's
// height it still is: what stands on the ground shows there.
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <vector>

#include "evidence_faces.h"
#include "test_support/traversability_scenes.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability {
namespace {

constexpr double kSensorHeightM = 1.4;

struct LidScene {
  mesher::TriangleMesh mesh;
  std::vector<mesher::SurfaceFace> faces;
  std::size_t floor_faces = 0;
};

/// A level floor, driven within the car's half width (0.9 m) of y = 0, with an unobserved lid
/// (no ray in front of it: interpolated) facing down at height `lid_z` beside the strip, 1.0 m to
/// 2.5 m left of the drive's centre line.
LidScene lidScene(double lid_z) {
  LidScene scene;
  scene.mesh = test::heightFieldMesh(-6, 10, -4, 4, 0.25, [](double, double) { return 0.0; });
  scene.floor_faces = scene.mesh.faces.size();
  test::appendMesh(scene.mesh, test::horizontalQuad(0, 4, 1.0, 2.5, lid_z, true));
  const std::size_t floor_faces = scene.floor_faces;
  scene.faces = facesOf(scene.mesh, 4, [floor_faces](std::size_t f) { return f >= floor_faces; });
  driveAlongX(scene.faces, floor_faces, 0.9);
  return scene;
}

/// The layers of the driven faces left of the centre line, not reaching it (centroid y in [0.3,
/// 0.85]: judged at the centroid), whose footprint turned along the drive reaches under the lid.
std::vector<FaceLayers> besideLid(const LidScene& scene, const std::map<mesher::FaceKey, FaceLayers>& layers) {
  std::vector<FaceLayers> out;
  for (std::size_t f = 0; f < scene.floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(scene.mesh, f);
    if (scene.faces[f].driven_vertices != 3 || c.y() < 0.3 || c.y() > 0.85 || c.x() < 0.5 || c.x() > 3.5) continue;
    out.push_back(layers.at(scene.faces[f].key));
  }
  return out;
}

std::map<mesher::FaceKey, FaceLayers> layersWith(const LidScene& scene, const RobotProfile& profile,
                                                 std::optional<double> sensor_height_m) {
  TraversabilityMap map(profile, MapFrame{});
  map.setDrivePoses(basesAlongX(scene.mesh), sensor_height_m);
  map.reset(scene.faces);
  return layersByKey(map);
}

TEST(DriveSensorTest, AnUnobservedLidAboveTheSensorBesideTheStripIsNoPossibleObstacle) {
  const RobotProfile car = loadRobotProfile(kRobots / "car.yaml");  // 4.8 x 1.8 m, 1.9 m tall
  ASSERT_GT(car.min_clearance_m, kSensorHeightM + 0.3);
  for (const double lid_z : {1.7, 1.1}) {
    const LidScene scene = lidScene(lid_z);
    const std::vector<FaceLayers> unknown_sensor = besideLid(scene, layersWith(scene, car, std::nullopt));
    const std::vector<FaceLayers> with_sensor = besideLid(scene, layersWith(scene, car, kSensorHeightM));
    ASSERT_GE(unknown_sensor.size(), 20u);
    ASSERT_EQ(with_sensor.size(), unknown_sensor.size());
    // Without the sensor's height the lid counts up to the car's roof: uncertain, never lethal.
    for (const FaceLayers& layers : unknown_sensor) {
      EXPECT_EQ(layers.face_class, FaceClass::kUncertain) << "lid at " << lid_z;
      EXPECT_TRUE(layers.reasons & reason::kPossibleObstacle) << "lid at " << lid_z;
    }
    // With it, a lid above the sensor says nothing: free. One below it still counts.
    const FaceClass want = lid_z > kSensorHeightM ? FaceClass::kFree : FaceClass::kUncertain;
    for (const FaceLayers& layers : with_sensor) EXPECT_EQ(layers.face_class, want) << "lid at " << lid_z;
  }
}

TEST(DriveSensorTest, TheLidComesAndGoesIncrementallyAsInAFullComputation) {
  const RobotProfile car = loadRobotProfile(kRobots / "car.yaml");
  for (const double lid_z : {1.7, 1.1}) {
    const LidScene scene = lidScene(lid_z);
    const std::vector<mesher::SurfaceFace> floor(scene.faces.begin(),
                                                 scene.faces.begin() + static_cast<std::ptrdiff_t>(scene.floor_faces));
    const std::vector<mesher::SurfaceFace> lid(scene.faces.begin() + static_cast<std::ptrdiff_t>(scene.floor_faces),
                                               scene.faces.end());
    LidScene bare = scene;
    bare.faces = floor;
    TraversabilityMap map(car, MapFrame{});
    map.setDrivePoses(basesAlongX(scene.mesh), kSensorHeightM);
    map.reset(floor);
    map.apply(deltaOf(lid, false), {});
    expectLayersMatch(map, layersWith(scene, car, kSensorHeightM), "the lid added");
    map.apply(deltaOf(lid, true), {});
    expectLayersMatch(map, layersWith(bare, car, kSensorHeightM), "the lid removed");
  }
}

}  // namespace
}  // namespace terramesh::traversability
