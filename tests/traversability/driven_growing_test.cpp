// Growing with trajectory evidence (MesherConfig::driven_cells_first): the free cells the robot's
// body passed through grow before the others, so the manifold test does not keep them out of O
// where a region only the sensor's rays support competes for the same vertices (a parked car's
// side points pinching the driven strip between the road and them), and those still refused are
// tried with their pocket of free cells. A generated street and garage, meshed with trajectory
// evidence as `terramesh mesh --robot` does it, with the switch on and off.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "datasets/slam_simulation.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"
#include "evidence_stream.h"
#include "mesher/mesher.h"
#include "test_support/mesh_queries.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/trajectory_evidence.h"

namespace terramesh::traversability {
namespace {

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

/// `scene` seen by the generator's SLAM, meshed with small_wheeled's trajectory evidence at the
/// scene's sensor height, growing's driven-first order on or off: the share of probes in the
/// robot's body volume along the true path (between consecutive keyframes, a quarter, half and
/// three quarters of the way; across the disc's 0.34 m radius; 0.05 to 0.3 m above the road) that
/// lie in the mesh's free space.
double bodyFreeShare(const datasets::SyntheticScene& scene, double sensor_height_m, bool driven_first) {
  const datasets::TriangleBvh bvh(scene.ground_truth.mesh);
  const datasets::SimulatedSlam slam = datasets::simulateSlam(scene, bvh, datasets::SlamSimulationConfig{});
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  const RobotProfile robot = loadRobotProfile(kRobots / "small_wheeled.yaml");
  const Eigen::Vector3d up = scene.up_W.normalized();
  TrajectoryEvidence evidence(robot, up, 1.0, sensor_height_m, Eigen::Vector3d::UnitZ(), TrajectoryEvidenceConfig{});
  evidence.configureMesher(config);
  config.driven_cells_first = driven_first;
  mesher::Mesher mesher(config);
  for (const datasets::StreamEvent& event : slam.stream.events) test_stream::applyEvent(mesher, event, &evidence);
  const mesher::InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
  const mesher::TriangleMesh mesh = mesher.extractMesh();
  EXPECT_TRUE(mesher::analyzeTopology(mesh).isClosedManifold());
  std::size_t free = 0, total = 0;
  for (std::size_t k = 0; k + 1 < slam.keyframes.size(); ++k) {
    const Eigen::Isometry3d& a = slam.keyframes[k].true_T_W_C;
    const Eigen::Vector3d b = slam.keyframes[k + 1].true_T_W_C.translation();
    for (double t : {0.25, 0.5, 0.75}) {
      for (double side : {-0.3, -0.15, 0.0, 0.15, 0.3}) {
        for (double above_road_m : {0.05, 0.15, 0.3}) {
          const Eigen::Vector3d p = (1 - t) * a.translation() + t * b + side * a.linear().col(0) -
                                    (sensor_height_m - above_road_m) * up;
          free += test::insideClosedMesh(mesh, p) ? 1 : 0;
          ++total;
        }
      }
    }
  }
  EXPECT_GT(total, 500u);
  return static_cast<double>(free) / static_cast<double>(total);
}

void expectDrivenFirstFreesMore(const char* name, const datasets::SyntheticScene& scene, double sensor_height_m) {
  const double first = bodyFreeShare(scene, sensor_height_m, true);
  const double by_weight = bodyFreeShare(scene, sensor_height_m, false);
  std::printf("%s: body volume along the path in free space: %.4f driven cells first, %.4f by weight alone\n", name,
              first, by_weight);
  EXPECT_GT(first, by_weight);
  EXPECT_GE(first, 0.995);
}

TEST(DrivenGrowingTest, TheBodysFreeSpaceGrowsFirstOnAStreet) {
  datasets::StreetSceneConfig config;
  config.length_m = 100;
  config.seed = 4;
  expectDrivenFirstFreesMore("street", datasets::buildStreetScene(config), config.camera_height_m);
}

TEST(DrivenGrowingTest, TheBodysFreeSpaceGrowsFirstInAGarage) {
  datasets::GarageSceneConfig config;
  config.length_m = 40;
  config.seed = 4;
  expectDrivenFirstFreesMore("garage", datasets::buildGarageScene(config), config.camera_height_m);
}

}  // namespace
}  // namespace terramesh::traversability
