// The drive against the SLAM points around it (docs/traversability.md, "Trajectory evidence"):
// points it drove through or over are left out, the sweep between keyframes and the stations at a
// drive's start; and later obstacles win over the old drive: a SLAM point first seen after the
// robot drove on, inside the body where it was, withdraws that drive's evidence, in
// TrajectoryEvidence and in the mesher.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>
#include <vector>

#include "mesher/mesher.h"
#include "test_support/mesh_queries.h"
#include "traversability/trajectory_evidence.h"

namespace terramesh::traversability {
namespace {

RobotProfile discRobot(double radius_m) {
  RobotProfile profile;
  profile.footprint = FootprintShape::kDisc;
  profile.footprint_radius_m = radius_m;
  return profile;  // max_step_m 0.2, min_clearance_m 1 by default: the body spans 0.2-1 m
}

/// A camera (x right, y down, z forward) at `position`, looking along `forward` (horizontal) in a
/// z-up world.
mesher::Keyframe cameraAt(std::uint64_t id, const Eigen::Vector3d& position,
                          const Eigen::Vector3d& forward = Eigen::Vector3d::UnitX()) {
  mesher::Keyframe keyframe;
  keyframe.id = mesher::KeyframeId{id};
  keyframe.position_W_C = position;
  Eigen::Matrix3d R_W_C;
  R_W_C.col(2) = forward.normalized();
  R_W_C.col(1) = -Eigen::Vector3d::UnitZ();
  R_W_C.col(0) = R_W_C.col(1).cross(R_W_C.col(2));
  keyframe.rotation_W_C = Eigen::Quaterniond(R_W_C);
  return keyframe;
}

mesher::PointObservation observation(std::uint64_t id, const Eigen::Vector3d& p) {
  mesher::PointObservation o;
  o.point = mesher::PointId{id};
  o.position_W = p;
  return o;
}

std::size_t drivenCount(const mesher::Keyframe& keyframe) {
  std::size_t n = 0;
  for (const auto& o : keyframe.observations) n += o.kind == mesher::PointKind::kDrivenGround ? 1 : 0;
  return n;
}

TEST(DrivenSamplesTest, AKeyframeThatStartsADriveHasStationsBackToItsFootprintsRearEdge) {
  // The car (4.8 m long) at its first keyframe stood on its whole footprint: besides its own
  // cross-section, cross-sections at most 0.5 m apart back to 2.4 m behind it.
  RobotProfile car;
  car.footprint = FootprintShape::kRectangle;
  car.footprint_length_m = 4.8;
  car.footprint_width_m = 1.8;
  TrajectoryEvidence evidence(car, Eigen::Vector3d::UnitZ(), 1.0, 1.65, Eigen::Vector3d::UnitZ(), {});
  const mesher::Keyframe first = evidence.augment(cameraAt(1, {10, 0, 1.65}));
  std::vector<Eigen::Vector3d> samples;
  for (const auto& o : first.observations) {
    if (o.kind == mesher::PointKind::kDrivenGround) samples.push_back(o.position_W);
  }
  ASSERT_EQ(samples.size(), 5 * evidence.samplesPerKeyframe());  // its own and 4 stations
  std::set<long> rows;
  for (const Eigen::Vector3d& p : samples) {
    EXPECT_NEAR(p.z(), 0.0, 1e-9);
    EXPECT_LE(std::abs(p.y()), 0.9 + 1e-9);
    rows.insert(std::lround((p.x() - 10.0) * 10));
  }
  EXPECT_EQ(rows, (std::set<long>{-24, -18, -12, -6, 0}));
  // The next keyframe, 3 m on, has its stations between the two, as before.
  const mesher::Keyframe second = evidence.augment(cameraAt(2, {13, 0, 1.65}));
  double rear = 1e9;
  for (const auto& o : second.observations) {
    if (isDrivenGroundId(o.point) && ((o.point.value & ~kDrivenGroundIdBit) >> kDrivenSampleIndexBits) == 2) {
      rear = std::min(rear, o.position_W.x());
    }
  }
  EXPECT_GT(rear, 10.0);
  EXPECT_LT(rear, 13.0);

  // Its body is the footprint it stood on (x 7.6 to 12.4), not one centred on each station (the
  // last would reach back to x 5.2): a point 0.5 m up behind the rear edge (a wall behind the
  // start) is kept, one over the footprint is the drive's to drop; neither overrides later.
  TrajectoryEvidence start(car, Eigen::Vector3d::UnitZ(), 1.0, 1.65, Eigen::Vector3d::UnitZ(), {});
  mesher::Keyframe seeing = cameraAt(1, {10, 0, 1.65});
  seeing.observations = {observation(500, {7.0, 0, 0.5}), observation(501, {8.5, 0, 0.5})};
  start.augment(seeing);
  ASSERT_EQ(start.newlyContradicted().size(), 1u);
  EXPECT_EQ(start.newlyContradicted().front().value, 501u);
  start.augment(cameraAt(2, {13, 0, 1.65}));
  for (std::uint64_t k : {3, 4}) {
    mesher::Keyframe later = cameraAt(k, {20.0 + static_cast<double>(k), 0, 1.65});
    later.observations = {observation(600, {6.8, 0.5, 0.5})};
    start.augment(later);
  }
  EXPECT_EQ(start.overriddenCount(), 0u);
}

TEST(DrivenSamplesTest, PointsForgottenBeyondTheKeptKeyframesAreJudgedAgain) {
  // The online freeze forgets the points of a region left behind: one the drive left out (inside
  // the body) and one it kept track of. Seen again from elsewhere, the first is not left out any
  // more; the counts of what was left out stay.
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  mesher::Keyframe first = cameraAt(1, {0, 0, 1});
  first.observations = {observation(10, {0.1, 0, 0.5}), observation(14, {5, 0, 0.5})};
  evidence.augment(first);
  ASSERT_EQ(evidence.contradictedCount(), 1u);
  EXPECT_EQ(evidence.forgetPointsBeyond({Eigen::Vector3d(20, 0, 1)}, 30.0), 0u);  // both within 30 m
  EXPECT_EQ(evidence.forgetPointsBeyond({Eigen::Vector3d(200, 0, 1)}, 30.0), 2u);
  EXPECT_EQ(evidence.forgetPointsBeyond({Eigen::Vector3d(200, 0, 1)}, 30.0), 0u);
  EXPECT_EQ(evidence.contradictedCount(), 1u);
  mesher::Keyframe later = cameraAt(2, {0, 3, 1}, Eigen::Vector3d::UnitY());
  later.observations = {observation(10, {0.1, 0, 0.5})};
  const mesher::Keyframe augmented = evidence.augment(later);
  const bool seen = std::any_of(augmented.observations.begin(), augmented.observations.end(),
                                [](const mesher::PointObservation& o) { return o.point.value == 10; });
  EXPECT_TRUE(seen);
}

TEST(DrivenSamplesTest, TheSweepSpansLongGapsAlongTheHeadingButNotAroundATurn) {
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  evidence.augment(cameraAt(1, {0, 0, 1}));
  evidence.augment(cameraAt(2, {8, 0, 1}));  // 8 m straight on: a car's keyframe gap
  EXPECT_EQ(evidence.bodyViewsOf(mesher::KeyframeId{2}).size(), kBodyViewSlots);
  // 8 m further, turned by 90 degrees: the straight line cuts the corner by about 1.6 m.
  evidence.augment(cameraAt(3, {16, 0, 1}, Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{3}).empty());
  // 11 m on: beyond max_sweep_distance_m.
  evidence.augment(cameraAt(4, {16, 11, 1}, Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{4}).empty());
}

TEST(DrivenSamplesTest, PointsInsideTheBodyWhereTheRobotDroveAreDroppedForGood) {
  // A 0.3 m disc robot (max_step 0.2 m, 1 m tall by default) with its sensor 1 m up: a point 0.5 m
  // above the ground right under the sensor is inside its body (an outlier the robot drove
  // through); a point on the ground under it is ground the drive measured (left out, absorbed);
  // points above the robot, beside it or 0.15 m under its contact plane are not.
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  const auto ids = [](const std::vector<mesher::PointId>& points) {
    std::vector<std::uint64_t> values;
    for (const mesher::PointId& id : points) values.push_back(id.value);
    std::sort(values.begin(), values.end());
    return values;
  };
  const auto kept = [](const mesher::Keyframe& keyframe) {
    std::vector<std::uint64_t> values;
    for (const auto& o : keyframe.observations) {
      if (!isDrivenGroundId(o.point)) values.push_back(o.point.value);
    }
    return values;
  };
  mesher::Keyframe first = cameraAt(1, {0, 0, 1});
  first.observations = {observation(10, {0.1, 0, 0.5}), observation(11, {0.1, 0, 0.01}), observation(12, {0, 0, 1.5}),
                        observation(13, {0, 0.5, 0.5}), observation(14, {5, 0, 0.5}), observation(16, {0, 0.1, -0.15}),
                        observation(17, {2.1, 0, 0.5}), observation(18, {2.1, 0.1, 0.02})};
  EXPECT_EQ(kept(evidence.augment(first)), (std::vector<std::uint64_t>{12, 13, 14, 16, 17, 18}));
  EXPECT_EQ(ids(evidence.newlyContradicted()), (std::vector<std::uint64_t>{10, 11}));
  EXPECT_EQ(evidence.contradictedCount(), 1u);
  EXPECT_EQ(evidence.absorbedCount(), 1u);
  // Half way to the next keyframe the body passes the point at x = 1: contradicted then. Point 10,
  // seen again, stays out (not newly contradicted); point 14 lies where the robot never was.
  // Points 17 and 18 were seen from the first keyframe ahead of the robot; the second one's body
  // reaches them (a forward camera does not see the road under the robot): left out now, though
  // the second keyframe does not see them.
  mesher::Keyframe second = cameraAt(2, {2, 0, 1});
  second.observations = {observation(10, {0.1, 0, 0.5}), observation(15, {1, 0, 0.5}), observation(14, {5, 0, 0.5})};
  EXPECT_EQ(kept(evidence.augment(second)), (std::vector<std::uint64_t>{14}));
  EXPECT_EQ(ids(evidence.newlyContradicted()), (std::vector<std::uint64_t>{15, 17, 18}));
  EXPECT_EQ(evidence.contradictedCount(), 3u);
  EXPECT_EQ(evidence.absorbedCount(), 2u);
  // An obstacle placed later where the robot once was (x = 0) is seen from keyframe 3, 20 m on.
  mesher::Keyframe third = cameraAt(3, {20, 0, 1});
  third.observations = {observation(20, {0.05, 0, 0.5})};
  EXPECT_EQ(evidence.augment(third).observations.front().point.value, 20u);
  EXPECT_TRUE(evidence.newlyContradicted().empty());
  // A ground point seen later where the robot drove is ground the drive measured.
  mesher::Keyframe fourth = cameraAt(4, {22, 0, 1});
  fourth.observations = {observation(21, {1.5, 0.05, -0.03})};
  EXPECT_EQ(kept(evidence.augment(fourth)), (std::vector<std::uint64_t>{}));
  EXPECT_EQ(ids(evidence.newlyContradicted()), (std::vector<std::uint64_t>{21}));
  EXPECT_EQ(evidence.absorbedCount(), 3u);
}

TEST(LaterObstacleTest, APointSeenLaterInsideAnOldBodyOverridesThatKeyframesDrive) {
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  for (std::uint64_t k = 1; k <= 5; ++k) evidence.augment(cameraAt(k, {2.0 * (k - 1), 0, 1}));
  ASSERT_EQ(evidence.bodyViewsOf(mesher::KeyframeId{3}).size(), kBodyViewSlots);
  const std::size_t patch = evidence.samplesPerKeyframe();
  // From 20 m on: a point 0.5 m up where keyframe 3 (x = 4) stood, one beside the path, one on the
  // ground (below the step height), all seen for the first time.
  mesher::Keyframe later = cameraAt(6, {20, 0, 1});
  later.observations = {observation(100, {4, 0, 0.5}), observation(101, {4, 2, 0.5}), observation(102, {4, 0, 0.05})};
  evidence.augment(later);
  // The point on the ground where keyframe 3 stood is ground the drive measured.
  ASSERT_EQ(evidence.newlyContradicted().size(), 1u);
  EXPECT_EQ(evidence.newlyContradicted().front().value, 102u);
  // Seen by one keyframe, a point is not in the mesh (min_views 2) and overrides no drive; nor
  // when that keyframe is sent again (a pose correction).
  EXPECT_TRUE(evidence.newlyOverridden().empty());
  evidence.augment(later);
  EXPECT_TRUE(evidence.newlyOverridden().empty());
  EXPECT_EQ(evidence.overriddenCount(), 0u);
  // A second keyframe sees it: keyframe 3, and keyframe 2, whose samples keyframe 3's sensor
  // swept to.
  mesher::Keyframe second = cameraAt(9, {21, 0, 1});
  second.observations = {observation(100, {4, 0, 0.5}), observation(101, {4, 2, 0.5})};
  evidence.augment(second);
  ASSERT_EQ(evidence.newlyOverridden().size(), 2u);
  EXPECT_EQ(evidence.newlyOverridden()[0].value, 3u);
  EXPECT_EQ(evidence.newlyOverridden()[1].value, 2u);
  EXPECT_EQ(evidence.overriddenCount(), 2u);
  // The views of 3 and 2, and of 4 and 3, which stand at their bases: every slot of each.
  std::vector<std::uint64_t> views;
  for (const mesher::KeyframeId& id : evidence.newlyWithdrawnViews()) {
    EXPECT_NE(id.value & kBodyViewKeyframeBit, 0u);
    views.push_back(id.value & ((std::uint64_t{1} << kBodyViewSlotShift) - 1));
  }
  std::sort(views.begin(), views.end());
  // (and the underside views of 3 and 2, which they would have with a level beneath)
  EXPECT_EQ(views, (std::vector<std::uint64_t>{2, 2, 2, 2, 2, 2, 2, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 4, 4, 4,
                                               4, 4, 4}));
  for (std::uint64_t k : {2, 3, 4}) EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{k}).empty()) << k;
  EXPECT_EQ(evidence.bodyViewsOf(mesher::KeyframeId{5}).size(), kBodyViewSlots);
  EXPECT_EQ(evidence.sampleIdsOf(mesher::KeyframeId{3}).size(), 2 * 4 * patch)
      << "its patch and 3 stations, and their undersides, to remove";
  // Re-sent, keyframe 3 carries no samples (nor a sweep); keyframe 4 its own but no sweep to 3's.
  EXPECT_EQ(drivenCount(evidence.augment(cameraAt(3, {4, 0, 1}))), 0u);
  EXPECT_EQ(drivenCount(evidence.augment(cameraAt(4, {6, 0, 1}))), 4 * patch);
  EXPECT_TRUE(evidence.newlyOverridden().empty());
  // A point seen before overrides nothing, even where the robot was.
  mesher::Keyframe again = cameraAt(7, {22, 0, 1});
  again.observations = {observation(100, {8, 0, 0.5})};
  evidence.augment(again);
  EXPECT_TRUE(evidence.newlyOverridden().empty());
  // Inside the body at the keyframe before: the robot drove through it, an outlier (contradicted).
  mesher::Keyframe next = cameraAt(8, {24, 0, 1});
  next.observations = {observation(103, {22, 0, 0.5})};
  evidence.augment(next);
  EXPECT_TRUE(evidence.newlyOverridden().empty());
  ASSERT_EQ(evidence.newlyContradicted().size(), 1u);
  EXPECT_EQ(evidence.newlyContradicted().front().value, 103u);
  // Removed, keyframe 3 is forgotten, overridden or not.
  evidence.remove(mesher::KeyframeId{3});
  EXPECT_EQ(evidence.overriddenCount(), 1u);

  TrajectoryEvidenceConfig off;
  off.later_obstacles_win = false;
  TrajectoryEvidence old_drive_wins(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), off);
  for (std::uint64_t k = 1; k <= 5; ++k) old_drive_wins.augment(cameraAt(k, {2.0 * (k - 1), 0, 1}));
  old_drive_wins.augment(later);
  EXPECT_TRUE(old_drive_wins.newlyOverridden().empty());

  // Where the mesher inserts points seen once (LiDAR: min_views 1), one sighting is enough.
  TrajectoryEvidenceConfig one_view;
  one_view.later_obstacle_min_views = 1;
  TrajectoryEvidence scans(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), one_view);
  for (std::uint64_t k = 1; k <= 5; ++k) scans.augment(cameraAt(k, {2.0 * (k - 1), 0, 1}));
  scans.augment(later);
  EXPECT_EQ(scans.overriddenCount(), 2u);
}

/// A box parked on a lane the robot drove earlier, seen only on a second lap, in the mesher. On
/// the first lap (lane y = 0) the camera looks to the right (-y), at ground beyond y = -2, so only
/// the driven evidence observes the lane; on the second (y = 4) it looks at the lane, at the box
/// (x 7.7-8.3, y -0.3-0.3, 0.6 m tall) and at the ground in front of it.
mesher::TriangleMesh meshBoxScene(bool later_obstacles_win, std::size_t& overridden) {
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  config.steiner_step_m = 4.0;
  TrajectoryEvidenceConfig evidence_config;
  evidence_config.later_obstacles_win = later_obstacles_win;
  // The robot drives along +x; its camera looks along -y: forward is -x in the camera frame.
  TrajectoryEvidence evidence(discRobot(0.3), Eigen::Vector3d::UnitZ(), 1.0, 1.65, -Eigen::Vector3d::UnitX(),
                              evidence_config);
  evidence.configureMesher(config);
  mesher::Mesher mesher(config);
  std::uint64_t next_point = 1;
  std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> ground_right, ground_front, box;
  for (double x = -4; x <= 20; x += 0.5) {
    for (double y = -12; y <= -2; y += 0.5) ground_right.push_back({next_point++, {x, y, 0}});
    for (double y = 0.5; y <= 3; y += 0.5) ground_front.push_back({next_point++, {x, y, 0}});
  }
  for (double x = 7.7; x <= 8.31; x += 0.1) {
    for (double z = 0.05; z <= 0.6; z += 0.1) box.push_back({next_point++, {x, 0.3, z}});
    for (double y = -0.3; y <= 0.31; y += 0.1) box.push_back({next_point++, {x, y, 0.6}});
  }
  const auto lap = [&](std::uint64_t first_id, double y, const std::vector<const decltype(box)*>& seen) {
    for (int k = 0; k <= 8; ++k) {
      mesher::Keyframe keyframe = cameraAt(first_id + k, {2.0 * k, y, 1.65}, -Eigen::Vector3d::UnitY());
      for (const auto* points : seen) {
        for (const auto& [id, p] : *points) {
          if ((p - keyframe.position_W_C).norm() < 12) keyframe.observations.push_back(observation(id, p));
        }
      }
      mesher.integrateKeyframe(evidence.augment(keyframe));
      if (!evidence.newlyContradicted().empty()) mesher.removePoints(evidence.newlyContradicted());
      for (const mesher::KeyframeId& id : evidence.newlyWithdrawnViews()) mesher.removeKeyframe(id);
      for (const mesher::KeyframeId& id : evidence.newlyOverridden()) mesher.removePoints(evidence.sampleIdsOf(id));
      for (const mesher::Keyframe& view : evidence.bodyViewsOf(keyframe.id)) mesher.integrateKeyframe(view);
    }
  };
  lap(1, 0.0, {&ground_right});
  lap(20, 4.0, {&ground_front, &box});
  overridden = evidence.overriddenCount();
  EXPECT_TRUE(mesher.checkInvariants().ok());
  return mesher.extractMesh();
}

TEST(LaterObstacleTest, ABoxParkedOnTheDrivenLaneStaysInTheMesh) {
  std::size_t overridden_on = 0, overridden_off = 0;
  const mesher::TriangleMesh on = meshBoxScene(true, overridden_on);
  const mesher::TriangleMesh off = meshBoxScene(false, overridden_off);
  ASSERT_TRUE(mesher::analyzeTopology(on).isClosedManifold());
  // Inside the box, 0.1-0.5 m up: free space (carved) means the box is gone from the map.
  std::size_t free_on = 0, free_off = 0, probes = 0;
  for (double x = 7.8; x <= 8.21; x += 0.1) {
    for (double y = -0.2; y <= 0.21; y += 0.1) {
      for (double z = 0.1; z <= 0.51; z += 0.1) {
        free_on += test::insideClosedMesh(on, {x, y, z});
        free_off += test::insideClosedMesh(off, {x, y, z});
        ++probes;
      }
    }
  }
  std::printf("box interior in free space: %zu of %zu probes with later obstacles winning (%zu keyframes "
              "overridden), %zu with the old drive winning\n", free_on, probes, overridden_on, free_off);
  EXPECT_EQ(overridden_off, 0u);
  EXPECT_GE(overridden_on, 1u);
  EXPECT_LE(free_on, probes / 10);
  EXPECT_GT(free_off, free_on);
}

}  // namespace
}  // namespace terramesh::traversability
