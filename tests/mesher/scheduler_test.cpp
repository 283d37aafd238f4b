// The scheduler's rules and deferred moves: a ray is walked at most once per update however many
// changes cut it, and a moved point whose star still touches O keeps its vertex until it can move.
#include <gtest/gtest.h>

#include <set>

#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

bool hasVertexAt(const Mesher& mesher, const Eigen::Vector3d& p) {
  for (const CellVisibility& cell : mesher.cellVisibility()) {
    for (const Eigen::Vector3d& v : cell.vertices_W) {
      if (v == p) return true;
    }
  }
  return false;
}

TEST(RayScheduler, WalksEachStoredRayAtMostOncePerUpdate) {
  test::SceneOptions options;
  const auto keyframes = test::withMovingEstimates(test::boxRoomScene(options).keyframes, 0.08, 11);
  for (bool scheduled : {true, false}) {
    MesherConfig config;
    config.steiner_step_m = 4.0;
    config.ray_scheduler = scheduled;
    Mesher mesher(config);
    std::size_t over = 0, busy = 0;
    for (const Keyframe& keyframe : keyframes) {
      const UpdateStats stats = mesher.integrateKeyframe(keyframe);
      const std::size_t walked = stats.rays_traced + stats.rays_retraced;
      // Rays walked in this update are stored at its end (none is destroyed after its walk).
      over += walked > mesher.size().rays;
      busy += stats.moved_points > 0 && stats.rays_retraced > 0;
    }
    ASSERT_GT(busy, 5u) << "updates must move points and cut stored rays";
    if (scheduled) {
      EXPECT_EQ(over, 0u) << "a ray was walked twice in one update";
    } else {
      EXPECT_GT(over, 0u) << "without the scheduler, rays cut by several changes are walked again";
    }
  }
}

TEST(DeferredMove, AMovedPointWhoseStarTouchesOKeepsItsVertexUntilItCanMove) {
  // litvinov13 with exact moves: its enclosing set is the sphere of radius max_camera_distance_m +
  // sqrt(3) l around the update's camera. A keyframe 60 m above a surface point re-estimates it:
  // the point's star lies outside that sphere, is not shrunk, and still touches O.
  test::SceneOptions options;
  std::vector<Keyframe> keyframes = test::planeScene(options).keyframes;
  const Keyframe& last = keyframes.back();
  // A point of the last keyframe near the middle of its view: on the carved surface.
  const PointObservation* chosen = nullptr;
  for (const PointObservation& o : last.observations) {
    if (chosen == nullptr || (o.position_W - last.position_W_C).norm() <
                                 (chosen->position_W - last.position_W_C).norm()) {
      chosen = &o;
    }
  }
  ASSERT_NE(chosen, nullptr);
  const PointObservation target = *chosen;
  const Eigen::Vector3d moved_to = target.position_W + Eigen::Vector3d(0.3, 0.2, 0.0);

  Keyframe far;
  far.id = KeyframeId{1000};
  far.position_W_C = target.position_W + Eigen::Vector3d(0, 0, 60);
  far.observations.push_back({target.point, moved_to});

  MesherConfig config = MesherConfig::forMode(MesherMode::kLitvinov13);
  config.point_policy = PointPolicy::kExactMoves;
  config.steiner_step_m = 4.0;
  std::vector<Keyframe> all = keyframes;
  all.push_back(far);
  config.fixed_grid_bounds_W = test::keyframeBounds(all);
  Mesher mesher(config);
  for (const Keyframe& keyframe : keyframes) mesher.integrateKeyframe(keyframe);
  ASSERT_TRUE(hasVertexAt(mesher, target.position_W));

  const UpdateStats deferred = mesher.integrateKeyframe(far);
  EXPECT_EQ(deferred.deferred_points, 1u);
  EXPECT_EQ(deferred.moved_points, 0u);
  EXPECT_TRUE(hasVertexAt(mesher, target.position_W)) << "the point keeps its vertex for now";
  EXPECT_FALSE(hasVertexAt(mesher, moved_to));
  InvariantReport report = mesher.checkInvariants();
  ASSERT_TRUE(report.ok()) << report.summary();

  // The last keyframe, re-sent with the new estimate: its camera's sphere encloses the star.
  Keyframe again = last;
  for (PointObservation& o : again.observations) {
    if (o.point == target.point) o.position_W = moved_to;
  }
  const UpdateStats moved = mesher.integrateKeyframe(again);
  EXPECT_EQ(moved.deferred_points, 0u);
  EXPECT_EQ(moved.moved_points, 1u);
  EXPECT_FALSE(hasVertexAt(mesher, target.position_W));
  EXPECT_TRUE(hasVertexAt(mesher, moved_to));
  report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
}

}  // namespace
}  // namespace terramesh::mesher
