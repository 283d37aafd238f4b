#pragma once
// A generated scene and its simulated SLAM stream (a street seen as KITTI is), for the tests that
// mesh generated scenes with trajectory evidence.

#include <cstdint>
#include <utility>

#include "datasets/slam_simulation.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::traversability::test_stream {

struct SimulatedScene {
  datasets::SyntheticScene scene;
  datasets::SimulatedSlam slam;
};
using SimulatedStreet = SimulatedScene;

/// `scene` seen by the simulated SLAM system of `slam`.
inline SimulatedScene simulate(datasets::SyntheticScene scene, const datasets::SlamSimulationConfig& slam) {
  SimulatedScene s;
  s.scene = std::move(scene);
  const datasets::TriangleBvh bvh(s.scene.ground_truth.mesh);
  s.slam = datasets::simulateSlam(s.scene, bvh, slam);
  return s;
}

/// A street `length_m` long (scene seed `seed`), seen by datasets::kittiLikeSlamConfig() with
/// `slam_seed` (0: the config's own) and `loop_closure_drift_m` of drift corrected by re-sent
/// keyframes (0: none).
inline SimulatedStreet simulateStreet(double length_m, std::uint64_t seed, std::uint64_t slam_seed = 0,
                                      double loop_closure_drift_m = 0) {
  datasets::StreetSceneConfig config;
  config.length_m = length_m;
  config.seed = seed;
  datasets::SlamSimulationConfig slam = datasets::kittiLikeSlamConfig();
  if (slam_seed != 0) slam.seed = slam_seed;
  slam.loop_closure_drift_m = loop_closure_drift_m;
  return simulate(datasets::buildStreetScene(config), slam);
}

}  // namespace terramesh::traversability::test_stream
