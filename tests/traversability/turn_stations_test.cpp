// Stations through a turn: where the straight line between two keyframes strays from the arc the
// robot drove by more than max_sweep_sagitta_m, but not by more than the footprint's half width,
// the driven-ground stations follow the curve tangent to both headings, and the sweep and body
// views keep only the rays whose ground track stays over the body swept along it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "traversability/robot_profile.h"
#include "traversability/trajectory_evidence.h"

namespace terramesh::traversability {
namespace {

constexpr double kRadius = 0.34;  // small_wheeled's disc
constexpr double kArcRadius = 2.0;
const Eigen::Vector2d kArcCentre(0.0, kArcRadius);

RobotProfile disc() {
  RobotProfile profile;
  profile.footprint = FootprintShape::kDisc;
  profile.footprint_radius_m = kRadius;
  profile.min_clearance_m = 0.5;
  return profile;
}

/// A camera (x right, y down, z forward) 1 m above the ground at (x, y), heading `yaw` in a z-up world.
mesher::Keyframe camera(std::uint64_t id, double x, double y, double yaw) {
  mesher::Keyframe keyframe;
  keyframe.id = mesher::KeyframeId{id};
  keyframe.position_W_C = Eigen::Vector3d(x, y, 1.0);
  const Eigen::Vector3d forward(std::cos(yaw), std::sin(yaw), 0.0);
  Eigen::Matrix3d R_W_C;
  R_W_C.col(0) = forward.cross(Eigen::Vector3d::UnitZ());
  R_W_C.col(1) = -Eigen::Vector3d::UnitZ();
  R_W_C.col(2) = forward;
  keyframe.rotation_W_C = Eigen::Quaterniond(R_W_C);
  return keyframe;
}

/// Keyframe 2 a 60-degree arc of radius 2 m after keyframe 1 (left turn, centre (0, 2)): 2 m
/// apart, so the sagitta rule gives 2 x (pi / 3) / 8 = 0.26 m, over the 0.25 m of a straight
/// stretch and under the disc's 0.34 m.
mesher::Keyframe afterTheTurn() {
  const double angle = M_PI / 3.0;
  return camera(2, kArcRadius * std::sin(angle), kArcRadius * (1.0 - std::cos(angle)), angle);
}

double offTheArc(const Eigen::Vector3d& p_W) { return std::abs((p_W.head<2>() - kArcCentre).norm() - kArcRadius); }

TEST(TurnStationsTest, StationsFollowTheArcAndTheRaysStayOverTheBodyItSwept) {
  TrajectoryEvidence evidence(disc(), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  const std::size_t n = evidence.samplesPerKeyframe();
  evidence.augment(camera(1, 0, 0, 0));
  const mesher::Keyframe second = evidence.augment(afterTheTurn());
  EXPECT_EQ(evidence.turnCount(), 1u);
  const std::size_t stations = evidence.stationsFor(2.0);
  ASSERT_EQ(stations, 3u);
  // Its own patch and three stations, then the first keyframe's samples its sensor sees over the arc.
  ASSERT_GT(second.observations.size(), (1 + stations) * n);
  ASSERT_LE(second.observations.size(), (2 + stations) * n);
  for (std::size_t station = 1; station <= stations; ++station) {
    const Eigen::Vector3d& centre = second.observations[station * n + n / 2].position_W;
    // On the arc within 3 cm; the straight line's point would be 0.07-0.27 m inside it.
    EXPECT_LT(offTheArc(centre), 0.03) << "station " << station;
    const std::optional<Eigen::Isometry3d> base = evidence.baseOf(second.observations[station * n + n / 2].point);
    ASSERT_TRUE(base.has_value());
    // Heading along the arc: the tangent turns with the station (0, 15, 30, 45, 60 degrees).
    const double yaw = std::atan2(base->linear()(1, 0), base->linear()(0, 0));
    EXPECT_NEAR(yaw, (M_PI / 3.0) * static_cast<double>(station) / 4.0, 0.05) << "station " << station;
  }
  // Every ray of the sweep and of the body views runs over the strip the disc swept along the arc.
  const auto stays_over_the_strip = [](const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
    for (int k = 0; k <= 8; ++k) {
      if (offTheArc(from + (k / 8.0) * (to - from)) > kRadius + 0.02) return false;
    }
    return true;
  };
  for (std::size_t i = (1 + stations) * n; i < second.observations.size(); ++i) {
    EXPECT_TRUE(stays_over_the_strip(second.position_W_C, second.observations[i].position_W)) << "sweep ray " << i;
  }
  const std::vector<mesher::Keyframe> views = evidence.bodyViewsOf(mesher::KeyframeId{2});
  ASSERT_FALSE(views.empty());
  std::size_t rays = 0;
  for (const mesher::Keyframe& view : views) {
    EXPECT_NEAR(view.position_W_C.z(), 0.5, 1e-12);
    for (const mesher::PointObservation& o : view.observations) {
      EXPECT_TRUE(stays_over_the_strip(view.position_W_C, o.position_W))
          << "view " << view.id.value << " at " << view.position_W_C.transpose() << " to " << o.position_W.transpose();
    }
    rays += view.observations.size();
  }
  // Some samples are out of a view's reach: the rays to them would cut across the inside of the turn.
  EXPECT_LT(rays, kBodyViewSlots * (1 + stations) * n);
  EXPECT_GT(rays, 0u);
}

TEST(TurnStationsTest, WithoutTheRuleATurnHasNoStationsNorViews) {
  TrajectoryEvidenceConfig config;
  config.stations_along_turns = false;
  TrajectoryEvidence evidence(disc(), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), config);
  evidence.augment(camera(1, 0, 0, 0));
  EXPECT_EQ(evidence.augment(afterTheTurn()).observations.size(), evidence.samplesPerKeyframe());
  EXPECT_TRUE(evidence.bodyViewsOf(mesher::KeyframeId{2}).empty());
  EXPECT_EQ(evidence.turnCount(), 0u);
}

TEST(TurnStationsTest, ASharperTurnOrAWayAcrossTheHeadingsIsNotFollowed) {
  TrajectoryEvidence evidence(disc(), Eigen::Vector3d::UnitZ(), 1.0, 1.0, Eigen::Vector3d::UnitZ(), {});
  const std::size_t n = evidence.samplesPerKeyframe();
  evidence.augment(camera(1, 0, 0, 0));
  // A right angle 2 m on: sagitta 2 x (pi / 2) / 8 = 0.39 m, over the disc's radius.
  EXPECT_EQ(evidence.augment(camera(2, 1.5, 1.5, M_PI / 2.0)).observations.size(), n);
  // Sideways (a legged robot stepping across its heading while it turns, sagitta 2 x 1.1 / 8 =
  // 0.275 m): the headings say nothing of the way.
  evidence.augment(camera(3, 30, 0, M_PI / 2.0));
  EXPECT_EQ(evidence.augment(camera(4, 32, 0, M_PI / 2.0 + 1.1)).observations.size(), n);
  EXPECT_EQ(evidence.turnCount(), 0u);
  // The same turn as the first test, backwards (both headings against the way): followed.
  evidence.augment(camera(5, 60, 0, M_PI));
  const mesher::Keyframe back = camera(6, 60 + kArcRadius * std::sin(M_PI / 3.0),
                                       kArcRadius * (1.0 - std::cos(M_PI / 3.0)), M_PI + M_PI / 3.0);
  EXPECT_GT(evidence.augment(back).observations.size(), n);
  EXPECT_EQ(evidence.turnCount(), 1u);
}

}  // namespace
}  // namespace terramesh::traversability
