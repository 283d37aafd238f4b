// Degenerate and invalid input: coplanar points, duplicates, a point at a camera centre, a camera
// on a vertex, empty keyframes, non-finite values, invalid configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

MesherConfig smallConfig() {
  MesherConfig config;
  config.steiner_step_m = 4.0;
  return config;
}

void expectInvariants(const Mesher& mesher) {
  const InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
}

Keyframe keyframe(std::uint64_t id, const Eigen::Vector3d& centre,
                  const std::vector<std::pair<std::uint64_t, Eigen::Vector3d>>& points) {
  Keyframe k;
  k.id.value = id;
  k.position_W_C = centre;
  for (const auto& [point, position] : points) k.observations.push_back({{point}, position});
  return k;
}

/// Points on a 5 x 5 grid in the plane z = 0 (exactly coplanar, on round coordinates).
std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> planeGrid() {
  std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> points;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) points.push_back({points.size(), Eigen::Vector3d(i, j, 0)});
  }
  return points;
}

TEST(DegenerateInput, ExactlyCoplanarPointsOnRoundCoordinates) {
  Mesher mesher(smallConfig());
  for (int k = 0; k < 6; ++k) {
    mesher.integrateKeyframe(keyframe(k, Eigen::Vector3d(k * 0.5, 2.0, 3.0), planeGrid()));
    expectInvariants(mesher);
  }
  EXPECT_EQ(mesher.size().inserted_points, 25u);
  EXPECT_TRUE(analyzeTopology(mesher.extractMesh()).isClosedManifold());
}

TEST(DegenerateInput, TwoPointsAtTheSamePositionInsertOnce) {
  Mesher mesher(smallConfig());
  auto points = planeGrid();
  points.push_back({100, points[7].second});  // same place, other id
  UpdateStats totals;
  for (int k = 0; k < 3; ++k) {
    totals += mesher.integrateKeyframe(keyframe(k, Eigen::Vector3d(k, 2.0, 3.0), points));
    expectInvariants(mesher);
  }
  EXPECT_EQ(totals.duplicate_points, 2u);  // refused at keyframes 1 and 2
  EXPECT_EQ(mesher.size().inserted_points, 25u);
}

TEST(DegenerateInput, PointAtACameraCentreGetsNoRayFromThatCamera) {
  Mesher mesher(smallConfig());
  auto points = planeGrid();
  const Eigen::Vector3d centre(2.0, 2.0, 3.0);
  points.push_back({200, centre});
  UpdateStats totals;
  totals += mesher.integrateKeyframe(keyframe(0, Eigen::Vector3d(0.5, 1.5, 3.2), points));
  totals += mesher.integrateKeyframe(keyframe(1, Eigen::Vector3d(1.0, 2.5, 2.9), points));
  totals += mesher.integrateKeyframe(keyframe(2, centre, points));  // camera on the vertex
  expectInvariants(mesher);
  EXPECT_EQ(totals.rays_skipped, 1u);
  EXPECT_GT(totals.walk_fallbacks, 0u) << "rays from a camera on a vertex walk from a displaced camera";
  EXPECT_EQ(totals.walk_failures, 0u);
  EXPECT_EQ(mesher.size().inserted_points, 26u);
  EXPECT_TRUE(analyzeTopology(mesher.extractMesh()).isClosedManifold());
}

TEST(DegenerateInput, EmptyKeyframesAreHarmless) {
  Mesher mesher(smallConfig());
  mesher.integrateKeyframe(keyframe(0, Eigen::Vector3d(0, 0, 0), {}));
  expectInvariants(mesher);
  for (int k = 1; k < 4; ++k) mesher.integrateKeyframe(keyframe(k, Eigen::Vector3d(k, 2.0, 3.0), planeGrid()));
  mesher.integrateKeyframe(keyframe(9, Eigen::Vector3d(1, 1, 1), {}));
  expectInvariants(mesher);
  EXPECT_EQ(mesher.size().inserted_points, 25u);
  EXPECT_EQ(mesher.size().keyframes, 5u);
}

TEST(DegenerateInput, NonFiniteValuesAreRejectedAndLeaveTheMapUnchanged) {
  Mesher mesher(smallConfig());
  for (int k = 0; k < 3; ++k) mesher.integrateKeyframe(keyframe(k, Eigen::Vector3d(k, 2.0, 3.0), planeGrid()));
  const MapSize before = mesher.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto points = planeGrid();
  points[3].second.y() = nan;
  EXPECT_THROW(mesher.integrateKeyframe(keyframe(7, Eigen::Vector3d(1, 1, 3), points)),
               std::invalid_argument);
  EXPECT_THROW(mesher.integrateKeyframe(keyframe(8, Eigen::Vector3d(nan, 1, 3), planeGrid())),
               std::invalid_argument);
  Keyframe bad_rotation = keyframe(9, Eigen::Vector3d(1, 1, 3), planeGrid());
  bad_rotation.rotation_W_C.coeffs().setConstant(std::numeric_limits<double>::infinity());
  EXPECT_THROW(mesher.integrateKeyframe(bad_rotation), std::invalid_argument);
  const MapSize after = mesher.size();
  EXPECT_EQ(after.keyframes, before.keyframes);
  EXPECT_EQ(after.rays, before.rays);
  EXPECT_EQ(after.cells, before.cells);
  expectInvariants(mesher);
}

TEST(DegenerateInput, APointListedTwiceInOneKeyframeIsRejected) {
  Mesher mesher(smallConfig());
  auto points = planeGrid();
  points.push_back({3, Eigen::Vector3d(9, 9, 0)});
  try {
    mesher.integrateKeyframe(keyframe(4, Eigen::Vector3d(1, 1, 3), points));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("point 3"), std::string::npos) << error.what();
  }
  EXPECT_EQ(mesher.size().keyframes, 0u);
}

TEST(DegenerateInput, FarOutliersBeyondRangeAreIgnored) {
  MesherConfig config = smallConfig();
  config.max_camera_distance_m = 20.0;
  Mesher mesher(config);
  auto points = planeGrid();
  points.push_back({300, Eigen::Vector3d(1e6, -2e6, 5e5)});
  for (int k = 0; k < 3; ++k) mesher.integrateKeyframe(keyframe(k, Eigen::Vector3d(k, 2.0, 3.0), points));
  EXPECT_EQ(mesher.size().inserted_points, 25u);
  expectInvariants(mesher);
}

TEST(MesherConfigValidation, ListsEveryProblem) {
  MesherConfig config;
  config.min_views = 0;
  config.steiner_step_m = -1;
  config.weight_crossed = std::nan("");
  const std::vector<std::string> problems = config.problems();
  EXPECT_EQ(problems.size(), 3u);
  try {
    Mesher mesher(config);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("min_views"), std::string::npos);
    EXPECT_NE(message.find("steiner_step_m"), std::string::npos);
    EXPECT_NE(message.find("weight_crossed"), std::string::npos);
  }
}

TEST(MesherConfigValidation, DrivenGroundUpIsZeroOrAUnitVector) {
  MesherConfig config;
  EXPECT_TRUE(config.problems().empty());  // zero: not given
  config.driven_ground_up_W = Eigen::Vector3d(0, 0, 2);
  ASSERT_EQ(config.problems().size(), 1u);
  EXPECT_NE(config.problems().front().find("driven_ground_up_W"), std::string::npos);
  config.driven_ground_up_W = Eigen::Vector3d(0, std::nan(""), 1);
  EXPECT_EQ(config.problems().size(), 1u);
  config.driven_ground_up_W = Eigen::Vector3d(0.6, 0, 0.8);
  EXPECT_TRUE(config.problems().empty());
}

TEST(MesherConfigValidation, BaselinesNeedAFixedGrid) {
  MesherConfig config = MesherConfig::forMode(MesherMode::kLitvinov13);
  EXPECT_FALSE(config.problems().empty());
  config.fixed_grid_bounds_W = AxisAlignedBox{Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()};
  EXPECT_TRUE(config.problems().empty());
  EXPECT_EQ(parseMesherMode("romanoni15"), MesherMode::kRomanoni15);
  EXPECT_FALSE(parseMesherMode("fast").has_value());
}

TEST(MesherConfigValidation, MetresPerUnitScalesDistancesIntoMapUnits) {
  MesherConfig config;
  config.metres_per_unit = 16.589;
  EXPECT_NEAR(config.steinerStepUnits(), 10.0 / 16.589, 1e-12);
  EXPECT_NEAR(config.maxCameraDistanceUnits(), 40.0 / 16.589, 1e-12);
}

}  // namespace
}  // namespace terramesh::mesher
