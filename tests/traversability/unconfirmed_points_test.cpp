// SLAM points the mesher has not inserted (seen by fewer than min_views keyframes): the mesher
// keeps the list current, and the layers treat each as a possible obstacle. A rock seen from one
// keyframe is never called free around it, never lethal either, and stops mattering once the
// point is gone or confirmed.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <sstream>

#include "mesher/checkpoint.h"
#include "mesher/mesher.h"
#include "test_support/traversability_scenes.h"
#include "traversability/layer_registry.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

mesher::PointObservation observation(std::uint64_t id, const Eigen::Vector3d& p) {
  mesher::PointObservation o;
  o.point = mesher::PointId{id};
  o.position_W = p;
  return o;
}

mesher::Keyframe keyframeAt(std::uint64_t id, const Eigen::Vector3d& position,
                            std::vector<mesher::PointObservation> observations) {
  mesher::Keyframe keyframe;
  keyframe.id = mesher::KeyframeId{id};
  keyframe.position_W_C = position;
  keyframe.observations = std::move(observations);
  return keyframe;
}

std::vector<std::uint64_t> idsOf(const std::vector<mesher::UnconfirmedPoint>& points) {
  std::vector<std::uint64_t> ids;
  for (const mesher::UnconfirmedPoint& p : points) ids.push_back(p.id.value);
  return ids;
}

TEST(UnconfirmedPointsTest, TheMesherListsThePointsWaitingForAViewAndForgetsThemWhenConfirmedOrGone) {
  mesher::MesherConfig config;
  config.min_views = 2;
  mesher::Mesher mesher(config);
  const std::vector<mesher::PointObservation> corners = {
      observation(1, {4, -2, -1}), observation(2, {4, 2, -1}), observation(3, {6, 0, -1}), observation(4, {5, 0, 1})};
  std::vector<mesher::PointObservation> first = corners;
  first.push_back(observation(10, {5, 0.5, 0}));  // seen again below
  first.push_back(observation(11, {5, -0.5, 0}));  // seen once only
  mesher.integrateKeyframe(keyframeAt(1, {0, 0, 0}, first));
  EXPECT_EQ(idsOf(mesher.unconfirmedPoints()), (std::vector<std::uint64_t>{1, 2, 3, 4, 10, 11}));
  EXPECT_EQ(mesher.unconfirmedPoints().back().views, 1u);
  EXPECT_EQ(mesher.unconfirmedPoints().back().position_W, Eigen::Vector3d(5, -0.5, 0));

  std::vector<mesher::PointObservation> second = corners;
  second.push_back(observation(10, {5, 0.5, 0}));
  mesher.integrateKeyframe(keyframeAt(2, {0, 1, 0}, second));
  EXPECT_EQ(idsOf(mesher.unconfirmedPoints()), (std::vector<std::uint64_t>{11})) << "the others are inserted";

  // A checkpoint keeps the list.
  std::stringstream bytes;
  mesher::saveCheckpoint(mesher, bytes);
  const mesher::LoadedCheckpoint loaded = mesher::loadCheckpoint(bytes, "memory");
  EXPECT_EQ(idsOf(loaded.mesher.unconfirmedPoints()), (std::vector<std::uint64_t>{11}));

  // Its only keyframe removed, point 11 is gone; driven-ground samples never wait.
  mesher.removeKeyframe(mesher::KeyframeId{1});
  EXPECT_TRUE(mesher.unconfirmedPoints().empty());
  mesher::PointObservation driven = observation(12, {5, 0, -1});
  driven.kind = mesher::PointKind::kDrivenGround;
  mesher.integrateKeyframe(keyframeAt(3, {0, -1, 0}, {driven}));
  EXPECT_TRUE(mesher.unconfirmedPoints().empty());
}

/// A flat, densely measured floor, 8 x 8 m, at height 0.
std::vector<mesher::SurfaceFace> floorFaces(std::uint8_t driven_vertices) {
  const mesher::TriangleMesh mesh = test::heightFieldMesh(-4, 4, -4, 4, 0.25, [](double, double) { return 0.0; });
  std::vector<mesher::SurfaceFace> faces;
  for (const auto& t : mesh.faces) {
    mesher::SurfaceFace face;
    for (int i = 0; i < 3; ++i) {
      face.vertices[i] = mesher::VertexKey{t[i], false};
      face.positions_W[i] = mesh.vertices[t[i]];
    }
    face.key = mesher::FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    face.rays = 10;
    face.front_crossings = 4;
    face.driven_vertices = driven_vertices;
    faces.push_back(face);
  }
  return faces;
}

std::vector<mesher::UnconfirmedPoint> onePoint(const Eigen::Vector3d& p) { return {{mesher::PointId{7}, p, 1}}; }

/// Horizontal distance from the origin to triangle abc (0 inside): the nearest of its three edges,
/// or 0 if the origin is on the same side of all of them.
double distanceFromOrigin(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const auto side = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) { return p.x() * q.y() - p.y() * q.x(); };
  const double s0 = side(a, b), s1 = side(b, c), s2 = side(c, a);
  if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) return 0;
  const auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    const double t = std::clamp(-p.dot(q - p) / (q - p).squaredNorm(), 0.0, 1.0);
    return (p + t * (q - p)).norm();
  };
  return std::min({edge(a, b), edge(b, c), edge(c, a)});
}

/// Class per face of the snapshot, with the horizontal distance from the origin to the face.
std::vector<std::pair<double, FaceClass>> classesByDistance(const TraversabilityMap& map) {
  const LayeredMesh snapshot = map.snapshot();
  std::vector<std::pair<double, FaceClass>> out;
  for (std::size_t f = 0; f < snapshot.mesh.faces.size(); ++f) {
    const auto& t = snapshot.mesh.faces[f];
    const auto& v = snapshot.mesh.vertices;
    out.emplace_back(distanceFromOrigin(v[t[0]].head<2>(), v[t[1]].head<2>(), v[t[2]].head<2>()),
                     snapshot.layers[f].face_class);
  }
  return out;
}

std::map<mesher::FaceKey, FaceLayers> layersByKey(const TraversabilityMap& map) {
  const LayeredMesh snapshot = map.snapshot();
  std::map<mesher::FaceKey, FaceLayers> out;
  for (std::size_t f = 0; f < snapshot.layers.size(); ++f) out.emplace(snapshot.face_keys[f], snapshot.layers[f]);
  return out;
}

TEST(UnconfirmedPointsTest, APointInsideTheBodyMakesTheFloorAroundItUncertainNeverLethal) {
  const RobotProfile profile = loadRobotProfile(kRobots / "small_wheeled.yaml");  // R 0.34, body 0.18-0.5 m
  const double reach = profile.footprint_radius_m + profile.evidence.unconfirmed_point_extension_m;
  const std::vector<mesher::SurfaceFace> floor = floorFaces(0);
  TraversabilityMap map(profile, MapFrame{});
  map.reset(floor);
  const std::map<mesher::FaceKey, FaceLayers> bare = layersByKey(map);
  for (const auto& [distance, face_class] : classesByDistance(map)) {
    if (distance < 3) ASSERT_EQ(face_class, FaceClass::kFree);
  }

  // A point 0.4 m up at the origin: a rock nobody confirmed. A robot anywhere on a face within the
  // footprint radius plus the point's extension of it may hit that rock.
  const LayerUpdateStats stats = map.setUnconfirmedPoints(onePoint({0, 0, 0.4}));
  EXPECT_EQ(stats.unconfirmed_points, 1u);
  EXPECT_GT(stats.faces_recomputed, 0u);
  std::size_t uncertain = 0;
  for (const auto& [distance, face_class] : classesByDistance(map)) {
    if (distance < 3) EXPECT_NE(face_class, FaceClass::kLethal) << distance;
    if (distance < reach - 0.01) {
      EXPECT_EQ(face_class, FaceClass::kUncertain) << distance;
      ++uncertain;
    }
    if (distance > reach + 0.01 && distance < 3) EXPECT_EQ(face_class, FaceClass::kFree) << distance;
  }
  EXPECT_GT(uncertain, 20u);
  // And they say why: that point, nothing else.
  for (const auto& [key, layers] : layersByKey(map)) {
    if (layers.face_class == FaceClass::kUncertain) EXPECT_EQ(layers.reasons, reason::kUnconfirmedPoint);
  }

  // The same map made from scratch with the point: identical layers (the update is exact).
  TraversabilityMap fresh(profile, MapFrame{});
  fresh.setUnconfirmedPoints(onePoint({0, 0, 0.4}));
  fresh.reset(floor);
  const std::map<mesher::FaceKey, FaceLayers> with_point = layersByKey(map);
  const std::map<mesher::FaceKey, FaceLayers> fresh_layers = layersByKey(fresh);
  ASSERT_EQ(with_point.size(), fresh_layers.size());
  for (const auto& [key, layers] : with_point) {
    EXPECT_EQ(layers.face_class, fresh_layers.at(key).face_class);
    EXPECT_FLOAT_EQ(layers.cost, fresh_layers.at(key).cost);
  }

  // Within the points' noise of the floor (3 sigma) or above the robot: nothing changes. Moved
  // there, the point leaves the floor as it was.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0.08), Eigen::Vector3d(0, 0, 0.9)}) {
    map.setUnconfirmedPoints(onePoint(p));
    for (const auto& [key, layers] : layersByKey(map)) {
      ASSERT_EQ(layers.face_class, bare.at(key).face_class) << p.transpose();
      ASSERT_FLOAT_EQ(layers.cost, bare.at(key).cost) << p.transpose();
    }
  }
  // Under the 0.18 m step but proud of the floor (over evidence.proud_point_rise_m, 0.1 m): a point
  // somewhere on a rock whose top nobody measured. The floor around it is uncertain as for 0.4 m.
  ASSERT_LT(profile.evidence.proud_point_rise_m, 0.15);
  ASSERT_GT(profile.max_step_m, 0.15);
  map.setUnconfirmedPoints(onePoint({0, 0, 0.15}));
  for (const auto& [distance, face_class] : classesByDistance(map)) {
    if (distance < reach - 0.01) EXPECT_EQ(face_class, FaceClass::kUncertain) << distance;
    if (distance > reach + 0.01 && distance < 3) EXPECT_EQ(face_class, FaceClass::kFree) << distance;
  }
  // With the rise set above it, the point is a pebble the robot climbs.
  RobotProfile climbs = profile;
  climbs.evidence.proud_point_rise_m = 0.16;
  TraversabilityMap pebble(climbs, MapFrame{});
  pebble.setUnconfirmedPoints(onePoint({0, 0, 0.15}));
  pebble.reset(floor);
  for (const auto& [key, layers] : layersByKey(pebble)) ASSERT_EQ(layers.face_class, bare.at(key).face_class);

  map.setUnconfirmedPoints(onePoint({0, 0, 0.4}));
  map.setUnconfirmedPoints({});
  for (const auto& [key, layers] : layersByKey(map)) ASSERT_EQ(layers.face_class, bare.at(key).face_class);

  // Over driven ground the robot's body swept that volume: the unconfirmed point does not count.
  TraversabilityMap driven(profile, MapFrame{});
  driven.setUnconfirmedPoints(onePoint({0, 0, 0.4}));
  driven.reset(floorFaces(3));
  for (const auto& [distance, face_class] : classesByDistance(driven)) {
    if (distance < 3) EXPECT_EQ(face_class, FaceClass::kFree) << distance;
  }
}

}  // namespace
}  // namespace terramesh::traversability
