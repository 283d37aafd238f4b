// Trajectory evidence: the sensor mounting in the profile, the sensor-height estimate and the
// not-driven rule, the driven-ground samples, and on a simulated street the height of the road
// under the path with and without them.
#include "traversability/robot_profile_yaml.h"
#include "traversability/trajectory_evidence.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <variant>

#include "common/input_error.h"
#include "datasets/slam_simulation.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"
#include "evidence_stream.h"
#include "mesher/mesher.h"
#include "simulated_scene.h"
#include "test_support/analytic_scenes.h"
#include "test_support/mesh_queries.h"
#include "test_support/temp_dir.h"

namespace terramesh::traversability {
namespace {

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

RobotProfile discRobot(double radius_m) {
  RobotProfile profile;
  profile.footprint = FootprintShape::kDisc;
  profile.footprint_radius_m = radius_m;
  return profile;
}

/// A camera (x right, y down, z forward) at `position` looking along +x of a z-up world.
mesher::Keyframe cameraAt(std::uint64_t id, const Eigen::Vector3d& position) {
  mesher::Keyframe keyframe;
  keyframe.id = mesher::KeyframeId{id};
  keyframe.position_W_C = position;
  Eigen::Matrix3d R_W_C;
  R_W_C.col(0) = -Eigen::Vector3d::UnitY();  // right
  R_W_C.col(1) = -Eigen::Vector3d::UnitZ();  // down
  R_W_C.col(2) = Eigen::Vector3d::UnitX();   // forward
  keyframe.rotation_W_C = Eigen::Quaterniond(R_W_C);
  return keyframe;
}

std::filesystem::path writeYaml(const test::TempDir& dir, const std::string& text) {
  const std::filesystem::path path = dir / "robot.yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(SensorMountingTest, CarProfileCarriesKittisCameraHeightOthersLeaveItUnset) {
  EXPECT_EQ(loadRobotProfile(kRobots / "car.yaml").sensor_height_m, 1.65);
  EXPECT_FALSE(loadRobotProfile(kRobots / "small_wheeled.yaml").mountedSensorHeightM());
  EXPECT_FALSE(loadRobotProfile(kRobots / "legged.yaml").mountedSensorHeightM());
}

TEST(SensorMountingTest, FullTransformReadsWritesBackAndIsChecked) {
  const test::TempDir dir;
  const RobotProfile profile = loadRobotProfile(writeYaml(
      dir, "name: r\nsensor_pose_in_base: {translation_m: [0.3, 0, 1.2], rotation_xyzw: [0.5, -0.5, 0.5, -0.5]}\n"));
  ASSERT_TRUE(profile.T_B_S);
  EXPECT_DOUBLE_EQ(*profile.mountedSensorHeightM(), 1.2);
  // A camera looking forward: its z axis is the base's x.
  EXPECT_TRUE((profile.T_B_S->linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  writeRobotProfile(dir / "back.yaml", profile);
  const RobotProfile back = loadRobotProfile(dir / "back.yaml");
  ASSERT_TRUE(back.T_B_S);
  EXPECT_TRUE(back.T_B_S->matrix().isApprox(profile.T_B_S->matrix(), 1e-12));

  EXPECT_THROW(loadRobotProfile(writeYaml(dir, "name: r\nsensor_height_m: 0\n")), InputError);
  EXPECT_THROW(loadRobotProfile(writeYaml(dir, "name: r\nsensor_pose_in_base: {translation_m: [0, 0, 1]}\n")),
               InputError);
  EXPECT_THROW(loadRobotProfile(writeYaml(dir, "name: r\nsensor_pose_in_base: {translation_m: [0, 0, 1], "
                                               "rotation_xyzw: [0, 0, 0, 1], scale: 2}\n")),
               InputError);
  EXPECT_THROW(loadRobotProfile(writeYaml(dir, "name: r\nsensor_height_m: 1.5\nsensor_pose_in_base: {translation_m: "
                                               "[0, 0, 1], rotation_xyzw: [0, 0, 0, 1]}\n")),
               InputError);
  RobotProfile bad = discRobot(0.3);
  bad.sensor_height_m = -1.0;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(DrivenSamplesTest, DiscPatchLiesAtTheSensorHeightBelowTheSensorWithReservedIds) {
  const TrajectoryEvidenceConfig config;
  TrajectoryEvidence evidence(discRobot(0.34), Eigen::Vector3d::UnitZ(), 1.0, 1.65, Eigen::Vector3d::UnitZ(), config);
  const mesher::Keyframe keyframe = cameraAt(7, {10, 5, 2.0});
  const std::vector<mesher::PointObservation> samples = evidence.samplesOf(keyframe);
  // The disc's diameter across the heading: its centre and both edges of the full footprint.
  ASSERT_EQ(samples.size(), 3u);
  std::vector<double> offsets;
  std::set<std::uint64_t> ids;
  for (const mesher::PointObservation& sample : samples) {
    EXPECT_EQ(sample.kind, mesher::PointKind::kDrivenGround);
    EXPECT_TRUE(isDrivenGroundId(sample.point));
    EXPECT_EQ((sample.point.value & ~kDrivenGroundIdBit) >> kDrivenSampleIndexBits, 7u);
    ids.insert(sample.point.value);
    EXPECT_NEAR(sample.position_W.z(), 2.0 - 1.65, 1e-12);
    EXPECT_LE((sample.position_W - Eigen::Vector3d(10, 5, 0.35)).norm(), 0.34 + 1e-12);
    offsets.push_back((sample.position_W - Eigen::Vector3d(10, 5, 0.35)).norm());
  }
  std::sort(offsets.begin(), offsets.end());
  EXPECT_NEAR(offsets[0], 0.0, 1e-12);
  EXPECT_NEAR(offsets[1], 0.34, 1e-12);
  EXPECT_NEAR(offsets[2], 0.34, 1e-12);
  EXPECT_NEAR((samples[0].position_W - samples[2].position_W).norm(), 0.68, 1e-12) << "on opposite sides";
  EXPECT_EQ(ids.size(), samples.size());
}

TEST(DrivenSamplesTest, RectanglePatchFollowsTheHeadingAndTheFullMounting) {
  RobotProfile car;
  car.footprint = FootprintShape::kRectangle;
  car.footprint_length_m = 4.8;
  car.footprint_width_m = 1.8;
  // The camera 1.2 m ahead of the footprint's centre, 1.65 m up, looking forward.
  car.T_B_S = Eigen::Isometry3d::Identity();
  car.T_B_S->linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  car.T_B_S->translation() = Eigen::Vector3d(1.2, 0, 1.65);
  const TrajectoryEvidenceConfig config;
  TrajectoryEvidence evidence(car, Eigen::Vector3d::UnitZ(), 1.0, 1.65, Eigen::Vector3d::UnitZ(), config);
  const std::vector<mesher::PointObservation> samples = evidence.samplesOf(cameraAt(1, {0, 0, 1.65}));
  ASSERT_EQ(samples.size(), evidence.samplesPerKeyframe());
  // The width across the heading (+x) through the footprint's centre, out to both sides: 1.8 m
  // takes two gaps of at most 1.5 m, so four rails 0.6 m apart, none on the centre line.
  ASSERT_EQ(samples.size(), 4u);
  std::vector<double> lateral;
  for (const mesher::PointObservation& sample : samples) {
    EXPECT_NEAR(sample.position_W.z(), 0.0, 1e-12);
    EXPECT_NEAR(sample.position_W.x(), -1.2, 1e-9);
    lateral.push_back(sample.position_W.y());
  }
  std::sort(lateral.begin(), lateral.end());
  const double expected[] = {-0.9, -0.3, 0.3, 0.9};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(lateral[i], expected[i], 1e-9) << i;
  // Three gaps (4.2 m) also take four rails; a footprint no wider than the spacing gets a centre rail.
  car.footprint_width_m = 4.2;
  EXPECT_EQ(TrajectoryEvidence(car, Eigen::Vector3d::UnitZ(), 1.0, 1.65, Eigen::Vector3d::UnitZ(), config)
                .samplesPerKeyframe(), 4u);
  car.footprint_width_m = 1.5;
  EXPECT_EQ(TrajectoryEvidence(car, Eigen::Vector3d::UnitZ(), 1.0, 1.65, Eigen::Vector3d::UnitZ(), config)
                .samplesPerKeyframe(), 3u);
}

TEST(DrivenSamplesTest, ReservedIdsAndHugeKeyframeIdsAreRefused) {
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  mesher::Keyframe keyframe = cameraAt(3, {0, 0, 1});
  keyframe.observations.push_back({mesher::PointId{kDrivenGroundIdBit | 5}, {3, 0, 0}, mesher::PointKind::kSlam});
  EXPECT_THROW(evidence.augment(keyframe), std::invalid_argument);
  EXPECT_TRUE(evidence.remove(keyframe.id).empty()) << "nothing recorded for a refused keyframe";
  EXPECT_THROW(evidence.samplesOf(cameraAt(kMaxDrivenKeyframeId + 1, {0, 0, 1})), std::invalid_argument);
}

TEST(DrivenSamplesTest, KeyframesObserveThePreviousPatchAndRemovalReturnsTheSamples) {
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  const std::size_t n = evidence.samplesPerKeyframe();
  // The patch (the disc's diameter across the heading) has no length: stations every 0.5 m.
  ASSERT_NEAR(evidence.patchLengthM(), 0.0, 1e-12);
  EXPECT_EQ(evidence.stationsFor(0.4), 0u);
  EXPECT_EQ(evidence.stationsFor(2.0), 3u);
  EXPECT_EQ(evidence.stationsFor(1e6), evidence.maxStationsPerKeyframe());
  EXPECT_EQ(evidence.augment(cameraAt(1, {0, 0, 1})).observations.size(), n);
  const mesher::Keyframe second = evidence.augment(cameraAt(2, {2, 0, 1}));
  // Its own patch (at x = 2), patches at stations 1-3 (x = 0.5, 1 and 1.5 on the way from the first
  // keyframe) and the sweep to the first one's.
  ASSERT_EQ(second.observations.size(), 5 * n);
  for (std::size_t station = 0; station <= 3; ++station) {
    EXPECT_NEAR(second.observations[station * n].position_W.x(), station == 0 ? 2.0 : 0.5 * static_cast<double>(station),
                1e-12);
    EXPECT_NEAR(second.observations[station * n].position_W.z(), 0.0, 1e-12);
  }
  const auto first_samples = evidence.samplesOf(cameraAt(1, {0, 0, 1}));
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(second.observations[4 * n + i].point, first_samples[i].point);
  // On one level nothing is beneath the drive: no underside views.
  EXPECT_FALSE(evidence.undersideViewOf(mesher::KeyframeId{2}).has_value());
  // Too far apart: no sweep and no stations.
  EXPECT_EQ(evidence.augment(cameraAt(3, {20, 0, 1})).observations.size(), n);
  // The samples' ids to remove, with the ids their undersides would have.
  const std::vector<mesher::PointId> removed = evidence.remove(mesher::KeyframeId{1});
  ASSERT_EQ(removed.size(), 2 * n);
  EXPECT_EQ(removed[n].value, removed[0].value + kDrivenUndersideIndex);
  EXPECT_EQ(removed.front(), first_samples.front().point);
  // Keyframe 2 re-sent: its predecessor is gone, so no sweep, but it keeps its 3 stations (placed
  // towards the pose it last saw): the same sample ids, so none is left behind in the mesher.
  const mesher::Keyframe resent = evidence.augment(cameraAt(2, {2, 0.1, 1}));
  ASSERT_EQ(resent.observations.size(), 4 * n);
  for (std::size_t i = 0; i < 4 * n; ++i) EXPECT_EQ(resent.observations[i].point, second.observations[i].point);
  EXPECT_EQ(evidence.remove(mesher::KeyframeId{2}).size(), 2 * 4 * n);
}

TEST(DrivenSamplesTest, EachSampleKnowsTheBaseItWasPutDownAt) {
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  const std::size_t n = evidence.samplesPerKeyframe();
  evidence.augment(cameraAt(1, {0, 0, 1}));
  const mesher::Keyframe second = evidence.augment(cameraAt(2, {2, 0, 1}));
  // Its own patch at x = 2 and stations 1-3 at x = 0.5, 1 and 1.5: the base 1 m under the camera.
  for (std::size_t station = 0; station <= 3; ++station) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::optional<Eigen::Isometry3d> base = evidence.baseOf(second.observations[station * n + i].point);
      ASSERT_TRUE(base.has_value());
      const double x = station == 0 ? 2.0 : 0.5 * static_cast<double>(station);
      EXPECT_LT((base->translation() - Eigen::Vector3d(x, 0, 0)).norm(), 1e-9) << "station " << station;
      EXPECT_LT((base->linear().col(0) - Eigen::Vector3d::UnitX()).norm(), 1e-9);
    }
  }
  EXPECT_FALSE(evidence.baseOf(mesher::PointId{7}).has_value()) << "a SLAM point";
  const mesher::PointId kept = second.observations.front().point;
  evidence.remove(mesher::KeyframeId{2});
  EXPECT_FALSE(evidence.baseOf(kept).has_value()) << "a removed keyframe's sample";
}

TEST(DrivenSamplesTest, BodyViewsSeeTheKeyframesSamplesFromInsideTheBodyAtThePreviousKeyframe) {
  RobotProfile robot = discRobot(0.3);
  robot.min_clearance_m = 0.5;  // the body: 0.5 m tall; the sensor 1 m up
  TrajectoryEvidence evidence(robot, Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  evidence.augment(cameraAt(1, {0, 0, 1}));
  EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{1}).empty()) << "no keyframe before the first";
  EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{9}).empty()) << "unknown";
  const mesher::Keyframe second = cameraAt(2, {2, 0, 1});
  evidence.augment(second);
  const std::vector<mesher::Keyframe> views = evidence.bodyViewsOf(mesher::KeyframeId{2});
  ASSERT_EQ(views.size(), kBodyViewSlots);
  const std::vector<mesher::PointObservation> samples = evidence.samplesOf(second);
  ASSERT_EQ(samples.size(), 4 * evidence.samplesPerKeyframe());  // its patch and 3 stations
  // At the body's top over the first keyframe's base and over the second's: on the centre line
  // and at both sides (the disc's radius across the path), each looking at the second's patch and
  // stations.
  for (const double end_x : {0.0, 2.0}) {
    std::vector<double> sides;
    for (std::uint64_t slot = 0; slot < kBodyViewSlots; ++slot) {
      const mesher::Keyframe& view = views[slot];
      EXPECT_EQ(view.id, bodyViewId(mesher::KeyframeId{2}, slot));
      EXPECT_NE(view.id.value & kBodyViewKeyframeBit, 0u);
      EXPECT_NEAR(view.position_W_C.z(), 0.5, 1e-12);
      ASSERT_EQ(view.observations.size(), samples.size());
      for (std::size_t i = 0; i < samples.size(); ++i) {
        EXPECT_EQ(view.observations[i].point, samples[i].point);
        EXPECT_EQ(view.observations[i].position_W, samples[i].position_W);
      }
      if (std::abs(view.position_W_C.x() - end_x) < 1e-12) sides.push_back(view.position_W_C.y());
    }
    ASSERT_EQ(sides.size(), kBodyViewsPerEnd) << "end at x = " << end_x;
    std::sort(sides.begin(), sides.end());
    EXPECT_NEAR(sides[0], -0.3, 1e-12);
    EXPECT_NEAR(sides[1], 0.0, 1e-12);
    EXPECT_NEAR(sides[2], 0.3, 1e-12);
  }
  // Every ray stays inside the body volume swept from the first keyframe to the second.
  for (const mesher::PointObservation& sample : samples) {
    const Eigen::Vector3d& p = sample.position_W;
    EXPECT_LE(std::abs(p.y()), 0.3 + 1e-12);
    EXPECT_GE(p.x(), 0.0);
    EXPECT_LE(p.x(), 2.0 + 1e-12);
  }
  const std::vector<mesher::KeyframeId> ids = bodyViewIds(mesher::KeyframeId{2});
  ASSERT_EQ(ids.size(), kBodyViewSlots);
  for (std::uint64_t slot = 0; slot < kBodyViewSlots; ++slot) EXPECT_EQ(ids[slot], views[slot].id);
  // Too far from the one before: no view; nor after the one before is gone.
  evidence.augment(cameraAt(3, {30, 0, 1}));
  EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{3}).empty());
  evidence.remove(mesher::KeyframeId{1});
  evidence.augment(cameraAt(2, {2, 0.1, 1}));
  EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{2}).empty());
}

TEST(DrivenSamplesTest, InTheMesherSamplesFollowACorrectedPoseAndGoWithTheirKeyframe) {
  const std::vector<mesher::Keyframe> keyframes = test::planeScene(test::SceneOptions{}).keyframes;  // 3 m up
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  config.steiner_step_m = 4.0;
  mesher::Mesher mesher(config);
  TrajectoryEvidence evidence(discRobot(0.6), Eigen::Vector3d::UnitZ(), 1.0, 3.0, Eigen::Vector3d::UnitZ(), {});
  for (const mesher::Keyframe& keyframe : keyframes) mesher.integrateKeyframe(evidence.augment(keyframe));
  mesher::Keyframe corrected = keyframes[10];
  corrected.position_W_C += Eigen::Vector3d(0.1, 0.3, 0.02);
  mesher.integrateKeyframe(evidence.augment(corrected));
  ASSERT_TRUE(mesher.checkInvariants().ok());
  std::unordered_map<std::uint64_t, Eigen::Vector3d> positions;
  const mesher::TriangleMesh mesh = mesher.extractMesh();
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) positions[mesh.vertex_keys[v].value] = mesh.vertices[v];
  std::size_t found = 0;
  for (const mesher::PointObservation& sample : evidence.samplesOf(corrected)) {
    if (!positions.count(sample.point.value)) continue;
    ++found;
    EXPECT_EQ(positions.at(sample.point.value), sample.position_W);
  }
  EXPECT_GE(found, 2u);

  // Keyframe 11 observes keyframe 10's samples (the sweep): removal must take them out explicitly.
  const std::size_t points = mesher.size().points;
  mesher.removeKeyframe(corrected.id);
  mesher.removePoints(evidence.remove(corrected.id));
  ASSERT_TRUE(mesher.checkInvariants().ok());
  EXPECT_LE(mesher.size().points + evidence.samplesPerKeyframe(), points);
  const mesher::TriangleMesh after = mesher.extractMesh();
  EXPECT_TRUE(mesher::analyzeTopology(after).isClosedManifold());
  for (std::size_t v = 0; v < after.vertices.size(); ++v) {
    if (after.vertex_keys[v].steiner || !isDrivenGroundId(mesher::PointId{after.vertex_keys[v].value})) continue;
    EXPECT_NE((after.vertex_keys[v].value & ~kDrivenGroundIdBit) >> kDrivenSampleIndexBits, corrected.id.value);
  }
}

/// Sensors along x at `height(k)` above z = 0, over random points of z = 0 with 3 cm noise.
void plane(int keyframes, const std::function<double(int)>& height, std::vector<Eigen::Vector3d>& sensors,
           std::vector<Eigen::Vector3d>& points) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(-5, 2.0 * keyframes + 5), y(-10, 10);
  std::normal_distribution<double> noise(0, 0.03);
  for (int i = 0; i < 3 * (2 * keyframes + 10) * 20; ++i) points.emplace_back(x(rng), y(rng), noise(rng));
  for (int k = 0; k < keyframes; ++k) sensors.emplace_back(2.0 * k, 0.3 * std::sin(k), height(k));
}

TEST(SensorHeightEstimateTest, DrivenDroneAndHandheldTrajectories) {
  const TrajectoryEvidenceConfig config;
  std::vector<Eigen::Vector3d> sensors, points;
  plane(60, [](int) { return 1.65; }, sensors, points);
  SensorHeightEstimate estimate = estimateSensorHeight(sensors, points, Eigen::Vector3d::UnitZ(), 1.0, config);
  EXPECT_EQ(estimate.status, SensorHeightEstimate::Status::kDriven) << estimate.reason;
  EXPECT_NEAR(estimate.height_m, 1.65, 0.02);
  EXPECT_LT(estimate.spread_m, 0.05);

  sensors.clear(), points.clear();
  plane(60, [](int) { return 15.0; }, sensors, points);
  estimate = estimateSensorHeight(sensors, points, Eigen::Vector3d::UnitZ(), 1.0, config);
  EXPECT_EQ(estimate.status, SensorHeightEstimate::Status::kNotDriven);
  EXPECT_NEAR(estimate.height_m, 15.0, 0.05);
  EXPECT_FALSE(decideTrajectoryEvidence(estimate, std::nullopt, 1.65, config).enabled);

  sensors.clear(), points.clear();
  plane(60, [](int k) { return 1.5 + 0.4 * std::sin(0.7 * k); }, sensors, points);  // a walking, waving hand
  estimate = estimateSensorHeight(sensors, points, Eigen::Vector3d::UnitZ(), 1.0, config);
  EXPECT_EQ(estimate.status, SensorHeightEstimate::Status::kNotDriven);
  EXPECT_GT(estimate.spread_m, config.max_height_spread_m);
  const TrajectoryEvidenceDecision off = decideTrajectoryEvidence(estimate, std::nullopt, std::nullopt, config);
  EXPECT_FALSE(off.enabled);
  EXPECT_NE(off.summary.find("does not look driven"), std::string::npos);

  estimate = estimateSensorHeight(sensors, {}, Eigen::Vector3d::UnitZ(), 1.0, config);
  EXPECT_EQ(estimate.status, SensorHeightEstimate::Status::kNoData);
  EXPECT_FALSE(decideTrajectoryEvidence(estimate, std::nullopt, std::nullopt, config).enabled);
  EXPECT_TRUE(decideTrajectoryEvidence(estimate, 1.65, std::nullopt, config).enabled);
}

TEST(SensorHeightEstimateTest, AnUpperGarageLevelIsTheGroundNotTheLevelBelowIt) {
  // The sensor 1.5 m above a floor; 3.1 m under that floor, a level below with twice as many
  // points (seen through the ramp openings). The lower envelope of all the depths would take the
  // level below for the ground, and its spread would turn the evidence off.
  const TrajectoryEvidenceConfig config;
  std::vector<Eigen::Vector3d> sensors, points;
  plane(60, [](int) { return 1.5; }, sensors, points);
  const std::vector<Eigen::Vector3d> floor = points;
  for (int copy = 1; copy <= 2; ++copy) {
    for (const Eigen::Vector3d& p : floor) points.push_back(p + Eigen::Vector3d(0.01 * copy, 0, -3.1));
  }
  const SensorHeightEstimate estimate = estimateSensorHeight(sensors, points, Eigen::Vector3d::UnitZ(), 1.0, config);
  EXPECT_EQ(estimate.status, SensorHeightEstimate::Status::kDriven) << estimate.reason;
  EXPECT_NEAR(estimate.height_m, 1.5, 0.02);
}

TEST(SensorHeightEstimateTest, AGivenHeightThatDisagreesWarnsNamingBothValues) {
  const TrajectoryEvidenceConfig config;
  std::vector<Eigen::Vector3d> sensors, points;
  plane(40, [](int) { return 1.65; }, sensors, points);
  const SensorHeightEstimate estimate = estimateSensorHeight(sensors, points, Eigen::Vector3d::UnitZ(), 1.0, config);
  const TrajectoryEvidenceDecision agree = decideTrajectoryEvidence(estimate, 1.7, std::nullopt, config);
  EXPECT_TRUE(agree.enabled);
  EXPECT_FALSE(agree.warning);
  EXPECT_EQ(agree.sensor_height_m, 1.7);
  const TrajectoryEvidenceDecision disagree = decideTrajectoryEvidence(estimate, 1.7, 1.2, config);
  EXPECT_TRUE(disagree.enabled);
  EXPECT_EQ(disagree.sensor_height_m, 1.2);
  ASSERT_TRUE(disagree.warning);
  EXPECT_NE(disagree.warning->find("1.200 m"), std::string::npos) << *disagree.warning;
  EXPECT_NE(disagree.warning->find("1.65"), std::string::npos) << *disagree.warning;
  EXPECT_NE(disagree.warning->find("--sensor-height-m"), std::string::npos) << *disagree.warning;
  const TrajectoryEvidenceDecision data = decideTrajectoryEvidence(estimate, std::nullopt, std::nullopt, config);
  EXPECT_EQ(data.source, "the data");
  EXPECT_NEAR(data.sensor_height_m, 1.65, 0.02);
}

// ---- On a simulated street ------------------------------------------------------------------

using Street = test_stream::SimulatedStreet;

/// An 80 m street (seed 2) whose keyframes are re-sent with corrected poses (0.5 m of drift).
const Street& street() {
  static const Street* const kStreet = new Street(test_stream::simulateStreet(80, 2, 0, 0.5));
  return *kStreet;
}

void latest(const datasets::SlamStream& stream, std::vector<Eigen::Vector3d>& sensors, std::vector<Eigen::Vector3d>& points) {
  std::unordered_map<std::uint64_t, Eigen::Vector3d> keyframes, by_point;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      keyframes[keyframe->id.value] = keyframe->position_W_C;
      for (const auto& o : keyframe->observations) by_point[o.point.value] = o.position_W;
    }
  }
  for (const auto& entry : keyframes) sensors.push_back(entry.second);
  for (const auto& entry : by_point) points.push_back(entry.second);
}

TEST(StreetEvidenceTest, EstimateRecoversTheGeneratorsCameraHeight) {
  std::vector<Eigen::Vector3d> sensors, points;
  latest(street().slam.stream, sensors, points);
  const SensorHeightEstimate estimate =
      estimateSensorHeight(sensors, points, street().scene.up_W, 1.0, TrajectoryEvidenceConfig{});
  std::printf("street estimate: %.3f m, spread %.3f m, %zu of %zu keyframes\n", estimate.height_m, estimate.spread_m,
              estimate.keyframes_used, estimate.keyframes_total);
  EXPECT_EQ(estimate.status, SensorHeightEstimate::Status::kDriven) << estimate.reason;
  EXPECT_NEAR(estimate.height_m, datasets::StreetSceneConfig{}.camera_height_m, 0.05);
}

/// Median of |reconstructed - true| road height straight below the true camera path: at every
/// scene frame (10 Hz, between keyframes too) between the first and the last keyframe, under the
/// camera and 0.6 m to either side.
double medianHeightErrorUnderPath(const mesher::TriangleMesh& mesh, std::size_t& missing) {
  const Street& s = street();
  const datasets::TriangleBvh truth(s.scene.ground_truth.mesh);
  const datasets::TriangleBvh reconstructed(mesh);
  std::vector<double> errors;
  missing = 0;
  const std::size_t first = s.slam.keyframes.front().frame, last = s.slam.keyframes.back().frame;
  for (std::size_t f = first; f <= last; ++f) {
    const Eigen::Isometry3d& T_W_C = s.scene.frames_T_W_C[f];
    for (double side : {-0.6, 0.0, 0.6}) {
      const Eigen::Vector3d origin = T_W_C.translation() + side * T_W_C.linear().col(0);
      const auto road = truth.firstHit(origin, -s.scene.up_W, 10.0);
      const auto surface = reconstructed.firstHit(origin, -s.scene.up_W, 10.0);
      if (!road) continue;
      if (!surface) {
        ++missing;
        continue;
      }
      errors.push_back(std::abs(surface->distance - road->distance));
    }
  }
  if (errors.empty()) return std::numeric_limits<double>::infinity();
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2), errors.end());
  return errors[errors.size() / 2];
}

/// The street meshed without or with trajectory evidence (as `terramesh mesh` does it); with it,
/// the mesher also knows up (so nothing under the driven ground is free) unless `ground_rule` is
/// false, and gets each keyframe's body view unless `body_views` is false.
mesher::TriangleMesh meshStreet(bool with_evidence, const TrajectoryEvidenceConfig& config = {},
                                bool ground_rule = true, bool body_views = true) {
  const Street& s = street();
  mesher::MesherConfig mesher_config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  RobotProfile car = loadRobotProfile(kRobots / "car.yaml");
  TrajectoryEvidenceConfig evidence_config = config;
  evidence_config.body_views = body_views;
  TrajectoryEvidence evidence(car, s.scene.up_W.normalized(), 1.0, 1.65, Eigen::Vector3d::UnitZ(), evidence_config);
  if (with_evidence && ground_rule) evidence.configureMesher(mesher_config);
  mesher::Mesher mesher(mesher_config);
  std::size_t keyframes = 0;
  for (const datasets::StreamEvent& event : s.slam.stream.events) {
    test_stream::applyEvent(mesher, event, with_evidence ? &evidence : nullptr);
    if (++keyframes % 15 == 0) {
      const mesher::InvariantReport report = mesher.checkInvariants();
      EXPECT_TRUE(report.ok()) << report.summary();
    }
  }
  const mesher::InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
  const mesher::TriangleMesh mesh = mesher.extractMesh();
  EXPECT_TRUE(mesher::analyzeTopology(mesh).isClosedManifold());
  if (with_evidence) {
    // Re-sent keyframes moved their samples: every driven vertex lies where its keyframe's last
    // pose puts it.
    std::unordered_map<std::uint64_t, Eigen::Vector3d> expected;
    std::unordered_map<std::uint64_t, const mesher::Keyframe*> last;
    for (const datasets::StreamEvent& event : s.slam.stream.events) {
      if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) last[keyframe->id.value] = keyframe;
    }
    for (const auto& entry : last) {
      for (const auto& sample : evidence.samplesOf(*entry.second)) expected[sample.point.value] = sample.position_W;
    }
    std::size_t driven = 0;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (mesh.driven_kind[v] != static_cast<std::uint8_t>(mesher::PointKind::kDrivenGround)) continue;
      ++driven;
      EXPECT_EQ(mesh.vertices[v], expected.at(mesh.vertex_keys[v].value));
    }
    EXPECT_GT(driven, s.slam.keyframes.size());
  }
  return mesh;
}

/// Fraction of points in the body volume between consecutive keyframes (0.4 and 0.9 m above the
/// road, under the camera and 0.5 m to either side, a quarter, half and three quarters of the way)
/// that lie in the mesh's free space; with `above_road_m` negative, of points that far under the
/// road instead.
double bodyVolumeFreeFraction(const mesher::TriangleMesh& mesh, std::vector<double> heights_m = {0.4, 0.9}) {
  const Street& s = street();
  const double camera_height_m = datasets::StreetSceneConfig{}.camera_height_m;
  std::size_t free = 0, total = 0;
  for (std::size_t k = 0; k + 1 < s.slam.keyframes.size(); ++k) {
    const Eigen::Isometry3d& a = s.slam.keyframes[k].true_T_W_C;
    const Eigen::Isometry3d& b = s.slam.keyframes[k + 1].true_T_W_C;
    for (double t : {0.25, 0.5, 0.75}) {
      for (double side : {-0.5, 0.0, 0.5}) {
        for (double above_road_m : heights_m) {
          const Eigen::Vector3d p = (1 - t) * a.translation() + t * b.translation() + side * a.linear().col(0) -
                                    (camera_height_m - above_road_m) * s.scene.up_W;
          free += test::insideClosedMesh(mesh, p);
          ++total;
        }
      }
    }
  }
  return static_cast<double>(free) / static_cast<double>(total);
}

TEST(StreetEvidenceTest, RoadUnderThePathIsCloserToTheTruthAndTheBodyVolumeFreeWithEvidence) {
  std::size_t missing_off = 0, missing_on = 0;
  const mesher::TriangleMesh without = meshStreet(false);
  const mesher::TriangleMesh with = meshStreet(true);
  const double off = medianHeightErrorUnderPath(without, missing_off);
  const double on = medianHeightErrorUnderPath(with, missing_on);
  std::printf("median road height error under the path: %.3f m without evidence (%zu misses), %.3f m with (%zu)\n",
              off, missing_off, on, missing_on);
  EXPECT_LT(on, off);
  EXPECT_LT(on, 0.05);
  // Evidence opens no hole under the path: probes that find no surface within 10 m below the
  // camera, at most 2 % more than without it (0 and 0 in the Release build, 2 and 0 of 291 in the
  // sanitizers' clang Debug build, 2026-12-02).
  const std::size_t probes = 3 * (street().slam.keyframes.back().frame - street().slam.keyframes.front().frame + 1);
  std::printf("%zu probes under the path\n", probes);
  EXPECT_LE(missing_on, missing_off + probes / 50);
  const double free_off = bodyVolumeFreeFraction(without);
  const double free_on = bodyVolumeFreeFraction(with);
  TrajectoryEvidenceConfig no_sweep;
  no_sweep.max_sweep_distance_m = 0;
  const double free_no_sweep = bodyVolumeFreeFraction(meshStreet(true, no_sweep));
  std::printf("body volume between keyframes in free space: %.3f without evidence, %.3f with (%.3f without the "
              "sweep rays)\n", free_off, free_on, free_no_sweep);
  EXPECT_GE(free_on, free_off);
  EXPECT_GE(free_on, free_no_sweep);
  EXPECT_GE(free_on, 0.95);

  // With the ground rule (no free cell under driven ground; over it, any ray crossing carves), the
  // body volume just above the road is freer than without it, and nothing under the road is free.
  const mesher::TriangleMesh without_rule = meshStreet(true, {}, false);
  const std::vector<double> low = {0.05, 0.1, 0.2};
  const double low_rule = bodyVolumeFreeFraction(with, low);
  const double low_no_rule = bodyVolumeFreeFraction(without_rule, low);
  const double under_rule = bodyVolumeFreeFraction(with, {-0.02, -0.05, -0.2});
  const double under_no_rule = bodyVolumeFreeFraction(without_rule, {-0.02, -0.05, -0.2});
  std::printf("body volume 0.05-0.2 m above the road in free space: %.3f with the ground rule, %.3f without; "
              "0.02-0.2 m under the road: %.3f with it, %.3f without\n", low_rule, low_no_rule, under_rule,
              under_no_rule);
  EXPECT_GE(low_rule, low_no_rule);
  EXPECT_LE(under_rule, 0.01);
  std::size_t missing_no_rule = 0;
  EXPECT_LE(on, medianHeightErrorUnderPath(without_rule, missing_no_rule) + 0.005);

  // The body views carve the body volume just above the road: 1.000 with them, 0.991 without
  // (2026-12-06). Views over the previous keyframe's base only left a few probes of 648 in the
  // wedge behind each keyframe, and took from it: 0.985.
  const mesher::TriangleMesh without_views = meshStreet(true, {}, true, false);
  const double low_no_views = bodyVolumeFreeFraction(without_views, low);
  std::printf("body volume 0.05-0.2 m above the road in free space: %.3f with the body views, %.3f without\n",
              low_rule, low_no_views);
  EXPECT_GE(low_rule, low_no_views);
}

}  // namespace
}  // namespace terramesh::traversability
