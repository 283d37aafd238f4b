// The body views of trajectory evidence (TrajectoryEvidence::bodyViewsOf) on a generated street,
// meshed with the layers kept current as `terramesh mesh --robot` keeps them: rays from behind and
// low inside the body volume the robot swept carve the closing faces that the sensor's own rays
// (from above and ahead) leave up the sides of the driven strip, so fewer faces of the strip are
// uncertain as guessed walls, and more of it is free.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "evidence_stream.h"
#include "mesher/mesher.h"
#include "simulated_scene.h"
#include "traversability/layer_registry.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/trajectory_evidence.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

using Street = test_stream::SimulatedStreet;

/// A 120 m street (scene and SLAM seed 4: the other street tests use seed 2).
const Street& street() {
  static const Street* const kStreet = new Street(test_stream::simulateStreet(120, 4, 4));
  return *kStreet;
}

/// The street meshed with trajectory evidence for `robot` and its layers, with or without the
/// body views.
LayeredMesh meshWithLayers(const RobotProfile& robot, bool body_views) {
  const Street& s = street();
  const Eigen::Vector3d up = s.scene.up_W.normalized();
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  TrajectoryEvidenceConfig evidence_config;
  evidence_config.body_views = body_views;
  TrajectoryEvidence evidence(robot, up, 1.0, datasets::StreetSceneConfig{}.camera_height_m, Eigen::Vector3d::UnitZ(),
                              evidence_config);
  evidence.configureMesher(config);
  mesher::Mesher mesher(config);
  MapFrame frame;
  frame.up_W = up;
  TraversabilityMap map(robot, frame);
  map.setDrivePoses([&evidence](mesher::PointId id) { return evidence.baseOf(id); });
  std::uint64_t revision = 0;
  for (const datasets::StreamEvent& event : s.slam.stream.events) {
    test_stream::applyEvent(mesher, event, &evidence);
    map.update(mesher, revision);
    revision = mesher.revision();
  }
  return map.snapshot();
}

/// Shares of the driven strip's area (faces whose centroid lies within `half_width_m` of the true
/// camera path horizontally and within 0.3 m of the true road height under it) that are free and
/// that carry `reason`.
struct StripShares {
  double free = 0;
  double with_reason = 0;
  double area_m2 = 0;
};

StripShares stripShares(const LayeredMesh& map, double half_width_m, std::uint16_t reason) {
  const Street& s = street();
  const Eigen::Vector3d up = s.scene.up_W.normalized();
  const double camera_height_m = datasets::StreetSceneConfig{}.camera_height_m;
  StripShares out;
  double free_m2 = 0, reason_m2 = 0;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    const auto& face = map.mesh.faces[f];
    const Eigen::Vector3d& a = map.mesh.vertices[face[0]];
    const Eigen::Vector3d& b = map.mesh.vertices[face[1]];
    const Eigen::Vector3d& c = map.mesh.vertices[face[2]];
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    bool in_strip = false;
    const auto& keyframes = s.slam.keyframes;
    for (std::size_t k = 0; k + 1 < keyframes.size() && !in_strip; ++k) {
      const Eigen::Vector3d p = keyframes[k].true_T_W_C.translation() - camera_height_m * up;
      const Eigen::Vector3d q = keyframes[k + 1].true_T_W_C.translation() - camera_height_m * up;
      const Eigen::Vector3d d = q - p;
      const double t = std::clamp((centroid - p).dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
      const Eigen::Vector3d offset = centroid - (p + t * d);
      const double vertical = offset.dot(up);
      in_strip = (offset - vertical * up).norm() <= half_width_m && std::abs(vertical) <= 0.3;
    }
    if (!in_strip) continue;
    const double area = 0.5 * (b - a).cross(c - a).norm();
    out.area_m2 += area;
    free_m2 += map.layers[f].face_class == FaceClass::kFree ? area : 0.0;
    reason_m2 += (map.layers[f].reasons & reason) != 0 ? area : 0.0;
  }
  out.free = free_m2 / std::max(out.area_m2, 1e-12);
  out.with_reason = reason_m2 / std::max(out.area_m2, 1e-12);
  return out;
}

TEST(BodyViewsTest, TheyClearGuessedWallsBesideTheCarsDriveAndFreeMoreOfIt) {
  const RobotProfile car = loadRobotProfile(kRobots / "car.yaml");
  const double half_width_m = 0.5 * car.footprint_width_m;
  const StripShares with = stripShares(meshWithLayers(car, true), half_width_m, reason::kGuessedWall);
  const StripShares without = stripShares(meshWithLayers(car, false), half_width_m, reason::kGuessedWall);
  std::printf("car's driven strip (%.0f and %.0f m2): free %.3f with the body views, %.3f without; guessed walls "
              "%.3f and %.3f\n", with.area_m2, without.area_m2, with.free, without.free, with.with_reason,
              without.with_reason);
  ASSERT_GT(with.area_m2, 100.0);
  EXPECT_LT(with.with_reason, without.with_reason);
  EXPECT_GE(with.free, without.free);
}

}  // namespace
}  // namespace terramesh::traversability
