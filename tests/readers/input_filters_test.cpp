// The mesher's input-filter counters (UpdateStats: observations, observations_too_far,
// points_waiting, points_waiting_too_far) on a stream whose distances are known, and the
// distance quantile that `--max-distance-m auto` uses.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "datasets/slam_stream.h"
#include "mesher/mesher.h"

namespace terramesh::test {
namespace {

/// Two cameras at x = 0 and x = 1 looking at 20 points on the plane z = 10 (near) and 20 on
/// z = 100 (far), all seen by both; point ids 0-19 near, 100-119 far.
datasets::SlamStream nearAndFarStream() {
  datasets::SlamStream stream;
  for (int k = 0; k < 2; ++k) {
    mesher::Keyframe keyframe;
    keyframe.id.value = static_cast<std::uint64_t>(k);
    keyframe.position_W_C = Eigen::Vector3d(k, 0, 0);
    for (int i = 0; i < 20; ++i) {
      const double x = (i % 5) - 2.0;
      const double y = (i / 5) - 1.5;
      keyframe.observations.push_back(
          {mesher::PointId{static_cast<std::uint64_t>(i)}, Eigen::Vector3d(x, y, 10 + 0.1 * (i % 3))});
      keyframe.observations.push_back({mesher::PointId{static_cast<std::uint64_t>(100 + i)},
                                       Eigen::Vector3d(10 * x, 10 * y, 100 + (i % 3))});
    }
    stream.events.emplace_back(std::move(keyframe));
  }
  return stream;
}

TEST(InputFilters, DistanceAndMinViewsCountersMatchTheScene) {
  const datasets::SlamStream stream = nearAndFarStream();
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  config.max_camera_distance_m = 40.0;
  config.min_views = 2;
  mesher::Mesher mesher(config);
  const mesher::UpdateStats first = datasets::applyEvent(mesher, stream.events[0]);
  EXPECT_EQ(first.observations, 40u);
  EXPECT_EQ(first.observations_too_far, 20u);
  // One keyframe so far: every point waits; none has min_views keyframes yet.
  EXPECT_EQ(first.points_waiting, 40u);
  EXPECT_EQ(first.points_waiting_too_far, 0u);
  EXPECT_EQ(first.new_points, 0u);

  const mesher::UpdateStats second = datasets::applyEvent(mesher, stream.events[1]);
  EXPECT_EQ(second.observations, 40u);
  EXPECT_EQ(second.observations_too_far, 20u);
  // The near points have two views in range and go in; the far ones have two views, both too far.
  EXPECT_EQ(second.points_waiting, 20u);
  EXPECT_EQ(second.points_waiting_too_far, 20u);
  EXPECT_EQ(second.new_points + second.duplicate_points + second.dropped_points, 20u);
  EXPECT_EQ(mesher.size().points - mesher.size().inserted_points,
            20u + second.duplicate_points + second.dropped_points);

  mesher::UpdateStats total = first;
  total += second;
  EXPECT_EQ(total.observations, 80u);
  EXPECT_EQ(total.observations_too_far, 40u);
  EXPECT_EQ(total.points_waiting, 60u);
  EXPECT_EQ(total.points_waiting_too_far, 20u);
}

TEST(InputFilters, NothingTooFarWithALargeDistance) {
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  config.max_camera_distance_m = 1000.0;
  mesher::Mesher mesher(config);
  mesher::UpdateStats total;
  for (const auto& event : nearAndFarStream().events) total += datasets::applyEvent(mesher, event);
  EXPECT_EQ(total.observations, 80u);
  EXPECT_EQ(total.observations_too_far, 0u);
  EXPECT_EQ(total.points_waiting_too_far, 0u);
  EXPECT_EQ(total.points_waiting, 40u);  // all 40 wait after the first keyframe only
}

TEST(InputFilters, DistanceQuantileIsTheNearestRank) {
  datasets::SlamStream stream;
  EXPECT_EQ(datasets::observationDistanceQuantile(stream, 0.95), 0.0);
  mesher::Keyframe keyframe;
  keyframe.position_W_C = Eigen::Vector3d(1, 2, 3);
  // Distances 1, 2, ..., 20 along x.
  for (int i = 1; i <= 20; ++i) {
    keyframe.observations.push_back({mesher::PointId{static_cast<std::uint64_t>(i)},
                                     keyframe.position_W_C + Eigen::Vector3d(i, 0, 0)});
  }
  stream.events.emplace_back(keyframe);
  stream.events.emplace_back(datasets::PointRemoval{{mesher::PointId{3}}});
  EXPECT_EQ(datasets::observationDistanceQuantile(stream, 0.95), 19.0);  // ceil(0.95 * 20) = 19th
  EXPECT_EQ(datasets::observationDistanceQuantile(stream, 1.0), 20.0);
  EXPECT_EQ(datasets::observationDistanceQuantile(stream, 0.5), 10.0);
  EXPECT_EQ(datasets::observationDistanceQuantile(stream, 0.0), 1.0);
  EXPECT_THROW(datasets::observationDistanceQuantile(stream, 1.5), std::invalid_argument);
  EXPECT_THROW(datasets::observationDistanceQuantile(stream, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::test
