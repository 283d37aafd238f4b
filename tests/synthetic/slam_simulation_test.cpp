#include "datasets/slam_simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "datasets/kitti_odometry_reader.h"

namespace terramesh::datasets {
namespace {

const std::string kKitti00 = std::string(TERRAMESH_SHARED_DIR) + "/data/kitti_poses/00.txt";

const SyntheticScene& smallStreet() {
  static const SyntheticScene scene = [] {
    StreetSceneConfig config;
    config.length_m = 160;
    return buildStreetScene(config);
  }();
  return scene;
}

const TriangleBvh& smallStreetBvh() {
  static const TriangleBvh bvh(smallStreet().ground_truth.mesh);
  return bvh;
}

std::vector<const mesher::Keyframe*> keyframesOf(const SlamStream& stream) {
  std::vector<const mesher::Keyframe*> keyframes;
  for (const StreamEvent& event : stream.events) keyframes.push_back(&std::get<mesher::Keyframe>(event));
  return keyframes;
}

TEST(SlamSimulationTest, EveryObservationIsInViewInRangeAndUnoccluded) {
  for (const SyntheticScene* scene : {&smallStreet()}) {
    SlamSimulationConfig config;
    config.outlier_fraction = 0.05;
    const SimulatedSlam slam = simulateSlam(*scene, smallStreetBvh(), config);
    ASSERT_GT(slam.stats.observations, 10000u);
    const double cx = config.image_width_px / 2.0, cy = config.image_height_px / 2.0;
    std::size_t checked = 0;
    for (const mesher::Keyframe* keyframe : keyframesOf(slam.stream)) {
      const Eigen::Isometry3d& T_W_C = slam.keyframes[keyframe->id.value].true_T_W_C;
      EXPECT_TRUE(T_W_C.translation().isApprox(keyframe->position_W_C)) << "no drift configured";
      std::set<std::uint64_t> ids;
      for (const mesher::PointObservation& observation : keyframe->observations) {
        ASSERT_TRUE(ids.insert(observation.point.value).second) << "point listed twice";
        ASSERT_TRUE(observation.position_W.allFinite());
        const SimulatedPoint& point = slam.points.at(observation.point.value);
        const Eigen::Vector3d ray = point.true_position_W - T_W_C.translation();
        const Eigen::Vector3d p_C = T_W_C.inverse() * point.true_position_W;
        ASSERT_GT(p_C.z(), 0.0);
        const double u = config.focal_length_px * p_C.x() / p_C.z() + cx;
        const double v = config.focal_length_px * p_C.y() / p_C.z() + cy;
        EXPECT_TRUE(u >= 0 && u < config.image_width_px && v >= 0 && v < config.image_height_px);
        EXPECT_LE(ray.norm(), config.max_range_m);
        EXPECT_GE(ray.norm(), config.min_range_m);
        // Unoccluded: the first surface along the ray is the point's own.
        const auto hit = smallStreetBvh().firstHit(T_W_C.translation(), ray);
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR(hit->distance, ray.norm(), 0.01) << "point " << observation.point.value;
        ++checked;
      }
      EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
    }
    EXPECT_EQ(checked, slam.stats.observations);
  }
}

TEST(SlamSimulationTest, StreamIsWellFormed) {
  SlamSimulationConfig config;
  config.keyframe_spacing_m = 3.0;
  const SimulatedSlam slam = simulateSlam(smallStreet(), smallStreetBvh(), config);
  const auto keyframes = keyframesOf(slam.stream);
  ASSERT_EQ(keyframes.size(), slam.keyframes.size());
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    EXPECT_EQ(keyframes[k]->id.value, k);
    EXPECT_NEAR(keyframes[k]->rotation_W_C.norm(), 1.0, 1e-12);
    if (k > 0) {
      const double step = (slam.keyframes[k].true_T_W_C.translation() - slam.keyframes[k - 1].true_T_W_C.translation()).norm();
      EXPECT_GE(step, 3.0 - 1e-9) << "keyframes at least the spacing apart (straight road)";
      EXPECT_LT(step, 3.0 + 0.81);
    }
  }
  EXPECT_EQ(slam.stream.metres_per_unit, 1.0);
  EXPECT_TRUE(slam.stream.scale_known);
  EXPECT_EQ(slam.stats.points, slam.points.size());
  EXPECT_NEAR(static_cast<double>(slam.stats.points) / static_cast<double>(slam.stats.keyframes),
              config.new_points_per_keyframe, 5.0);
  config.keyframe_every_frames = 4;
  const std::vector<std::size_t> every4 = selectKeyframeFrames(smallStreet().frames_T_W_C, config);
  for (std::size_t k = 0; k < every4.size(); ++k) EXPECT_EQ(every4[k], 4 * k);
}

TEST(SlamSimulationTest, NoiseShrinksAsPointsAreReobserved) {
  SlamSimulationConfig config;
  config.outlier_fraction = 0.0;
  config.noise_std_m = 0.1;
  const SimulatedSlam slam = simulateSlam(smallStreet(), smallStreetBvh(), config);
  // Error of each sent estimate, grouped by how many views the point had when it was sent; the
  // along-ray noise of a first view is normalised by the model's sigma at its depth.
  std::map<std::uint64_t, int> views;
  std::vector<double> sum_squared(6, 0.0);
  std::vector<int> count(6, 0);
  double normalised_first = 0.0;
  int first = 0;
  for (const mesher::Keyframe* keyframe : keyframesOf(slam.stream)) {
    const Eigen::Vector3d camera = slam.keyframes[keyframe->id.value].true_T_W_C.translation();
    for (const mesher::PointObservation& observation : keyframe->observations) {
      const SimulatedPoint& point = slam.points[observation.point.value];
      const int n = ++views[observation.point.value];
      const Eigen::Vector3d error = observation.position_W - point.true_position_W;
      const std::size_t bucket = static_cast<std::size_t>(std::min(n, 5));
      sum_squared[bucket] += error.squaredNorm();
      ++count[bucket];
      if (n == 1) {
        const double depth = (point.true_position_W - camera).norm();
        const double sigma = config.noise_std_m + config.depth_noise_per_m * depth * depth;
        const double along = error.dot((point.true_position_W - camera) / depth) / sigma;
        normalised_first += along * along;
        ++first;
      }
    }
  }
  EXPECT_NEAR(normalised_first / first, 1.0, 0.05) << "first views follow the noise model";
  double previous = INFINITY;
  for (std::size_t n = 1; n <= 4; ++n) {
    ASSERT_GT(count[n], 200) << "views " << n;
    const double rms = std::sqrt(sum_squared[n] / count[n]);
    EXPECT_LT(rms, previous) << "estimates sent at view " << n;
    previous = rms;
  }
  EXPECT_LT(std::sqrt(sum_squared[4] / count[4]), 0.7 * std::sqrt(sum_squared[1] / count[1]));
}

TEST(SlamSimulationTest, EstimatesMoveOnlyForMovingPoints) {
  SlamSimulationConfig config;
  config.outlier_fraction = 0.0;
  for (const double fraction : {0.0, 1.0}) {
    config.moving_point_fraction = fraction;
    const SimulatedSlam slam = simulateSlam(smallStreet(), smallStreetBvh(), config);
    std::map<std::uint64_t, Eigen::Vector3d> last;
    std::size_t moves = 0;
    for (const mesher::Keyframe* keyframe : keyframesOf(slam.stream)) {
      for (const mesher::PointObservation& observation : keyframe->observations) {
        const auto [it, inserted] = last.emplace(observation.point.value, observation.position_W);
        if (!inserted && it->second != observation.position_W) ++moves;
        it->second = observation.position_W;
      }
    }
    if (fraction == 0.0) {
      EXPECT_EQ(moves, 0u);
      EXPECT_EQ(slam.stats.points_moved_after_second_view, 0u);
    } else {
      EXPECT_GT(moves, slam.stats.points / 4);
      EXPECT_EQ(slam.stats.moving_points, slam.stats.points);
    }
  }
}

TEST(SlamSimulationTest, OutlierFractionIsRespectedAndOutliersAreFar) {
  SlamSimulationConfig config;
  config.outlier_fraction = 0.2;
  const SimulatedSlam slam = simulateSlam(smallStreet(), smallStreetBvh(), config);
  const double n = static_cast<double>(slam.stats.points);
  const double measured = static_cast<double>(slam.stats.outliers) / n;
  EXPECT_NEAR(measured, 0.2, 4.0 * std::sqrt(0.2 * 0.8 / n));
  for (const SimulatedPoint& point : slam.points) {
    if (!point.outlier) continue;
    const Eigen::Vector3d camera = slam.keyframes[point.first_keyframe].true_T_W_C.translation();
    const double depth = (point.true_position_W - camera).norm();
    EXPECT_GE((point.final_estimate_W - point.true_position_W).norm(), 0.19 * depth);
    EXPECT_FALSE(point.moving);
  }
}

TEST(SlamSimulationTest, SameSeedSameStreamOtherSeedOtherStream) {
  SlamSimulationConfig config;
  config.outlier_fraction = 0.05;
  const SimulatedSlam a = simulateSlam(smallStreet(), smallStreetBvh(), config);
  const SimulatedSlam b = simulateSlam(smallStreet(), smallStreetBvh(), config);
  ASSERT_EQ(a.stream.events.size(), b.stream.events.size());
  for (std::size_t i = 0; i < a.stream.events.size(); ++i) {
    const auto& ka = std::get<mesher::Keyframe>(a.stream.events[i]);
    const auto& kb = std::get<mesher::Keyframe>(b.stream.events[i]);
    ASSERT_EQ(ka.observations.size(), kb.observations.size());
    for (std::size_t j = 0; j < ka.observations.size(); ++j) {
      ASSERT_EQ(ka.observations[j].point, kb.observations[j].point);
      ASSERT_EQ(ka.observations[j].position_W, kb.observations[j].position_W);
    }
  }
  config.seed = 99;
  const SimulatedSlam c = simulateSlam(smallStreet(), smallStreetBvh(), config);
  EXPECT_NE(a.points.front().true_position_W, c.points.front().true_position_W);
}

TEST(SlamSimulationTest, LoopClosureResendsDriftedKeyframesCorrected) {
  SlamSimulationConfig config;
  config.loop_closure_drift_m = 2.0;
  const SimulatedSlam slam = simulateSlam(smallStreet(), smallStreetBvh(), config);
  std::map<std::uint64_t, std::vector<const mesher::Keyframe*>> sends;
  for (const StreamEvent& event : slam.stream.events) {
    const auto& keyframe = std::get<mesher::Keyframe>(event);
    sends[keyframe.id.value].push_back(&keyframe);
  }
  std::size_t resent = 0;
  double largest_jump = 0.0;
  for (const auto& [id, messages] : sends) {
    const SimulatedKeyframe& truth = slam.keyframes[id];
    ASSERT_LE(messages.size(), 2u);
    EXPECT_EQ(messages.size() == 2, truth.corrected_by_loop_closure);
    if (messages.size() < 2) continue;
    ++resent;
    EXPECT_TRUE(messages[1]->position_W_C.isApprox(truth.true_T_W_C.translation())) << "re-sent with the true pose";
    EXPECT_EQ(messages[1]->observations.size(), messages[0]->observations.size());
    largest_jump = std::max(largest_jump, (messages[0]->position_W_C - messages[1]->position_W_C).norm());
  }
  EXPECT_GT(resent, 10u);
  EXPECT_EQ(slam.stats.keyframe_events, slam.stats.keyframes + resent);
  EXPECT_NEAR(largest_jump, 2.0, 0.2);
}

TEST(SlamSimulationTest, KittiLikePresetMeetsTheBenchmarkStatistics) {
  const PoseList poses = selectFrames(readKittiPoses(kKitti00), 0, 1200);
  StreetSceneConfig street;
  street.length_m = 0.0;
  const SyntheticScene scene = buildStreetScene(street, poses);
  const TriangleBvh bvh(scene.ground_truth.mesh);
  const SimulatedSlam slam = simulateSlam(scene, bvh, kittiLikeSlamConfig());
  EXPECT_EQ(slam.stats.keyframes, 300u) << "a keyframe every 4 frames";
  const double keyframes = static_cast<double>(slam.stats.keyframes);
  // What the mesher will see (points inserted once seen twice, their rays): Table IV's ~130 and ~500.
  double traced = 0.0;
  for (const SimulatedPoint& point : slam.points) traced += point.observations >= 2 ? point.observations : 0;
  EXPECT_NEAR(static_cast<double>(slam.stats.points_seen_twice) / keyframes, 130.0, 20.0);
  EXPECT_NEAR(traced / keyframes, 500.0, 120.0);
  EXPECT_NEAR(static_cast<double>(slam.stats.points_moved_after_second_view) /
                  static_cast<double>(slam.stats.points_seen_twice), 0.1, 0.03);
}

TEST(SlamSimulationTest, BadConfigAndMismatchedInputsThrow) {
  SlamSimulationConfig config;
  config.max_range_m = 0.1;
  config.outlier_fraction = 2.0;
  try {
    config.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("max_range_m"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("outlier_fraction"), std::string::npos);
  }
  const TriangleBvh other{mesher::TriangleMesh{}};
  EXPECT_THROW(simulateSlam(smallStreet(), other, SlamSimulationConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::datasets
