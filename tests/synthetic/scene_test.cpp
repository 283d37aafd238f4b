#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "datasets/kitti_odometry_reader.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::datasets {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
const std::string kKitti00 = std::string(TERRAMESH_SHARED_DIR) + "/data/kitti_poses/00.txt";

std::set<SurfaceLabel> labelsOf(const LabeledMesh& mesh) {
  return std::set<SurfaceLabel>(mesh.labels.begin(), mesh.labels.end());
}

/// What every ground truth must satisfy: sizes agree, geometry finite and non-degenerate, each
/// stored slope the angle of its face's normal to up, cameras above ground.
void expectSaneScene(const SyntheticScene& scene) {
  const LabeledMesh& gt = scene.ground_truth;
  ASSERT_NO_THROW(gt.validate());
  ASSERT_GT(gt.mesh.faces.size(), 100u);
  ASSERT_FALSE(scene.frames_T_W_C.empty());
  EXPECT_NEAR(scene.up_W.norm(), 1.0, 1e-12);
  for (const Eigen::Vector3d& v : gt.mesh.vertices) ASSERT_TRUE(v.allFinite());
  std::vector<bool> used(gt.mesh.vertices.size(), false);
  for (std::size_t f = 0; f < gt.mesh.faces.size(); ++f) {
    const auto& face = gt.mesh.faces[f];
    for (const std::uint32_t v : face) {
      ASSERT_LT(v, gt.mesh.vertices.size());
      used[v] = true;
    }
    const Eigen::Vector3d normal = (gt.mesh.vertices[face[1]] - gt.mesh.vertices[face[0]])
                                       .cross(gt.mesh.vertices[face[2]] - gt.mesh.vertices[face[0]]);
    ASSERT_GT(normal.norm(), 1e-8) << "degenerate face " << f;
    const double slope = std::acos(std::clamp(normal.normalized().dot(scene.up_W), -1.0, 1.0)) * kRadToDeg;
    ASSERT_NEAR(gt.slope_deg[f], slope, 1e-3) << "face " << f;
    if (gt.labels[f] == SurfaceLabel::kRoad) {
      ASSERT_LT(slope, 20.0) << "road face " << f << " is not ground";
    }
    if (gt.labels[f] == SurfaceLabel::kCeiling) {
      ASSERT_GT(slope, 170.0) << "ceiling face " << f;
    }
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "unused vertices";
  // Every camera has ground below it and is not inside a solid (the first surface below is seen
  // from its front).
  const TriangleBvh bvh(gt.mesh);
  for (std::size_t i = 0; i < scene.frames_T_W_C.size(); i += 25) {
    const Eigen::Vector3d camera = scene.frames_T_W_C[i].translation();
    const auto below = bvh.firstHit(camera, -scene.up_W, 10.0);
    ASSERT_TRUE(below.has_value()) << "no ground under frame " << i;
    EXPECT_LT(gt.slope_deg[below->face], 45.0) << "frame " << i << " is not above ground";
  }
}

TEST(StreetSceneTest, ProceduralStreetIsSaneWithAllItsParts) {
  StreetSceneConfig config;
  config.length_m = 250;
  const SyntheticScene scene = buildStreetScene(config);
  expectSaneScene(scene);
  EXPECT_EQ(scene.up_W, Eigen::Vector3d::UnitZ());
  const std::set<SurfaceLabel> expected = {SurfaceLabel::kRoad,     SurfaceLabel::kSidewalk,   SurfaceLabel::kCurb,
                                           SurfaceLabel::kWall,     SurfaceLabel::kObstacle,   SurfaceLabel::kVegetation,
                                           SurfaceLabel::kRamp};
  EXPECT_EQ(labelsOf(scene.ground_truth), expected);
  // Frames 0.8 m apart (8 m/s at 10 Hz) over the whole road.
  EXPECT_NEAR(static_cast<double>(scene.frames_T_W_C.size()), 250 / 0.8, 3.0);
}

TEST(StreetSceneTest, CamberCurbAndRampSlopesAreAnalytic) {
  StreetSceneConfig config;
  config.length_m = 200;
  config.max_grade_percent = 0.0;  // level road: the only slope of the road is its camber
  config.object_density = 0.0;
  const SyntheticScene scene = buildStreetScene(config);
  const LabeledMesh& gt = scene.ground_truth;
  const double camber_deg = std::atan(config.camber_percent / 100.0) * kRadToDeg;
  const double ramp_deg = config.ramp_slope_deg;
  int road = 0, curb_faces = 0, ramps = 0;
  for (std::size_t f = 0; f < gt.labels.size(); ++f) {
    if (gt.labels[f] == SurfaceLabel::kRoad) {
      EXPECT_NEAR(gt.slope_deg[f], camber_deg, 0.02) << "road face " << f;
      ++road;
    } else if (gt.labels[f] == SurfaceLabel::kRamp) {
      EXPECT_NEAR(gt.slope_deg[f], ramp_deg, 1e-4) << "ramp face " << f;
      ++ramps;
    } else if (gt.labels[f] == SurfaceLabel::kCurb && gt.slope_deg[f] > 45) {
      EXPECT_NEAR(gt.slope_deg[f], 90.0, 0.01) << "curb face " << f << " is vertical";
      ++curb_faces;
    }
  }
  EXPECT_GT(road, 1000);
  EXPECT_GT(curb_faces, 200);
  EXPECT_GE(ramps, 2) << "at least one ramp";
  // Heights across the section, by ray casting down 1 m from the start (heading +x, left = +y):
  // crown 0, road falling by the camber to the curb at 3.5 m, curb top 0.15 higher.
  const TriangleBvh bvh(gt.mesh);
  auto heightAt = [&](double x, double y) {
    const auto hit = bvh.firstHit({x, y, 10}, {0, 0, -1});
    EXPECT_TRUE(hit.has_value());
    return hit ? hit->point.z() : NAN;
  };
  const double crown = heightAt(1, 0);
  for (const double side : {-1.0, 1.0}) {
    const double road_edge = heightAt(1, side * 3.4) - crown;
    const double curb_top = heightAt(1, side * 3.6) - crown;
    EXPECT_NEAR(road_edge, -0.02 * 3.4, 0.002);
    EXPECT_NEAR(curb_top - road_edge, config.curb_height_m, 0.005);
  }
}

TEST(StreetSceneTest, FollowsRealKittiPosesWithCameraAboveTheRoad) {
  const PoseList poses = selectFrames(readKittiPoses(kKitti00), 0, 600);
  StreetSceneConfig config;
  config.length_m = 0.0;
  const SyntheticScene scene = buildStreetScene(config, poses);
  expectSaneScene(scene);
  EXPECT_EQ(scene.up_W, Eigen::Vector3d(0, -1, 0)) << "KITTI's world frame is y-down";
  ASSERT_EQ(scene.frames_T_W_C.size(), 600u);
  EXPECT_TRUE(scene.frames_T_W_C[123].isApprox(poses[123])) << "the camera follows the file";
  const TriangleBvh bvh(scene.ground_truth.mesh);
  for (std::size_t i = 0; i < 600; i += 50) {
    const auto below = bvh.firstHit(poses[i].translation(), {0, 1, 0}, 5.0);
    ASSERT_TRUE(below.has_value());
    EXPECT_NEAR(below->distance, config.camera_height_m, 0.15) << "frame " << i;
    EXPECT_EQ(scene.ground_truth.labels[below->face], SurfaceLabel::kRoad) << "frame " << i;
  }
  // A cut by distance keeps about that much trajectory.
  config.length_m = 100.0;
  const SyntheticScene short_scene = buildStreetScene(config, poses);
  double travelled = 0.0;
  for (std::size_t i = 1; i < short_scene.frames_T_W_C.size(); ++i) {
    travelled += (short_scene.frames_T_W_C[i].translation() - short_scene.frames_T_W_C[i - 1].translation()).norm();
  }
  EXPECT_NEAR(travelled, 100.0, 1.5);
}

TEST(StreetSceneTest, RepeatedPassesShareOneRoad) {
  // KITTI 00 drives several blocks twice: the ground truth must not stack road on road.
  const PoseList poses = readKittiPoses(kKitti00);
  StreetSceneConfig config;
  config.length_m = 0.0;
  config.object_density = 0.0;
  const SyntheticScene scene = buildStreetScene(config, poses);
  expectSaneScene(scene);
  const TriangleBvh bvh(scene.ground_truth.mesh);
  // Count road surfaces under each camera: a second layer would be hit from below the first.
  int doubled = 0;
  for (std::size_t i = 0; i < poses.size(); i += 10) {
    const auto first = bvh.firstHit(poses[i].translation(), {0, 1, 0}, 5.0);
    ASSERT_TRUE(first.has_value()) << "frame " << i;
    const auto second = bvh.firstHit(first->point + Eigen::Vector3d(0, 0.05, 0), {0, 1, 0}, 0.3);
    doubled += second.has_value();
  }
  EXPECT_LT(doubled, 10) << "frames over two overlapping road layers";
}

TEST(OffroadSceneTest, TerrainSpansGentleToSteepSlopes) {
  OffroadSceneConfig config;
  config.length_m = 120;
  const SyntheticScene scene = buildOffroadScene(config);
  expectSaneScene(scene);
  EXPECT_EQ(labelsOf(scene.ground_truth),
            (std::set<SurfaceLabel>{SurfaceLabel::kRoad, SurfaceLabel::kObstacle, SurfaceLabel::kVegetation}));
  double steepest = 0.0, flattest = 90.0;
  for (std::size_t f = 0; f < scene.ground_truth.labels.size(); ++f) {
    if (scene.ground_truth.labels[f] != SurfaceLabel::kVegetation) continue;
    steepest = std::max(steepest, static_cast<double>(scene.ground_truth.slope_deg[f]));
    flattest = std::min(flattest, static_cast<double>(scene.ground_truth.slope_deg[f]));
  }
  EXPECT_LT(flattest, 1.0);
  EXPECT_GT(steepest, config.bank_slope_deg);
  EXPECT_LT(steepest, std::atan(std::tan(config.bank_slope_deg / kRadToDeg) + std::tan(config.hill_slope_deg / kRadToDeg)) *
                          kRadToDeg + 1.0);
  // The camera rides camera_height_m above the track.
  const TriangleBvh bvh(scene.ground_truth.mesh);
  const auto below = bvh.firstHit(scene.frames_T_W_C[40].translation(), {0, 0, -1});
  ASSERT_TRUE(below.has_value());
  EXPECT_NEAR(below->distance, config.camera_height_m, 0.02);
  EXPECT_EQ(scene.ground_truth.labels[below->face], SurfaceLabel::kRoad);
}

TEST(GarageSceneTest, TwoLevelsRampPillarsAndOverhangs) {
  GarageSceneConfig config;
  const SyntheticScene scene = buildGarageScene(config);
  expectSaneScene(scene);
  EXPECT_EQ(labelsOf(scene.ground_truth),
            (std::set<SurfaceLabel>{SurfaceLabel::kRoad, SurfaceLabel::kWall, SurfaceLabel::kObstacle,
                                    SurfaceLabel::kCeiling, SurfaceLabel::kRamp}));
  const double rise = config.clear_height_m + config.slab_thickness_m;
  const double ramp_deg = std::atan(rise / kGarageRampLengthM) * kRadToDeg;
  for (std::size_t f = 0; f < scene.ground_truth.labels.size(); ++f) {
    if (scene.ground_truth.labels[f] == SurfaceLabel::kRamp) {
      EXPECT_NEAR(scene.ground_truth.slope_deg[f], ramp_deg, 1e-4);
    }
    if (scene.ground_truth.labels[f] == SurfaceLabel::kCeiling) {
      EXPECT_NEAR(scene.ground_truth.slope_deg[f], 180.0, 1e-4);
    }
  }
  const TriangleBvh bvh(scene.ground_truth.mesh);
  // Ceiling overhead on both levels; the camera reaches the upper level.
  double highest = -1;
  for (std::size_t i = 0; i < scene.frames_T_W_C.size(); i += 20) {
    const Eigen::Vector3d camera = scene.frames_T_W_C[i].translation();
    highest = std::max(highest, camera.z());
    const auto above = bvh.firstHit(camera, {0, 0, 1}, 10.0);
    ASSERT_TRUE(above.has_value()) << "frame " << i;
    EXPECT_TRUE(scene.ground_truth.labels[above->face] == SurfaceLabel::kCeiling) << "frame " << i;
  }
  EXPECT_NEAR(highest, rise + config.camera_height_m, 0.05);
  // A pillar stands from floor to ceiling: horizontal rays at several heights all hit it.
  for (const double z : {0.2, 1.4, config.clear_height_m - 0.2}) {
    const auto hit = bvh.firstHit({4, 8, z}, {1, 0, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->distance, 4.0 - config.pillar_size_m / 2, 1e-9) << "height " << z;
  }
  // The ground-floor drive (before the ramp) winds once round the pillar at (24, 8): free space
  // around the pillars has genus > 0 and the camera sees it from all sides.
  double winding = 0.0;
  Eigen::Vector2d previous = scene.frames_T_W_C.front().translation().head<2>() - Eigen::Vector2d(24, 8);
  std::size_t last_ground = 0;
  while (scene.frames_T_W_C[last_ground + 1].translation().z() < config.camera_height_m + 0.01) ++last_ground;
  for (std::size_t i = 1; i <= last_ground + 1; ++i) {
    const Eigen::Vector2d p = (i <= last_ground ? scene.frames_T_W_C[i] : scene.frames_T_W_C.front()).translation().head<2>() -
                              Eigen::Vector2d(24, 8);
    winding += std::atan2(previous.x() * p.y() - previous.y() * p.x(), previous.dot(p));
    previous = p;
  }
  EXPECT_NEAR(std::abs(winding), 2 * M_PI, 1e-6);
}

TEST(SyntheticSceneTest, SameSeedSameSceneOtherSeedOtherScene) {
  StreetSceneConfig config;
  config.length_m = 120;
  const SyntheticScene a = buildStreetScene(config);
  const SyntheticScene b = buildStreetScene(config);
  EXPECT_EQ(a.ground_truth.mesh.vertices, b.ground_truth.mesh.vertices);
  EXPECT_EQ(a.ground_truth.mesh.faces, b.ground_truth.mesh.faces);
  EXPECT_EQ(a.ground_truth.labels, b.ground_truth.labels);
  config.seed = 2;
  const SyntheticScene c = buildStreetScene(config);
  EXPECT_NE(a.ground_truth.mesh.vertices, c.ground_truth.mesh.vertices);
  OffroadSceneConfig offroad;
  offroad.length_m = 40;
  EXPECT_EQ(buildOffroadScene(offroad).ground_truth.mesh.vertices, buildOffroadScene(offroad).ground_truth.mesh.vertices);
}

TEST(SyntheticSceneTest, ConfigsReportEveryProblem) {
  StreetSceneConfig street;
  street.road_width_m = 1.0;
  street.camber_percent = -1.0;
  try {
    street.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("road_width_m"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("camber_percent"), std::string::npos);
  }
  OffroadSceneConfig offroad;
  offroad.length_m = 1;
  EXPECT_THROW(buildOffroadScene(offroad), std::invalid_argument);
  GarageSceneConfig garage;
  garage.length_m = 20;
  EXPECT_THROW(buildGarageScene(garage), std::invalid_argument);
  StreetSceneConfig ok;
  PoseList one_pose(2, Eigen::Isometry3d::Identity());
  EXPECT_THROW(buildStreetScene(ok, one_pose), std::invalid_argument) << "a trajectory that does not move";
}

}  // namespace
}  // namespace terramesh::datasets
