// Numerical robustness: georeferenced (UTM-sized) coordinates, points a billionth of a metre
// apart, coplanar, cospherical and collinear sets, cameras inside the cloud, keyframes that see
// nothing, enormous and tiny scales. Each gives a closed manifold with clean invariants, or a
// clear refusal (std::invalid_argument naming the keyframe); never a hang or a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

struct Outcome {
  MapSize size;
  MeshTopology topology;
  UpdateStats totals;
};

/// Runs every keyframe, checking invariants after each; the surface must end a closed manifold.
Outcome runChecked(const MesherConfig& config, const std::vector<Keyframe>& keyframes) {
  Mesher mesher(config);
  Outcome outcome;
  for (const Keyframe& keyframe : keyframes) {
    outcome.totals += mesher.integrateKeyframe(keyframe);
    const InvariantReport report = mesher.checkInvariants();
    EXPECT_TRUE(report.ok()) << "keyframe " << keyframe.id.value << ": " << report.summary();
    if (!report.ok()) break;
  }
  outcome.size = mesher.size();
  outcome.topology = analyzeTopology(mesher.extractMesh());
  EXPECT_TRUE(outcome.topology.isClosedManifold());
  EXPECT_EQ(outcome.totals.walk_failures, 0u);
  return outcome;
}

MesherConfig roomConfig() {
  MesherConfig config;
  config.steiner_step_m = 4.0;
  return config;
}

std::vector<Keyframe> room() {
  test::SceneOptions options;
  options.keyframes = 12;
  return test::boxRoomScene(options).keyframes;
}

/// x' = scale * x + offset, for cameras and points.
std::vector<Keyframe> transformed(std::vector<Keyframe> keyframes, double scale, const Eigen::Vector3d& offset) {
  for (Keyframe& keyframe : keyframes) {
    keyframe.position_W_C = scale * keyframe.position_W_C + offset;
    for (PointObservation& o : keyframe.observations) o.position_W = scale * o.position_W + offset;
  }
  return keyframes;
}

Keyframe keyframeAt(std::uint64_t id, const Eigen::Vector3d& centre, const std::vector<Eigen::Vector3d>& points,
                    std::uint64_t first_point = 0) {
  Keyframe keyframe;
  keyframe.id.value = id;
  keyframe.position_W_C = centre;
  for (std::size_t i = 0; i < points.size(); ++i) keyframe.observations.push_back({{first_point + i}, points[i]});
  return keyframe;
}

TEST(NumericalRobustness, ReferenceRoomMeshes) {
  const Outcome plain = runChecked(roomConfig(), room());
  EXPECT_GT(plain.size.inserted_points, 200u);
  EXPECT_GT(plain.topology.faces, 200u);
}

TEST(NumericalRobustness, UtmSizedOffsetsGiveTheSameMap) {
  const Outcome plain = runChecked(roomConfig(), room());
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(5e5, 0, 0), Eigen::Vector3d(0, 5e6, 0),
                                       Eigen::Vector3d(654321.37, 5432109.81, 312.5),
                                       Eigen::Vector3d(-4e6, -7e6, 1e3)}) {
    SCOPED_TRACE("offset " + std::to_string(offset.x()) + ", " + std::to_string(offset.y()));
    const Outcome utm = runChecked(roomConfig(), transformed(room(), 1.0, offset));
    // Coordinates lose their last bits (ulp 1e-9 m at 5e6 m), so the surfaces can differ a little.
    EXPECT_EQ(utm.size.inserted_points, plain.size.inserted_points);
    EXPECT_NEAR(static_cast<double>(utm.topology.faces), static_cast<double>(plain.topology.faces),
                0.1 * static_cast<double>(plain.topology.faces));
  }
}

TEST(NumericalRobustness, EnormousAndTinyScalesWithTheirUnitsGiveTheSameMap) {
  const Outcome plain = runChecked(roomConfig(), room());
  for (const double scale : {1e6, 1e-6}) {
    SCOPED_TRACE("scale " + std::to_string(scale));
    MesherConfig config = roomConfig();
    config.metres_per_unit = 1.0 / scale;
    const Outcome scaled = runChecked(config, transformed(room(), scale, Eigen::Vector3d::Zero()));
    EXPECT_EQ(scaled.size.inserted_points, plain.size.inserted_points);
    EXPECT_NEAR(static_cast<double>(scaled.topology.faces), static_cast<double>(plain.topology.faces),
                0.1 * static_cast<double>(plain.topology.faces));
  }
}

TEST(NumericalRobustness, TinyScaleInMetresMeshesInsideOneSteinerCell) {
  // The whole room is 12 micrometres wide, with the default metric distances.
  runChecked(roomConfig(), transformed(room(), 1e-6, Eigen::Vector3d(3.3, 1.1, 0.7)));
}

TEST(NumericalRobustness, EnormousScaleInMetresIsRefusedNotAHang) {
  // The room is 12,000 km wide but the map is said to be in metres: covering the cameras with a
  // 4 m Steiner grid would take about 1e19 nodes. The mesher must refuse, not try.
  const std::vector<Keyframe> keyframes = transformed(room(), 1e6, Eigen::Vector3d::Zero());
  Mesher mesher(roomConfig());
  std::size_t refused = 0;
  for (const Keyframe& keyframe : keyframes) {
    try {
      mesher.integrateKeyframe(keyframe);
    } catch (const std::invalid_argument& error) {
      ++refused;
      EXPECT_NE(std::string(error.what()).find("Steiner grid"), std::string::npos) << error.what();
    }
  }
  EXPECT_GT(refused, 0u);
  const InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_TRUE(analyzeTopology(mesher.extractMesh()).isClosedManifold());
}

TEST(NumericalRobustness, PointsABillionthOfAMetreApart) {
  std::vector<Keyframe> keyframes = room();
  const Eigen::Vector3d tiny = 1e-9 * Eigen::Vector3d(0.6, 0.64, 0.48);
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d::Zero().eval(), Eigen::Vector3d(654321.0, 5432109.0, 0.0)}) {
    SCOPED_TRACE("offset " + std::to_string(offset.y()));
    std::vector<Keyframe> twins = transformed(keyframes, 1.0, offset);
    for (Keyframe& keyframe : twins) {
      const std::size_t n = keyframe.observations.size();
      for (std::size_t i = 0; i < n; ++i) {
        const PointObservation& o = keyframe.observations[i];
        keyframe.observations.push_back({{o.point.value + 1'000'000}, o.position_W + tiny});
      }
    }
    const Outcome outcome = runChecked(roomConfig(), twins);
    EXPECT_GT(outcome.size.inserted_points, 200u);
  }
}

TEST(NumericalRobustness, CosphericalPointsWithCamerasInside) {
  // Every integer point on the sphere of radius 15 (exactly cospherical), seen from cameras
  // inside the sphere.
  std::vector<Eigen::Vector3d> sphere;
  for (int x = -15; x <= 15; ++x) {
    for (int y = -15; y <= 15; ++y) {
      for (int z = -15; z <= 15; ++z) {
        if (x * x + y * y + z * z == 225) sphere.emplace_back(x, y, z);
      }
    }
  }
  ASSERT_GT(sphere.size(), 100u);
  std::vector<Keyframe> keyframes;
  for (int k = 0; k < 8; ++k) {
    const double a = 0.8 * k;
    keyframes.push_back(keyframeAt(k, Eigen::Vector3d(4 * std::cos(a), 4 * std::sin(a), k - 4.0), sphere));
  }
  const Outcome outcome = runChecked(roomConfig(), keyframes);
  EXPECT_EQ(outcome.size.inserted_points, sphere.size());
  EXPECT_GT(outcome.topology.faces, 50u);
}

TEST(NumericalRobustness, CoplanarPointsSeenFromBothSides) {
  std::vector<Eigen::Vector3d> plane;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j) plane.emplace_back(i, j, 0.0);
  }
  std::vector<Keyframe> keyframes;
  for (int k = 0; k < 8; ++k) {
    keyframes.push_back(keyframeAt(k, Eigen::Vector3d(2.0 + k, 5.5, k % 2 == 0 ? 3.0 : -3.0), plane));
  }
  const Outcome outcome = runChecked(roomConfig(), keyframes);
  EXPECT_EQ(outcome.size.inserted_points, plane.size());
}

TEST(NumericalRobustness, CollinearPointsOnALineThroughTheCameras) {
  // Every ray runs along the line, through the vertices of the nearer points: degenerate walks.
  std::vector<Eigen::Vector3d> line;
  for (int t = 1; t <= 30; ++t) line.emplace_back(0.5 * t, 0.0, 1.0);
  std::vector<Keyframe> keyframes;
  keyframes.push_back(keyframeAt(0, Eigen::Vector3d(-1.0, 0.0, 1.0), line));   // on the line
  keyframes.push_back(keyframeAt(1, Eigen::Vector3d(-2.5, 0.0, 1.0), line));   // on the line
  keyframes.push_back(keyframeAt(2, Eigen::Vector3d(7.0, 3.0, 2.0), line));    // off it
  keyframes.push_back(keyframeAt(3, Eigen::Vector3d(5.0, 0.0, 1.0), line));    // on a vertex
  const Outcome outcome = runChecked(roomConfig(), keyframes);
  EXPECT_EQ(outcome.size.inserted_points, line.size());
  EXPECT_GT(outcome.totals.walk_fallbacks, 0u) << "rays along the line are degenerate";
}

TEST(NumericalRobustness, CamerasInsideARandomCloud) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::vector<Eigen::Vector3d> cloud;
  for (int i = 0; i < 400; ++i) cloud.emplace_back(u(rng), u(rng), u(rng));
  std::vector<Keyframe> keyframes;
  for (int k = 0; k < 10; ++k) keyframes.push_back(keyframeAt(k, Eigen::Vector3d(u(rng), u(rng), u(rng)), cloud));
  const Outcome outcome = runChecked(roomConfig(), keyframes);
  EXPECT_EQ(outcome.size.inserted_points, cloud.size());
  EXPECT_GT(outcome.size.outside_cells, 100u);
}

TEST(NumericalRobustness, KeyframesThatSeeNothing) {
  std::vector<Keyframe> keyframes = room();
  std::vector<Keyframe> stream;
  stream.push_back(keyframeAt(100, Eigen::Vector3d(1, 1, 1), {}));  // first of all: nothing seen
  std::uint64_t id = 200;
  for (const Keyframe& keyframe : keyframes) {
    stream.push_back(keyframe);
    // Sees only points far out of range (500 m away).
    stream.push_back(keyframeAt(id, keyframe.position_W_C,
                                {keyframe.position_W_C + Eigen::Vector3d(500, 0, 0)}, 5'000'000 + id));
    ++id;
  }
  const Outcome outcome = runChecked(roomConfig(), stream);
  EXPECT_GT(outcome.size.inserted_points, 200u);
  EXPECT_GT(outcome.totals.observations_too_far, 0u);
}

}  // namespace
}  // namespace terramesh::mesher
