#include "traversability/robot_profile.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>

#include "common/input_error.h"
#include "test_support/analytic_scenes.h"
#include "test_support/temp_dir.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

std::filesystem::path writeText(const test::TempDir& dir, const std::string& text) {
  const std::filesystem::path path = dir / "robot.yaml";
  std::ofstream(path) << text;
  return path;
}

/// Loads `text` and returns the InputError's message (fails if it loads).
std::string loadError(const std::string& text) {
  test::TempDir dir;
  const std::filesystem::path path = writeText(dir, text);
  try {
    loadRobotProfile(path);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "loaded without error:\n" << text;
  return "";
}

TEST(RobotProfileTest, EveryShippedProfileLoadsAndValidates) {
  for (const char* name : {"small_wheeled", "car", "legged"}) {
    const RobotProfile profile = loadRobotProfile(kRobots / (std::string(name) + ".yaml"));
    EXPECT_EQ(profile.name, name);
    EXPECT_NO_THROW(profile.validate());
    EXPECT_FALSE(profile.gravity_W.has_value()) << "shipped profiles estimate gravity";
  }
}

TEST(RobotProfileTest, ShippedProfilesMatchTheIssue) {
  const RobotProfile wheeled = loadRobotProfile(kRobots / "small_wheeled.yaml");
  EXPECT_GE(wheeled.max_step_m, 0.15) << "a 0.15 m curb is passable";
  EXPECT_LT(wheeled.max_step_m, 0.4) << "a 0.4 m ledge is not";
  const RobotProfile car = loadRobotProfile(kRobots / "car.yaml");
  EXPECT_EQ(car.footprint, FootprintShape::kRectangle);
  EXPECT_NEAR(car.footprint_length_m, 4.8, 0.1);
  EXPECT_NEAR(car.footprint_width_m, 1.8, 0.1);
  EXPECT_GE(car.min_clearance_m, 1.5);
  EXPECT_NEAR(car.footprintCircumradiusM(), 0.5 * std::hypot(4.8, 1.8), 1e-12);
  EXPECT_EQ(car.motion_model, MotionModel::kDiffDrive) << "a car faces its travel";
  EXPECT_EQ(loadRobotProfile(kRobots / "legged.yaml").motion_model, MotionModel::kOmni) << "a quadruped walks sideways";
}

TEST(RobotProfileTest, WriteThenLoadGivesTheSameProfile) {
  RobotProfile profile;
  profile.name = "custom";
  profile.footprint = FootprintShape::kRectangle;
  profile.footprint_length_m = 1.234567890123;
  profile.footprint_width_m = 0.7;
  profile.max_slope_deg = 12.5;
  profile.weights.roughness = 0.25;
  profile.contact_headings = 12;
  profile.motion_model = MotionModel::kOmni;
  profile.min_rays = 5;
  profile.gravity_W = Eigen::Vector3d(0.1, -9.8, 0.2);
  test::TempDir dir;
  writeRobotProfile(dir / "p.yaml", profile);
  const RobotProfile back = loadRobotProfile(dir / "p.yaml");
  EXPECT_EQ(back.name, profile.name);
  EXPECT_EQ(back.footprint, profile.footprint);
  EXPECT_EQ(back.footprint_length_m, profile.footprint_length_m);
  EXPECT_EQ(back.footprint_width_m, profile.footprint_width_m);
  EXPECT_EQ(back.max_slope_deg, profile.max_slope_deg);
  EXPECT_EQ(back.weights.roughness, profile.weights.roughness);
  EXPECT_EQ(back.contact_headings, profile.contact_headings);
  EXPECT_EQ(back.motion_model, MotionModel::kOmni);
  EXPECT_EQ(back.min_rays, profile.min_rays);
  ASSERT_TRUE(back.gravity_W.has_value());
  EXPECT_EQ(*back.gravity_W, *profile.gravity_W);
}

TEST(RobotProfileTest, BadValuesNameTheKeyTheLineAndTheRange) {
  const std::string message = loadError("name: r\nfootprint: {radius_m: 0.3}\nmax_slope_deg: 95\n");
  EXPECT_NE(message.find("max_slope_deg"), std::string::npos) << message;
  EXPECT_NE(message.find("line 3"), std::string::npos) << message;
  EXPECT_NE(message.find("95"), std::string::npos) << message;
  EXPECT_NE(message.find("(0, 90)"), std::string::npos) << message;

  const std::string text = loadError("name: r\nmax_step_m: high\n");
  EXPECT_NE(text.find("max_step_m"), std::string::npos) << text;
  EXPECT_NE(text.find("high"), std::string::npos) << text;

  const std::string nested = loadError("name: r\nweights:\n  slope: -1\n");
  EXPECT_NE(nested.find("weights.slope"), std::string::npos) << nested;
  EXPECT_NE(nested.find("line 3"), std::string::npos) << nested;

  const std::string integer = loadError("name: r\ncontact_headings: 2.5\n");
  EXPECT_NE(integer.find("contact_headings"), std::string::npos) << integer;

  const std::string motion = loadError("name: r\nmotion_model: holonomic\n");
  EXPECT_NE(motion.find("line 2, key motion_model"), std::string::npos) << motion;
  EXPECT_NE(motion.find("\"holonomic\": expected diff_drive or omni"), std::string::npos) << motion;
}

TEST(RobotProfileTest, UnknownKeysAreErrors) {
  const std::string top = loadError("name: r\nmax_speed: 3\n");
  EXPECT_NE(top.find("max_speed"), std::string::npos) << top;
  EXPECT_NE(top.find("unknown"), std::string::npos) << top;
  const std::string nested = loadError("name: r\nfootprint: {radius_m: 0.3, height_m: 1}\n");
  EXPECT_NE(nested.find("footprint.height_m"), std::string::npos) << nested;
}

TEST(RobotProfileTest, FootprintMustBeOneShapeAndNameIsRequired) {
  EXPECT_NE(loadError("name: r\nfootprint: {radius_m: 0.3, length_m: 1}\n").find("footprint"), std::string::npos);
  EXPECT_NE(loadError("name: r\nfootprint: {length_m: 1}\n").find("footprint"), std::string::npos);
  EXPECT_NE(loadError("max_step_m: 0.1\n").find("name"), std::string::npos);
  EXPECT_NE(loadError("name: r\ngravity: [0, 0]\n").find("gravity"), std::string::npos);
  EXPECT_NE(loadError("name: r\ngravity: down\n").find("gravity"), std::string::npos);
  EXPECT_NE(loadError("name: r\ninscribed_radius_m: 2\ninflation_radius_m: 1\n").find("inflation_radius_m"),
            std::string::npos);
}

TEST(RobotProfileTest, GravityAutoOrVector) {
  test::TempDir dir;
  EXPECT_FALSE(loadRobotProfile(writeText(dir, "name: r\ngravity: auto\n")).gravity_W.has_value());
  const RobotProfile p = loadRobotProfile(writeText(dir, "name: r\ngravity: [0, 9.81, 0]\n"));
  ASSERT_TRUE(p.gravity_W.has_value());
  EXPECT_EQ(*p.gravity_W, Eigen::Vector3d(0, 9.81, 0));
}

TEST(RobotProfileTest, ValidateListsEveryProblem) {
  RobotProfile profile;
  profile.max_slope_deg = -1;
  profile.min_support = 2;
  profile.contact_headings = 0;
  try {
    profile.validate();
    FAIL() << "validated";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("max_slope_deg: -1"), std::string::npos) << m;
    EXPECT_NE(m.find("min_support: 2"), std::string::npos) << m;
    EXPECT_NE(m.find("contact_headings: 0"), std::string::npos) << m;
  }
}

TEST(MapFrameTest, UpFromKittiCamerasIsMinusY) {
  // KITTI: world = first camera frame (y down); the car drives and turns about the y axis.
  std::vector<Eigen::Matrix3d> rotations;
  for (double yaw : {0.0, 0.3, 1.2, -2.0, 3.0}) {
    rotations.push_back(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                        Eigen::AngleAxisd(0.02 * yaw, Eigen::Vector3d::UnitX()).toRotationMatrix());
  }
  const Eigen::Vector3d up = estimateUpFromCameras(rotations);
  EXPECT_NEAR(up.y(), -1.0, 1e-3);
  EXPECT_NEAR(up.norm(), 1.0, 1e-12);
}

TEST(MapFrameTest, UpFromZUpSceneCamerasIsPlusZ) {
  // Cameras of the z-up test scenes look ahead and down; their image up has a positive z.
  std::vector<Eigen::Matrix3d> rotations;
  for (const auto& keyframe : test::planeScene(test::SceneOptions{}).keyframes) {
    rotations.push_back(keyframe.rotation_W_C.toRotationMatrix());
  }
  const Eigen::Vector3d up = estimateUpFromCameras(rotations);
  EXPECT_GT(up.z(), 0.8);
}

TEST(MapFrameTest, UpFromKittiVelodyneIsMinusY) {
  // A Velodyne frame (x forward, y left, z up) mounted level on a KITTI car: in the y-down world
  // its z axis points along -y. With the camera's axis (-y) the estimate would be wrong.
  Eigen::Matrix3d cam0_from_velodyne;
  cam0_from_velodyne << 0, -1, 0,  //
      0, 0, -1,                     //
      1, 0, 0;
  std::vector<Eigen::Matrix3d> rotations;
  for (double yaw : {0.0, 0.5, -1.4}) {
    rotations.push_back(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix() * cam0_from_velodyne);
  }
  const Eigen::Vector3d up = estimateUpFromCameras(rotations, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(up.y(), -1.0, 1e-9);
  EXPECT_LT(std::abs(estimateUpFromCameras(rotations).y()), 0.5);
  EXPECT_THROW(estimateUpFromCameras(rotations, Eigen::Vector3d::Zero()), std::invalid_argument);
}

TEST(MapFrameTest, BadInputsThrow) {
  EXPECT_THROW(estimateUpFromCameras({}), std::invalid_argument);
  const Eigen::Matrix3d flip = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_THROW(estimateUpFromCameras({Eigen::Matrix3d::Identity(), flip}), std::invalid_argument);
  MapFrame frame;
  frame.metres_per_unit = 0;
  EXPECT_THROW(frame.validate(), std::invalid_argument);
  frame = MapFrame{};
  frame.up_W = Eigen::Vector3d::Zero();
  EXPECT_THROW(frame.validate(), std::invalid_argument);
  RobotProfile bad;
  bad.max_step_m = -1;
  EXPECT_THROW(TraversabilityMap(bad, MapFrame{}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::traversability
