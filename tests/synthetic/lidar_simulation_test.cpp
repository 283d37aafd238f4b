#include "datasets/lidar_simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace terramesh::datasets {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

/// A level square of ground z = 0 (label road), `half_size_m` to each side of the origin, z up.
LabeledMesh groundPlane(double half_size_m) {
  LabeledMesh truth;
  const double h = half_size_m;
  truth.mesh.vertices = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  truth.mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  truth.labels = {SurfaceLabel::kRoad, SurfaceLabel::kRoad};
  truth.slope_deg = {0.0f, 0.0f};
  return truth;
}

/// The sensor at `height_m` above the origin, level, x forward.
Eigen::Isometry3d levelSensorAt(double height_m) {
  Eigen::Isometry3d T_W_S = Eigen::Isometry3d::Identity();
  T_W_S.translation() = Eigen::Vector3d(0, 0, height_m);
  return T_W_S;
}

/// Elevation of a return above the sensor's xy plane, in degrees.
double elevationDeg(const VelodyneReturn& point) {
  const Eigen::Vector3d p = point.position_S.cast<double>();
  return std::atan2(p.z(), p.head<2>().norm()) * kRadToDeg;
}

/// The beam whose elevation is nearest to `elevation_deg`.
std::size_t nearestBeam(const std::vector<double>& elevations_deg, double elevation_deg) {
  std::size_t best = 0;
  for (std::size_t b = 1; b < elevations_deg.size(); ++b) {
    if (std::abs(elevations_deg[b] - elevation_deg) <
        std::abs(elevations_deg[best] - elevation_deg))
      best = b;
  }
  return best;
}

TEST(LidarSimulationTest, SixtyFourBeamsEvenlySpacedFromPlus2ToMinus24_8Degrees) {
  const LidarSimulationConfig config;
  const std::vector<double> elevations = lidarBeamElevationsDeg(config);
  ASSERT_EQ(elevations.size(), 64u);
  EXPECT_DOUBLE_EQ(elevations.front(), 2.0);
  EXPECT_NEAR(elevations.back(), -24.8, 1e-12);
  for (std::size_t b = 1; b < elevations.size(); ++b) {
    EXPECT_NEAR(elevations[b - 1] - elevations[b], 26.8 / 63.0, 1e-12) << "beam " << b;
  }
  const std::vector<Eigen::Vector3d> directions = lidarRayDirections(config);
  ASSERT_EQ(directions.size(), 64u * 2048u) << "131,072 rays a scan";
  for (const Eigen::Vector3d& direction : directions) ASSERT_NEAR(direction.norm(), 1.0, 1e-12);
  // Firing order: column 0 (forward) top to bottom, then column 1, 360/2048 degrees to the left.
  EXPECT_NEAR(std::asin(directions[0].z()) * kRadToDeg, 2.0, 1e-9);
  EXPECT_NEAR(directions[0].y(), 0.0, 1e-15);
  EXPECT_NEAR(std::asin(directions[63].z()) * kRadToDeg, -24.8, 1e-9);
  EXPECT_NEAR(std::atan2(directions[64].y(), directions[64].x()) * kRadToDeg, 360.0 / 2048.0, 1e-9);
  EXPECT_NEAR(std::asin(directions[64].z()) * kRadToDeg, 2.0, 1e-9);
}

TEST(LidarSimulationTest, ValidateNamesEveryBadField) {
  EXPECT_NO_THROW(LidarSimulationConfig().validate());
  LidarSimulationConfig config;
  config.beam_count = 0;
  config.columns_per_revolution = 0;
  config.max_range_m = 0.5;  // below min_range_m
  config.range_noise_std_m = -0.01;
  config.rate_hz = 0.0;
  config.speed_m_per_s = std::numeric_limits<double>::quiet_NaN();
  config.upper_elevation_deg = -30.0;  // below lower_elevation_deg
  try {
    config.validate();
    FAIL() << "an invalid config validated";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    for (const char* field :
         {"beam_count", "columns_per_revolution", "max_range_m", "range_noise_std_m", "rate_hz",
          "speed_m_per_s", "upper_elevation_deg must be >= lower"}) {
      EXPECT_NE(message.find(field), std::string::npos) << field << " missing from: " << message;
    }
  }
}

TEST(LidarSimulationTest, FlatGroundRangeIsHeightOverSineOfDepression) {
  const LabeledMesh truth = groundPlane(2000.0);
  const TriangleBvh bvh(truth.mesh);
  LidarSimulationConfig config;
  const double height_m = 1.73;
  const std::vector<double> elevations = lidarBeamElevationsDeg(config);
  // Beams that meet the ground within range; none is within 6 sigma of a range limit, so the
  // count is exact.
  std::size_t beams_on_ground = 0;
  for (const double elevation : elevations) {
    if (elevation >= 0) continue;
    const double range = height_m / std::sin(-elevation / kRadToDeg);
    ASSERT_GT(std::abs(range - config.max_range_m), 0.2) << "beam at " << elevation << " deg";
    if (range <= config.max_range_m) ++beams_on_ground;
  }
  ASSERT_GT(beams_on_ground, 50u);
  for (const double noise_m : {0.0, 0.02}) {
    config.range_noise_std_m = noise_m;
    const LidarScan scan = LidarSimulator(truth, bvh, config).scan(levelSensorAt(height_m), 0);
    ASSERT_EQ(scan.returns.size(), beams_on_ground * 2048u) << "noise " << noise_m;
    EXPECT_EQ(scan.stats.returns, scan.returns.size());
    ASSERT_EQ(scan.labels.size(), scan.returns.size());
    double sum_squared = 0.0;
    for (std::size_t i = 0; i < scan.returns.size(); ++i) {
      const double elevation = elevations[nearestBeam(elevations, elevationDeg(scan.returns[i]))];
      const double expected = height_m / std::sin(-elevation / kRadToDeg);
      const double error = scan.returns[i].position_S.cast<double>().norm() - expected;
      ASSERT_LE(std::abs(error), noise_m > 0 ? 6 * noise_m : 1e-4)
          << "return " << i << " beam at " << elevation;
      sum_squared += error * error;
      EXPECT_EQ(scan.labels[i], SurfaceLabel::kRoad);
      EXPECT_LT(scan.faces[i], 2u);
    }
    const double rms = std::sqrt(sum_squared / static_cast<double>(scan.returns.size()));
    if (noise_m > 0) {
      EXPECT_NEAR(rms, noise_m, 0.05 * noise_m) << "the noise has the configured sigma";
    }
  }
}

TEST(LidarSimulationTest, MissesGiveNoReturn) {
  const LabeledMesh truth = groundPlane(2000.0);
  const TriangleBvh bvh(truth.mesh);
  const LidarSimulationConfig config;
  const LidarSimulator simulator(truth, bvh, config);
  const LidarScan scan = simulator.scan(levelSensorAt(1.73), 0);
  // Beams at or above the horizon see only sky: no return; 6 beams point up (2.0 ... 0.30 deg).
  for (const VelodyneReturn& point : scan.returns) ASSERT_LT(point.position_S.z(), 0.0f);
  EXPECT_EQ(scan.stats.rays, 64u * 2048u);
  EXPECT_GE(scan.stats.misses, 6u * 2048u);
  EXPECT_EQ(scan.stats.rays, scan.stats.returns + scan.stats.misses + scan.stats.out_of_range);
  // Ground beyond max_range_m is not seen: 200 m up, every ray misses.
  const LidarScan high = simulator.scan(levelSensorAt(200.0), 1);
  EXPECT_TRUE(high.returns.empty());
  EXPECT_EQ(high.stats.misses, high.stats.rays);
  // An empty world gives empty scans.
  const LabeledMesh empty;
  const TriangleBvh empty_bvh(empty.mesh);
  EXPECT_TRUE(
      LidarSimulator(empty, empty_bvh, config).scan(levelSensorAt(1.73), 0).returns.empty());
}

TEST(LidarSimulationTest, SameSeedAndIndexGiveTheSameScan) {
  const LabeledMesh truth = groundPlane(2000.0);
  const TriangleBvh bvh(truth.mesh);
  LidarSimulationConfig config;
  const auto positions = [&](std::uint64_t seed, std::size_t index) {
    config.seed = seed;
    const LidarScan scan = LidarSimulator(truth, bvh, config).scan(levelSensorAt(1.73), index);
    std::vector<Eigen::Vector3f> result;
    for (const VelodyneReturn& point : scan.returns) result.push_back(point.position_S);
    return result;
  };
  const std::vector<Eigen::Vector3f> first = positions(7, 3);
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(positions(7, 3), first) << "bit for bit";
  EXPECT_NE(positions(8, 3), first) << "another seed, other noise";
  EXPECT_NE(positions(7, 4), first) << "another scan of the sequence, other noise";
}

/// A z-up scene on the ground plane whose camera drives along +x from x = 0 to 50 m at 1.2 m,
/// one frame a metre.
SyntheticScene straightDrive() {
  SyntheticScene scene;
  scene.name = "plane";
  scene.ground_truth = groundPlane(100.0);
  for (int i = 0; i <= 50; ++i) {
    Eigen::Isometry3d T_W_C = Eigen::Isometry3d::Identity();
    T_W_C.linear() << 0, 0, 1,  // camera x right = -y_W, y down = -z_W, z forward = +x_W
        -1, 0, 0,               //
        0, -1, 0;
    T_W_C.translation() = Eigen::Vector3d(i, 0, 1.2);
    scene.frames_T_W_C.push_back(T_W_C);
  }
  return scene;
}

TEST(LidarSimulationTest, ScansAreSpeedOverRateApartAndMountHeightAboveTheGround) {
  const SyntheticScene scene = straightDrive();
  const TriangleBvh bvh(scene.ground_truth.mesh);
  const LidarSimulationConfig config;  // 8 m/s at 10 Hz: 0.8 m apart
  const std::vector<Eigen::Isometry3d> poses = lidarScanPoses(scene, bvh, config);
  ASSERT_EQ(poses.size(), 63u) << "0, 0.8, ..., 49.6 m on a 50 m trajectory";
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_TRUE(poses[i].translation().isApprox(
        Eigen::Vector3d(0.8 * static_cast<double>(i), 0, 1.73), 1e-12))
        << "scan " << i << " at " << poses[i].translation().transpose();
    EXPECT_TRUE(poses[i].linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12))
        << "x forward, y left, z up";
  }
  EXPECT_EQ(lidarScanPoses(scene, bvh, config, 5).size(), 5u);
  LidarSimulationConfig slow = config;
  slow.speed_m_per_s = 2.5;  // 0.25 m apart
  EXPECT_EQ(lidarScanPoses(scene, bvh, slow).size(), 201u);
}

TEST(LidarSimulationTest, NoGroundUnderTheTrajectoryIsAnError) {
  SyntheticScene scene = straightDrive();
  scene.ground_truth = groundPlane(10.0);  // the camera drives off it at x = 10 m
  const TriangleBvh bvh(scene.ground_truth.mesh);
  try {
    lidarScanPoses(scene, bvh, LidarSimulationConfig());
    FAIL() << "no error";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("no ground"), std::string::npos) << error.what();
  }
  EXPECT_EQ(lidarScanPoses(scene, bvh, LidarSimulationConfig(), 12).size(), 12u)
      << "up to 8.8 m is fine";
}

TEST(LidarSimulationTest, StreetScanHasAbout120kReturnsOnTheirTruthFaces) {
  StreetSceneConfig street;
  street.length_m = 120.0;
  const SyntheticScene scene = buildStreetScene(street);
  const TriangleBvh bvh(scene.ground_truth.mesh);
  LidarSimulationConfig config;
  const std::vector<Eigen::Isometry3d> poses = lidarScanPoses(scene, bvh, config);
  ASSERT_GT(poses.size(), 100u);
  const LidarScan scan =
      LidarSimulator(scene.ground_truth, bvh, config).scan(poses[75], 75);  // at 60 m
  EXPECT_GT(scan.returns.size(), 100000u);
  EXPECT_LT(scan.returns.size(), 131072u) << "the upper beams see sky through the gaps";
  std::size_t per_label[kSurfaceLabelCount] = {};
  const mesher::TriangleMesh& mesh = scene.ground_truth.mesh;
  for (std::size_t i = 0; i < scan.returns.size(); ++i) {
    ++per_label[static_cast<std::size_t>(scan.labels[i])];
    ASSERT_EQ(scan.labels[i], scene.ground_truth.labels[scan.faces[i]]);
    // The return, taken to the world, lies on its face's plane within the range noise.
    const auto& face = mesh.faces[scan.faces[i]];
    const Eigen::Vector3d& a = mesh.vertices[face[0]];
    const Eigen::Vector3d normal =
        (mesh.vertices[face[1]] - a).cross(mesh.vertices[face[2]] - a).normalized();
    const Eigen::Vector3d p_W = scan.T_W_S * scan.returns[i].position_S.cast<double>();
    ASSERT_LT(std::abs(normal.dot(p_W - a)), 6 * config.range_noise_std_m) << "return " << i;
  }
  for (const SurfaceLabel label :
       {SurfaceLabel::kRoad, SurfaceLabel::kSidewalk, SurfaceLabel::kWall}) {
    EXPECT_GT(per_label[static_cast<std::size_t>(label)], 1000u) << toString(label);
  }
}

}  // namespace
}  // namespace terramesh::datasets
