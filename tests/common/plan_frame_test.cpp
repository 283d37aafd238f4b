// planFrame: orthonormal right-handed frames from an up vector, the helper axis each rule picks
// and the exact first axis of each variant its users depend on.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "common/plan_frame.h"

namespace terramesh::geometry {
namespace {

void expectOrthonormalRightHanded(const PlanFrame& f, const Eigen::Vector3d& up) {
  EXPECT_EQ(f.up, up);
  EXPECT_NEAR(f.e1.norm(), 1.0, 1e-12);
  EXPECT_NEAR(f.e2.norm(), 1.0, 1e-12);
  EXPECT_NEAR(f.e1.dot(f.e2), 0.0, 1e-12);
  EXPECT_NEAR(f.e1.dot(up), 0.0, 1e-12);
  EXPECT_NEAR(f.e2.dot(up), 0.0, 1e-12);
  EXPECT_NEAR((f.e1.cross(f.e2) - up).norm(), 0.0, 1e-12);
}

TEST(PlanFrameTest, EveryRuleGivesOrthonormalRightHandedFrames) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  for (int n = 0; n < 500; ++n) {
    const Eigen::Vector3d up = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    for (const PlanFrameRule& rule : {PlanFrameRule{}, exportFrameRule(), headingFrameRule(), acrossFrameRule()}) {
      expectOrthonormalRightHanded(planFrame(up, rule), up);
    }
  }
}

TEST(PlanFrameTest, ZUpGivesTheMapAxes) {
  const PlanFrame f = planFrame(Eigen::Vector3d::UnitZ());
  EXPECT_EQ(f.e1, Eigen::Vector3d::UnitX());
  EXPECT_EQ(f.e2, Eigen::Vector3d::UnitY());
  EXPECT_EQ(f.project(Eigen::Vector3d(3, -2, 5)), Eigen::Vector2d(3, -2));
  // up x helper is a quarter turn about up: e1 = y, e2 = -x.
  const PlanFrame g = planFrame(Eigen::Vector3d::UnitZ(), acrossFrameRule());
  EXPECT_EQ(g.e1, Eigen::Vector3d::UnitY());
  EXPECT_EQ(g.e2, -Eigen::Vector3d::UnitX());
}

TEST(PlanFrameTest, UpAlongEachMapAxisFallsBackAsDocumented) {
  // Up along x: x is no helper, y is; projected, e1 = y and e2 = x cross y = z.
  const PlanFrame x_up = planFrame(Eigen::Vector3d::UnitX());
  EXPECT_EQ(x_up.e1, Eigen::Vector3d::UnitY());
  EXPECT_EQ(x_up.e2, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(planFrame(-Eigen::Vector3d::UnitX()).e1, Eigen::Vector3d::UnitY());
  EXPECT_EQ(planFrame(Eigen::Vector3d::UnitX(), acrossFrameRule()).e1, Eigen::Vector3d::UnitZ());
  // Up along y (a camera frame): x stays the helper.
  const PlanFrame y_up = planFrame(Eigen::Vector3d::UnitY());
  EXPECT_EQ(y_up.e1, Eigen::Vector3d::UnitX());
  EXPECT_EQ(y_up.e2, -Eigen::Vector3d::UnitZ());
  const PlanFrame y_down = planFrame(-Eigen::Vector3d::UnitY());
  EXPECT_EQ(y_down.e1, Eigen::Vector3d::UnitX());
  EXPECT_EQ(y_down.e2, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(planFrame(Eigen::Vector3d::UnitY(), acrossFrameRule()).e1, -Eigen::Vector3d::UnitZ());
}

TEST(PlanFrameTest, HelperSwitchesAtTheRulesThreshold) {
  const auto tilted = [](double x) { return Eigen::Vector3d(x, 0, std::sqrt(1 - x * x)); };
  // Default: x while |up.x| < 0.9 (e1 leans on x), y from there on (e1 = y exactly: up has no y).
  EXPECT_GT(planFrame(tilted(0.89)).e1.x(), 0.4);
  EXPECT_EQ(planFrame(tilted(0.9)).e1, Eigen::Vector3d::UnitY());
  EXPECT_EQ(planFrame(tilted(-0.95)).e1, Eigen::Vector3d::UnitY());
  // The exports' rule: x up to and including |up.x| = cos 30 degrees.
  const PlanFrameRule rule = exportFrameRule();
  const double c = std::cos(30.0 * M_PI / 180.0);
  EXPECT_EQ(rule.x_helper_below_abs_up_x, std::nextafter(c, 2.0));
  EXPECT_GT(planFrame(tilted(c), rule).e1.x(), 0.4);
  EXPECT_EQ(planFrame(tilted(0.87), rule).e1, Eigen::Vector3d::UnitY());
  // By the projected norm: |x projected| = sqrt(1 - up.x^2), below 0.3 from |up.x| ~ 0.954 on.
  const PlanFrameRule by_norm = headingFrameRule();
  EXPECT_GT(planFrame(tilted(0.95), by_norm).e1.x(), 0.2);
  EXPECT_EQ(planFrame(tilted(0.96), by_norm).e1, Eigen::Vector3d::UnitY());
}

TEST(PlanFrameTest, FirstAxisIsTheProjectedHelperOrUpCrossHelper) {
  const Eigen::Vector3d up = Eigen::Vector3d(0.3, -0.4, 0.8).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  EXPECT_EQ(planFrame(up).e1, (x - x.dot(up) * up).normalized());
  EXPECT_EQ(planFrame(up, acrossFrameRule()).e1, up.cross(x).normalized());
  EXPECT_NEAR((planFrame(up, acrossFrameRule()).e1 - planFrame(up).e2).norm(), 0.0, 1e-15);
}

TEST(PlanFrameTest, InvalidRulesThrow) {
  PlanFrameRule rule;
  rule.x_helper_below_abs_up_x = 0.0;
  EXPECT_THROW(rule.validate(), std::invalid_argument);
  EXPECT_THROW(planFrame(Eigen::Vector3d::UnitZ(), rule), std::invalid_argument);
  rule = {};
  rule.x_helper_min_projected_norm = 1.0;
  EXPECT_THROW(rule.validate(), std::invalid_argument);
  rule.x_helper_below_abs_up_x = std::nan("");
  // Both problems are named at once.
  std::string message;
  EXPECT_THROW(
      {
        try {
          rule.validate();
        } catch (const std::invalid_argument& e) {
          message = e.what();
          throw;
        }
      },
      std::invalid_argument);
  EXPECT_NE(message.find("x_helper_below_abs_up_x"), std::string::npos) << message;
  EXPECT_NE(message.find("x_helper_min_projected_norm"), std::string::npos) << message;
  for (const PlanFrameRule& preset : {PlanFrameRule{}, exportFrameRule(), headingFrameRule(), acrossFrameRule()}) {
    EXPECT_NO_THROW(preset.validate());
  }
}

TEST(RotationUpToZTest, TurnsUpOntoZByTheSmallestRotation) {
  EXPECT_TRUE(rotationUpToZ(Eigen::Vector3d::UnitZ()).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  for (const Eigen::Vector3d& up : {Eigen::Vector3d(0.1, -0.2, 0.97), Eigen::Vector3d(1, 0, 0.01), Eigen::Vector3d(0, 3, 4)}) {
    const Eigen::Matrix3d R = rotationUpToZ(up);
    EXPECT_TRUE((R * up.normalized()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12)) << up.transpose();
    EXPECT_TRUE((R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    // The axis of the turn (up x z) stays where it is: no extra spin about up.
    const Eigen::Vector3d axis = up.normalized().cross(Eigen::Vector3d::UnitZ()).normalized();
    EXPECT_TRUE((R * axis).isApprox(axis, 1e-12)) << up.transpose();
  }
}

}  // namespace
}  // namespace terramesh::geometry
