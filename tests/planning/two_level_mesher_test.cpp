// Between two floors through the whole pipeline: a small two-level scene (a ground floor, a deck
// over part of it, a ramp up to the deck) observed by a camera that drives under the deck and then
// up the ramp, meshed by the mesher, layered for a robot, planned on. The path from the ground
// floor under the deck to the deck right above it must go over the ramp; it is checked against the
// scene's analytic geometry, not against our own map.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "mesher/mesher.h"
#include "planning/face_graph.h"
#include "planning/surface_planner.h"
#include "traversability/robot_profile.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::planning {
namespace {

// The scene (z up, metres): ground z = 0 over [-6, 30] x [0, 10]; a deck (slab [16, 30] x [0, 10] x
// [2.6, 3.0]) over the ground's far half; a ramp (a solid wedge over [0, 16] x [7, 10], top
// z = 3 x / 16, 10.6 degrees) from the ground up to the deck's top.
constexpr double kDeckX = 16, kDeckBottom = 2.6, kDeckTop = 3.0, kRampY = 7, kWidth = 10, kLength = 30;

double rampHeight(double x) { return kDeckTop * x / kDeckX; }

bool inRampFootprint(const Eigen::Vector3d& p) { return p.x() >= 0 && p.x() <= kDeckX && p.y() >= kRampY && p.y() <= kWidth; }

bool inMatter(const Eigen::Vector3d& p) {
  if (p.z() < 0) return true;
  const bool over_plan = p.x() >= 0 && p.x() <= kLength && p.y() >= 0 && p.y() <= kWidth;
  if (over_plan && p.x() >= kDeckX && p.z() >= kDeckBottom && p.z() <= kDeckTop) return true;
  return inRampFootprint(p) && p.z() < rampHeight(p.x());
}

/// Height of the drivable surface nearest to z at (x, y): the ground, the ramp or the deck top.
double nearestDrivableHeight(const Eigen::Vector3d& p) {
  double best = 0;
  if (inRampFootprint(p)) best = rampHeight(p.x());
  if (p.x() >= kDeckX && std::abs(p.z() - kDeckTop) < std::abs(p.z() - best)) best = kDeckTop;
  return best;
}

struct Patch {
  Eigen::Vector3d origin, u, v;
};

Eigen::Quaterniond lookAlong(const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d rotation;
  rotation << x, z.cross(x), z;
  return Eigen::Quaterniond(rotation);
}

std::vector<mesher::Keyframe> twoLevelStream() {
  const std::vector<Patch> patches = {
      {{-6, 0, 0}, {kLength + 6, 0, 0}, {0, kRampY, 0}},                            // ground beside the ramp
      {{-6, kRampY, 0}, {6, 0, 0}, {0, kWidth - kRampY, 0}},                        // ground before its foot
      {{kDeckX, kRampY, 0}, {kLength - kDeckX, 0, 0}, {0, kWidth - kRampY, 0}},     // ground under the deck's ramp side
      {{0, kRampY, 0}, {kDeckX, 0, kDeckTop}, {0, kWidth - kRampY, 0}},             // ramp top
      {{kDeckX, 0, kDeckTop}, {kLength - kDeckX, 0, 0}, {0, kWidth, 0}},            // deck top
      {{kDeckX, 0, kDeckBottom}, {kLength - kDeckX, 0, 0}, {0, kWidth, 0}},         // deck underside
      {{kDeckX, 0, kDeckBottom}, {0, kRampY, 0}, {0, 0, kDeckTop - kDeckBottom}}};  // deck front
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (const Patch& p : patches) {
    const long count = std::lround(p.u.cross(p.v).norm() * 8.0);
    for (long i = 0; i < count; ++i) points.push_back(p.origin + unit(rng) * p.u + unit(rng) * p.v);
  }
  // Ramp side (y = 7, below the ramp's top): a triangle, sampled by rejection.
  for (int i = 0; i < 200; ++i) {
    const double x = kDeckX * unit(rng), z = kDeckTop * unit(rng);
    if (z < rampHeight(x)) points.emplace_back(x, kRampY, z);
  }
  // Under the deck along y = 3.5, back out, then up the ramp along y = 8.5 and over the deck.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> cameras;  // centre, forward
  for (int k = 0; k < 17; ++k) cameras.push_back({{-5.0 + 2.0 * k, 3.5 + 0.3 * std::sin(k), 1.3}, {1, 0, -0.25}});
  for (int k = 0; k < 8; ++k) cameras.push_back({{27.0 - 4.0 * k, 5.0, 1.3}, {-1, 0.2, -0.25}});
  for (int k = 0; k < 18; ++k) {
    const double x = -5.5 + 2.0 * k;
    const double ground = x <= 0 ? 0.0 : x <= kDeckX ? rampHeight(x) : kDeckTop;
    cameras.push_back({{x, 8.5 - (x > kDeckX ? 3.5 * (x - kDeckX) / (kLength - kDeckX) : 0.0), ground + 1.3},
                       {1, x > kDeckX ? -0.3 : 0.0, -0.35}});
  }
  std::vector<mesher::Keyframe> keyframes;
  const double cos_half_fov = std::cos(60.0 * M_PI / 180.0);
  for (std::size_t k = 0; k < cameras.size(); ++k) {
    const auto& [centre, forward] = cameras[k];
    mesher::Keyframe keyframe;
    keyframe.id.value = k;
    keyframe.position_W_C = centre;
    keyframe.rotation_W_C = lookAlong(forward);
    const Eigen::Vector3d f = forward.normalized();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d offset = points[i] - centre;
      const double distance = offset.norm();
      if (distance > 15.0 || offset.dot(f) < cos_half_fov * distance) continue;
      bool hidden = false;
      for (double s = 0.05; s < distance - 0.05 && !hidden; s += 0.05) hidden = inMatter(centre + offset * (s / distance));
      if (!hidden) keyframe.observations.push_back({{i}, points[i]});
    }
    keyframes.push_back(std::move(keyframe));
  }
  return keyframes;
}

traversability::LayeredMesh twoLevelMap(const traversability::RobotProfile& profile) {
  mesher::MesherConfig config;
  config.steiner_step_m = 4.0;
  mesher::Mesher mesher(config);
  for (const mesher::Keyframe& keyframe : twoLevelStream()) mesher.integrateKeyframe(keyframe);
  return traversability::TraversabilityMap::computeForMesh(mesher.extractMesh(), profile, traversability::MapFrame{},
                                                           static_cast<std::uint32_t>(profile.min_rays));
}

TEST(TwoLevelMesherTest, FromUnderTheDeckToItsTopOverTheRamp) {
  const traversability::RobotProfile profile = traversability::loadRobotProfile(
      std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots" / "small_wheeled.yaml");
  setOmplLogging(false);
  const traversability::LayeredMesh map = twoLevelMap(profile);
  WalkabilityConfig walkability;
  walkability.min_lethal_distance_m = profile.inscribed_radius_m;
  const FaceGraph graph(map, walkability);
  const Eigen::Vector3d start(24, 3.5, 0), goal(24, 3.5, kDeckTop);  // the goal is right above the start
  PlannerConfig config;
  config.snap_radius_m = 0.5;
  const PlanResult result = planOnFaceGraph(graph, start, goal, config);
  ASSERT_TRUE(result.solved()) << toString(result.status) << ": " << result.reason << " (" << graph.walkableFaceCount()
                               << " walkable faces of " << graph.faceCount() << ", " << graph.componentCount()
                               << " components)";
  // The only way up is the ramp: the path is far longer than the 3 m between the floors, it has
  // points on the ramp's middle, and every point lies on the true ground, ramp or deck top.
  EXPECT_GT(result.length_m, 2 * (24.0 - kDeckX));
  bool on_ramp = false;
  for (const PathState& state : result.states) {
    const Eigen::Vector3d& p = state.location.point_W;
    on_ramp = on_ramp || (inRampFootprint(p) && p.z() > 1.0 && p.z() < 2.0);
    EXPECT_NEAR(p.z(), nearestDrivableHeight(p), 0.3) << "off the true surface at " << p.transpose();
    if (p.z() > 0.3 && p.z() < kDeckTop - 0.3) {
      EXPECT_TRUE(inRampFootprint(p)) << "between floors off the ramp at " << p.transpose();
    }
  }
  EXPECT_TRUE(on_ramp);

  // A sampling planner takes the same way. Whether it finds the path must not depend on the load
  // of the machine running the test: without one after 1 s it keeps searching, up to 60 s.
  config.planner = "bitstar";
  config.time_budget_s = 1.0;
  config.time_cap_s = 60.0;
  const PlanResult sampled = planOnSurface(graph, start, goal, config);
  ASSERT_TRUE(sampled.solved()) << sampled.reason;
  EXPECT_GE(sampled.cost, result.cost * 0.99);
  for (const PathState& state : sampled.states) {
    const Eigen::Vector3d& p = state.location.point_W;
    EXPECT_NEAR(p.z(), nearestDrivableHeight(p), 0.3) << "off the true surface at " << p.transpose();
  }
}

}  // namespace
}  // namespace terramesh::planning
