// The hazards scene: every hazard in the truth mesh with its intended size, per-robot truth labels
// and reachability across each (small_wheeled), and the sparse SLAM stream of its default config.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "datasets/slam_density.h"
#include "datasets/slam_simulation.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/ground_truth_traversability.h"
#include "evaluation/robot_limits.h"
#include "evaluation/truth_reachability.h"
#include "traversability/robot_profile.h"
#include "traversability/robot_profile_yaml.h"

namespace terramesh::datasets {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr std::uint64_t kSeeds[] = {1, 2, 3, 4, 5};

SyntheticScene hazards(std::uint64_t seed) {
  HazardsSceneConfig config;
  config.seed = seed;
  return buildHazardsScene(config);
}

std::vector<const SceneHazard*> ofKind(const SyntheticScene& scene, HazardKind kind) {
  std::vector<const SceneHazard*> out;
  for (const SceneHazard& h : scene.hazards) {
    if (h.kind == kind) out.push_back(&h);
  }
  return out;
}

/// Height of the first surface straight below (x, y, 5), or NaN.
double heightAt(const TriangleBvh& bvh, double x, double y) {
  const auto hit = bvh.firstHit({x, y, 5.0}, -Eigen::Vector3d::UnitZ(), 10.0);
  return hit ? hit->point.z() : std::nan("");
}

TEST(HazardsSceneTest, SeedsOneToFiveBuildSaneScenesThatDiffer) {
  std::set<std::vector<double>> layouts;
  for (const std::uint64_t seed : kSeeds) {
    const SyntheticScene scene = hazards(seed);
    const LabeledMesh& gt = scene.ground_truth;
    ASSERT_NO_THROW(gt.validate());
    EXPECT_EQ(scene.up_W, Eigen::Vector3d::UnitZ());
    for (std::size_t f = 0; f < gt.mesh.faces.size(); ++f) {
      const auto& t = gt.mesh.faces[f];
      const Eigen::Vector3d n = (gt.mesh.vertices[t[1]] - gt.mesh.vertices[t[0]])
                                    .cross(gt.mesh.vertices[t[2]] - gt.mesh.vertices[t[0]]);
      ASSERT_GT(n.norm(), 1e-8) << "seed " << seed << " face " << f;
      ASSERT_NEAR(gt.slope_deg[f], std::acos(std::clamp(n.normalized().z(), -1.0, 1.0)) * kRadToDeg, 1e-3);
    }
    EXPECT_EQ(ofKind(scene, HazardKind::kSlab).size(), 2u);
    EXPECT_EQ(ofKind(scene, HazardKind::kPlateau).size(), 1u);
    EXPECT_EQ(ofKind(scene, HazardKind::kPit).size(), 1u);
    EXPECT_EQ(ofKind(scene, HazardKind::kThinWall).size(), 2u);
    EXPECT_EQ(ofKind(scene, HazardKind::kRock).size(), static_cast<std::size_t>(kHazardsRockCount));
    // The camera drives on the ground plane at a ground robot's mast height, level.
    const TriangleBvh bvh(gt.mesh);
    for (std::size_t i = 0; i < scene.frames_T_W_C.size(); i += 10) {
      const Eigen::Vector3d c = scene.frames_T_W_C[i].translation();
      const auto below = bvh.firstHit(c, -Eigen::Vector3d::UnitZ(), 5.0);
      ASSERT_TRUE(below.has_value()) << "seed " << seed << " frame " << i;
      EXPECT_NEAR(below->distance, 1.4, 1e-6) << "seed " << seed << " frame " << i;
      EXPECT_NEAR(scene.frames_T_W_C[i].linear().col(1).dot(-scene.up_W), 1.0, 1e-6);  // camera y down
    }
    // The lane passes every hazard within a few metres.
    for (const SceneHazard& h : scene.hazards) {
      double nearest = INFINITY;
      for (const Eigen::Isometry3d& T_W_C : scene.frames_T_W_C) {
        nearest = std::min(nearest, (T_W_C.translation() - h.centre_W).head<2>().norm());
      }
      EXPECT_LT(nearest, 8.0) << "seed " << seed << " " << h.name;
      EXPECT_GT(nearest, 2.5) << "seed " << seed << " " << h.name << " is on the lane";
    }
    std::vector<double> layout;
    for (const SceneHazard& h : scene.hazards) {
      layout.insert(layout.end(), {h.centre_W.x(), h.centre_W.y(), h.height_m});
    }
    layouts.insert(layout);
  }
  EXPECT_EQ(layouts.size(), std::size(kSeeds)) << "two seeds gave the same layout";
}

TEST(HazardsSceneTest, EveryHazardIsInTheTruthWithItsIntendedSize) {
  for (const std::uint64_t seed : kSeeds) {
    const SyntheticScene scene = hazards(seed);
    const TriangleBvh bvh(scene.ground_truth.mesh);
    for (const SceneHazard& h : scene.hazards) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " " + h.name);
      const double cx = h.centre_W.x(), cy = h.centre_W.y();
      const double x0 = cx - h.size_m.x() / 2, x1 = cx + h.size_m.x() / 2;
      switch (h.kind) {
        case HazardKind::kSlab: {
          const double jump = heightAt(bvh, x0 + 0.05, cy) - heightAt(bvh, x0 - 0.05, cy);
          EXPECT_GE(jump, 0.3);
          EXPECT_LE(jump, 0.5);
          EXPECT_NEAR(heightAt(bvh, x1 - 0.05, cy) - heightAt(bvh, x1 + 0.05, cy), jump, 1e-9);
          break;
        }
        case HazardKind::kPit: {
          const double depth = heightAt(bvh, x0 - 0.05, cy) - heightAt(bvh, x0 + 0.05, cy);
          EXPECT_GE(depth, 0.3);
          EXPECT_LE(depth, 0.6);
          EXPECT_NEAR(heightAt(bvh, cx, cy), -depth, 1e-9);
          break;
        }
        case HazardKind::kPlateau: {
          // Two samples on the ramp, 1 m apart along it.
          const double foot = x0 - h.ramp_length_m;
          const double rise = heightAt(bvh, foot + 1.5, cy) - heightAt(bvh, foot + 0.5, cy);
          const double slope = std::atan(rise) * kRadToDeg;
          EXPECT_GE(slope, 15.0);
          EXPECT_LE(slope, 18.0);
          EXPECT_NEAR(slope, h.ramp_slope_deg, 1e-6);
          EXPECT_NEAR(heightAt(bvh, cx, cy), h.height_m, 1e-9);  // the plateau top ...
          EXPECT_NEAR(heightAt(bvh, x1 + 0.05, cy), 0.0, 1e-9);  // ... and its far edge drops to the ground
          EXPECT_GT(h.height_m, 0.3);
          break;
        }
        case HazardKind::kThinWall: {
          const bool along_x = h.size_m.x() > h.size_m.y();
          const Eigen::Vector3d across = along_x ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
          const Eigen::Vector3d along = along_x ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
          const double length = along_x ? h.size_m.x() : h.size_m.y();
          // Thickness: a horizontal ray through it at 0.5 m enters one face and leaves by the other.
          const Eigen::Vector3d side = h.centre_W - 1.0 * across + 0.5 * Eigen::Vector3d::UnitZ();
          const auto in = bvh.firstHit(side, across, 2.0);
          ASSERT_TRUE(in.has_value());
          const auto out = bvh.firstHit(in->point + 1e-6 * across, across, 2.0);
          ASSERT_TRUE(out.has_value());
          EXPECT_GE(out->distance, 0.1 - 1e-5);
          EXPECT_LE(out->distance, 0.2);
          const double top = heightAt(bvh, cx, cy);
          EXPECT_GE(top, 1.0);
          EXPECT_LE(top, 2.0);
          // Free ends: the ground just past either end.
          for (const double end : {-1.0, 1.0}) {
            const Eigen::Vector3d past = h.centre_W + end * (length / 2 + 0.1) * along;
            EXPECT_NEAR(heightAt(bvh, past.x(), past.y()), 0.0, 1e-9);
          }
          break;
        }
        case HazardKind::kRock: {
          const auto hit = bvh.firstHit({cx, cy, 5.0}, -Eigen::Vector3d::UnitZ(), 10.0);
          ASSERT_TRUE(hit.has_value());
          EXPECT_EQ(scene.ground_truth.labels[hit->face], SurfaceLabel::kObstacle);
          EXPECT_GT(hit->point.z(), 0.2);  // above small_wheeled's 0.18 m step
          EXPECT_LT(hit->point.z(), 0.9);
          EXPECT_GE(h.size_m.x(), 0.3);
          EXPECT_LE(h.size_m.x(), 0.9);
          EXPECT_NEAR(heightAt(bvh, cx + 0.6 * h.size_m.x(), cy), 0.0, 1e-9);  // just a rock
          break;
        }
      }
    }
  }
}

/// small_wheeled's truth on a scene, with what places points on it.
struct SmallWheeledTruth {
  evaluation::GroundTruthTraversability labels;
  evaluation::TruthReachability reach;

  explicit SmallWheeledTruth(const SyntheticScene& scene)
      : labels(evaluation::labelTraversability(
            scene.ground_truth,
            evaluation::robotLimitsFrom(traversability::loadRobotProfile(
                std::string(TERRAMESH_SOURCE_DIR) + "/traversability/robots/small_wheeled.yaml")),
            scene.up_W, {})),
        reach(labels) {}

  /// Whether the truth face under (x, y) at height z is traversable (false with no face).
  bool traversableAt(double x, double y, double z) const {
    const auto face = reach.faceUnder({x, y, z});
    return face && labels.traversable[*face];
  }
};

TEST(HazardsSceneTest, SmallWheeledTruthBlocksEdgesWallsAndRocksButNotTheRamp) {
  const SyntheticScene scene = hazards(1);
  const SmallWheeledTruth truth(scene);
  ASSERT_EQ(truth.labels.robot.max_slope_deg, 20.0);
  for (const SceneHazard& h : scene.hazards) {
    SCOPED_TRACE(h.name);
    const double cx = h.centre_W.x(), cy = h.centre_W.y();
    const double x0 = cx - h.size_m.x() / 2;
    switch (h.kind) {
      case HazardKind::kSlab:
        EXPECT_FALSE(truth.traversableAt(x0 - 0.15, cy, 0));  // at the foot of the edge
        EXPECT_TRUE(truth.traversableAt(x0 - 1.0, cy, 0));
        EXPECT_TRUE(truth.traversableAt(cx, cy, h.height_m));  // its top, but see the reachability test
        break;
      case HazardKind::kPit:
        EXPECT_FALSE(truth.traversableAt(x0 + 0.15, cy, h.height_m));  // the floor at the foot of its wall
        EXPECT_TRUE(truth.traversableAt(cx, cy, h.height_m));           // its middle, but see the reachability test
        break;
      case HazardKind::kPlateau: {
        const double foot = x0 - h.ramp_length_m;
        EXPECT_TRUE(truth.traversableAt(foot - 0.2, cy, 0));
        EXPECT_TRUE(truth.traversableAt(foot + 1.5, cy, 0.5 * h.height_m));
        EXPECT_TRUE(truth.traversableAt(x0 + 0.2, cy, h.height_m));
        EXPECT_FALSE(truth.traversableAt(cx, cy - h.size_m.y() / 2 - 0.15, 0));  // beside its side wall
        break;
      }
      case HazardKind::kThinWall: {
        const bool along_x = h.size_m.x() > h.size_m.y();
        const double off = (along_x ? h.size_m.y() : h.size_m.x()) / 2 + 0.15;
        EXPECT_FALSE(truth.traversableAt(along_x ? cx : cx + off, along_x ? cy + off : cy, 0));
        break;
      }
      case HazardKind::kRock:
        EXPECT_FALSE(truth.traversableAt(cx + h.size_m.x() / 2 + 0.1, cy, 0));
        EXPECT_TRUE(truth.traversableAt(cx + h.size_m.x() / 2 + 0.9, cy, 0));
        break;
    }
  }
}

TEST(HazardsSceneTest, TruthReachabilityAcrossEachHazard) {
  for (const std::uint64_t seed : {1, 4}) {
    const SyntheticScene scene = hazards(seed);
    const SmallWheeledTruth truth(scene);
    for (const SceneHazard& h : scene.hazards) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " " + h.name);
      const evaluation::ReachAnswer answer = truth.reach.connects(h.start_W, h.goal_W);
      switch (h.kind) {
        case HazardKind::kSlab:
        case HazardKind::kPit:
          // Both ends traversable, but only an edge taller than the step joins them.
          EXPECT_EQ(answer.status, evaluation::ReachStatus::kDifferentComponents)
              << evaluation::toString(answer.status);
          break;
        case HazardKind::kPlateau:
        case HazardKind::kThinWall:
        case HazardKind::kRock:
          EXPECT_TRUE(answer.reachable()) << evaluation::toString(answer.status);
          break;
      }
    }
    // The plateau from beside its far wall: only round by the ramp.
    const SceneHazard& plateau = *ofKind(scene, HazardKind::kPlateau).front();
    const Eigen::Vector3d beyond(plateau.centre_W.x() + plateau.size_m.x() / 2 + 1.5, plateau.centre_W.y(), 0);
    EXPECT_TRUE(truth.reach.connects(beyond, plateau.goal_W).reachable());
  }
}

TEST(HazardsSceneTest, DefaultSlamIsSparseWithThreeCentimetreNoise) {
  const SyntheticScene scene = hazards(1);
  const TriangleBvh bvh(scene.ground_truth.mesh);
  const SlamSimulationConfig config = hazardsSlamConfig();
  const SimulatedSlam slam = simulateSlam(scene, bvh, config);
  const GroundDensity density = measureGroundDensity(scene, bvh, slam, config);
  EXPECT_GT(density.seen_area_m2, 0.5 * density.ground_area_m2);
  EXPECT_GE(density.points_per_m2, 1.0);
  EXPECT_LE(density.points_per_m2, 3.0);
  EXPECT_GT(density.median_error_m, 0.01);
  EXPECT_LT(density.median_error_m, 0.05);
  // Rocks: a handful of points each.
  std::size_t on_obstacles = 0;
  for (const SimulatedPoint& p : slam.points) {
    if (scene.ground_truth.labels[p.face] == SurfaceLabel::kObstacle) ++on_obstacles;
  }
  EXPECT_GT(on_obstacles, 0u);
  EXPECT_LT(on_obstacles, 20u * kHazardsRockCount);
}

TEST(HazardsSceneTest, ConfigReportsEveryProblem) {
  HazardsSceneConfig config;
  config.object_density = -1;
  config.camera_height_m = 0;
  config.speed_m_per_s = 0;
  try {
    config.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    for (const char* field : {"object_density", "camera_height_m", "speed_m_per_s"}) {
      EXPECT_NE(message.find(field), std::string::npos) << message;
    }
  }
  GroundDensityConfig density;
  density.sample_spacing_m = 0;
  EXPECT_THROW(density.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::datasets
