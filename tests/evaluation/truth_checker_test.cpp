// evaluation's checkAgainstTruth and TruthChecker on analytic truth meshes: a ground plane, a wall, a low ceiling
// and a step, each with a path that must pass and its twin that must fail.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "evaluation/truth_checker.h"

namespace terramesh::evaluation {
namespace {

using datasets::SurfaceLabel;
using Eigen::Vector3d;
using ::testing::HasSubstr;
using ::testing::Not;

/// A labelled truth built from axis-aligned quads (two triangles each).
class Truth {
 public:
  /// Horizontal rectangle [x0, x1] x [y0, y1] at height z.
  Truth& level(double x0, double x1, double y0, double y1, double z, SurfaceLabel label, float slope_deg = 0.0f) {
    return quad({x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}, label, slope_deg);
  }
  /// Vertical rectangle along x at y, from x0 to x1 and z0 to z1.
  Truth& wallAlongX(double y, double x0, double x1, double z0, double z1, SurfaceLabel label) {
    return quad({x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}, label, 90.0f);
  }
  /// Vertical rectangle along y at x, from y0 to y1 and z0 to z1.
  Truth& wallAlongY(double x, double y0, double y1, double z0, double z1, SurfaceLabel label) {
    return quad({x, y0, z0}, {x, y1, z0}, {x, y1, z1}, {x, y0, z1}, label, 90.0f);
  }
  const datasets::LabeledMesh& labeled() const { return mesh_; }
  TruthCheck check(const std::vector<Vector3d>& path, const TruthCheckConfig& config) const {
    const datasets::TriangleBvh bvh(mesh_.mesh);
    return checkAgainstTruth(mesh_, bvh, path, Vector3d::UnitZ(), 1.0, config);
  }
  /// The path walked by a body that keeps its own heading, `body` at each point.
  TruthCheck check(const std::vector<Vector3d>& path, const TruthCheckConfig& config,
                   const std::vector<Vector3d>& body) const {
    const datasets::TriangleBvh bvh(mesh_.mesh);
    return TruthChecker(mesh_, bvh).check(path, Vector3d::UnitZ(), 1.0, config, body);
  }

 private:
  Truth& quad(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d, SurfaceLabel label,
              float slope_deg) {
    const auto base = static_cast<std::uint32_t>(mesh_.mesh.vertices.size());
    mesh_.mesh.vertices.insert(mesh_.mesh.vertices.end(), {a, b, c, d});
    mesh_.mesh.faces.push_back({base, base + 1, base + 2});
    mesh_.mesh.faces.push_back({base, base + 2, base + 3});
    for (int i = 0; i < 2; ++i) {
      mesh_.labels.push_back(label);
      mesh_.slope_deg.push_back(slope_deg);
    }
    return *this;
  }
  datasets::LabeledMesh mesh_;
};

/// small_wheeled: a 0.34 m disc, 0.18 m step, 0.5 m high, 20 deg.
TruthCheckConfig smallWheeled() {
  TruthCheckConfig config;
  config.footprint_radius_m = 0.34;
  config.max_step_m = 0.18;
  config.min_clearance_m = 0.5;
  config.max_slope_deg = 20.0;
  return config;
}

std::vector<Vector3d> alongX(double y, double z) { return {{-3.0, y, z}, {0.0, y, z}, {3.0, y, z}}; }

TEST(GroundTruthCheck, PathOnTheGroundPasses) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  const TruthCheck check = truth.check(alongX(0.0, 0.0), smallWheeled());
  EXPECT_TRUE(check.valid) << check.reason;
  EXPECT_EQ(check.samples, 61u);  // 6 m every 0.1 m, both ends
  EXPECT_NEAR(check.max_ground_offset_m, 0.0, 1e-9);
}

TEST(GroundTruthCheck, PathWithinTheToleranceAboveTheGroundPasses) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  const TruthCheck check = truth.check(alongX(0.0, 0.25), smallWheeled());
  EXPECT_TRUE(check.valid) << check.reason;
  EXPECT_NEAR(check.max_ground_offset_m, 0.25, 1e-9);
}

TEST(GroundTruthCheck, PathHalfAMetreAboveTheGroundFails) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  const TruthCheck check = truth.check(alongX(0.0, 0.5), smallWheeled());
  EXPECT_FALSE(check.valid);
  EXPECT_THAT(check.reason, HasSubstr("0.500 m above the true road surface at (-3, 0, 0.5), 0.200 m beyond the tolerance"));
  EXPECT_THAT(check.reason, HasSubstr("tolerance 0.30 m"));
  EXPECT_THAT(check.reason, HasSubstr("reconstruction error"));
}

TEST(GroundTruthCheck, PathHalfAMetreBelowTheGroundFails) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  const TruthCheck check = truth.check(alongX(0.0, -0.5), smallWheeled());
  EXPECT_FALSE(check.valid);
  EXPECT_THAT(check.reason, HasSubstr("0.500 m below the true road surface"));
}

TEST(GroundTruthCheck, PathWithNoTrueSurfaceNearFails) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  const TruthCheck check = truth.check({{20.0, 0.0, 0.0}, {21.0, 0.0, 0.0}}, smallWheeled());
  EXPECT_FALSE(check.valid);
  EXPECT_THAT(check.reason, HasSubstr("no true surface within 5.00 m"));
}

TEST(GroundTruthCheck, WallWithinTheFootprintFailsAndBeyondItPasses) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kSidewalk).wallAlongX(1.0, -5, 5, 0.0, 2.0, SurfaceLabel::kWall);
  const TruthCheck near = truth.check(alongX(0.8, 0.0), smallWheeled());  // 0.2 m from the wall
  EXPECT_FALSE(near.valid);
  EXPECT_THAT(near.reason, HasSubstr("true wall face 0.20 m from the path at (-3, 0.8, 0)"));
  EXPECT_THAT(near.reason, HasSubstr("inside the 0.34 m footprint by 0.14 m"));
  const TruthCheck far = truth.check(alongX(0.5, 0.0), smallWheeled());  // 0.5 m from it
  EXPECT_TRUE(far.valid) << far.reason;
  TruthCheckConfig narrow = smallWheeled();
  narrow.footprint_radius_m = 0.15;  // the same 0.2 m gap is wide enough for a smaller robot
  const TruthCheck small = truth.check(alongX(0.8, 0.0), narrow);
  EXPECT_TRUE(small.valid) << small.reason;
}

TEST(GroundTruthCheck, LowCeilingFailsAndHighCeilingPasses) {
  Truth low;
  low.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).level(-1, 1, -2, 2, 0.4, SurfaceLabel::kCeiling, 180.0f);
  const TruthCheck under_low = low.check(alongX(0.0, 0.0), smallWheeled());
  EXPECT_FALSE(under_low.valid);
  EXPECT_THAT(under_low.reason, HasSubstr("true ceiling face 0.30 m from the path at (-1.3, 0, 0), inside the 0.34 m footprint by 0.04 m"));
  EXPECT_THAT(under_low.reason, HasSubstr("0.40 m above the true ground"));
  Truth high;
  high.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).level(-1, 1, -2, 2, 0.6, SurfaceLabel::kCeiling, 180.0f);
  const TruthCheck under_high = high.check(alongX(0.0, 0.0), smallWheeled());
  EXPECT_TRUE(under_high.valid) << under_high.reason;
}

/// Lower ground for x < 0, upper ground `step_m` higher for x > 0, joined by a wall riser.
Truth step(double step_m) {
  Truth truth;
  truth.level(-5, 0, -5, 5, 0.0, SurfaceLabel::kRoad)
      .level(0, 5, -5, 5, step_m, SurfaceLabel::kRoad)
      .wallAlongY(0.0, -5, 5, 0.0, step_m, SurfaceLabel::kWall);
  return truth;
}

std::vector<Vector3d> overStep(double step_m) {
  return {{-3.0, 0.0, 0.0}, {-0.01, 0.0, 0.0}, {0.01, 0.0, step_m}, {3.0, 0.0, step_m}};
}

TEST(GroundTruthCheck, StepBelowMaxStepPassesAndAboveItFails) {
  const TruthCheck low = step(0.1).check(overStep(0.1), smallWheeled());
  EXPECT_TRUE(low.valid) << low.reason;
  const TruthCheck high = step(0.25).check(overStep(0.25), smallWheeled());
  EXPECT_FALSE(high.valid);
  EXPECT_THAT(high.reason, HasSubstr("true wall face"));
  EXPECT_THAT(high.reason, HasSubstr("above the true ground (body from 0.18 m to 0.50 m)"));
}

TEST(GroundTruthCheck, NonDrivableFaceUnderThePathFails) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kObstacle);
  const TruthCheck check = truth.check(alongX(0.0, 0.0), smallWheeled());
  EXPECT_FALSE(check.valid);
  EXPECT_THAT(check.reason, HasSubstr("true obstacle face 0.00 m below the path at (-3, 0, 0) (not drivable)"));
}

TEST(GroundTruthCheck, TrueSlopeAboveTheLimitFails) {
  Truth steep;
  steep.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRamp, 25.0f);  // the label carries the true slope
  const TruthCheck check = steep.check(alongX(0.0, 0.0), smallWheeled());
  EXPECT_FALSE(check.valid);
  EXPECT_THAT(check.reason, HasSubstr("true slope 25 deg > 20 deg (by 5 deg)"));
  Truth gentle;
  gentle.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRamp, 15.0f);
  EXPECT_TRUE(gentle.check(alongX(0.0, 0.0), smallWheeled()).valid);
}

TEST(GroundTruthCheck, CrossingALowWallBetweenSamplesFails) {
  // A wall 0.4 m high and 0.01 m thick across the path, sparse samples either side of it: the
  // body test sees it from the samples; with a tiny robot only the crossing test can.
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).wallAlongY(0.0, -5, 5, 0.0, 0.4, SurfaceLabel::kWall);
  TruthCheckConfig config = smallWheeled();
  config.footprint_radius_m = 0.01;
  config.spacing_m = 1.0;
  const TruthCheck check = truth.check({{-0.5, 0.0, 0.0}, {0.5, 0.0, 0.0}}, config);
  EXPECT_FALSE(check.valid);
  EXPECT_THAT(check.reason, HasSubstr("crosses the true surface between (-0.5, 0, 0) and (0.5, 0, 0)"));
}

/// legged: a 1.1 x 0.5 m rectangle (circumscribed radius 0.60 m), 0.3 m step, 1 m high.
TruthCheckConfig legged() {
  TruthCheckConfig config;
  config.footprint_length_m = 1.1;
  config.footprint_width_m = 0.5;
  config.footprint_radius_m = 0.5 * std::hypot(1.1, 0.5);
  config.max_step_m = 0.3;
  config.min_clearance_m = 1.0;
  return config;
}

TEST(GroundTruthCheck, RectangleAlongItsPathPassesWhereItsCircumscribedDiscFails) {
  // A wall 0.30 m beside the path: outside the 0.25 m half width of the body driving along it,
  // inside its 0.60 m circumscribed disc and the half width of the same body turned across.
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).wallAlongX(0.3, -5, 5, 0.0, 2.0, SurfaceLabel::kWall);
  const TruthCheck along = truth.check(alongX(0.0, 0.0), legged());
  EXPECT_TRUE(along.valid) << along.reason;
  TruthCheckConfig disc = legged();
  disc.footprint_length_m = disc.footprint_width_m = 0.0;
  const TruthCheck as_disc = truth.check(alongX(0.0, 0.0), disc);
  EXPECT_FALSE(as_disc.valid);
  EXPECT_THAT(as_disc.reason, HasSubstr("inside the 0.60 m footprint"));
  TruthCheckConfig across = legged();
  std::swap(across.footprint_length_m, across.footprint_width_m);
  const TruthCheck wide = truth.check(alongX(0.0, 0.0), across);
  EXPECT_FALSE(wide.valid);
  EXPECT_THAT(wide.reason, HasSubstr("true wall face inside the 0.50 m x 1.10 m footprint turned to the heading"));
  EXPECT_THAT(wide.reason, HasSubstr("0.30 m left of the path at (-3, 0, 0)"));
}

TEST(GroundTruthCheck, RectangleDrivingUpToAWallFailsAtItsFrontEnd) {
  // A wall across the way 0.40 m beyond the path's end: the body's front reaches 0.55 m ahead,
  // into the wall from the sample at x = 2.9 on.
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).wallAlongY(3.4, -5, 5, 0.0, 2.0, SurfaceLabel::kWall);
  const TruthCheck check = truth.check(alongX(0.0, 0.0), legged());
  EXPECT_FALSE(check.valid);
  EXPECT_THAT(check.reason, HasSubstr("0.50 m ahead of and 0.00 m left of the path at (2.9, 0, 0)"));
  // Stopping 0.60 m short of it keeps the front 0.05 m clear.
  const TruthCheck short_of_it = truth.check({{-3.0, 0.0, 0.0}, {2.8, 0.0, 0.0}}, legged());
  EXPECT_TRUE(short_of_it.valid) << short_of_it.reason;
}

TEST(GroundTruthCheck, RectangleTurningAtACornerSweepsWhatItsSamplesMiss) {
  // A 0.1 x 1.0 m bar turns right at the corner of an L-shaped path: between the sample before
  // the corner (heading +x, the bar along y) and the one at it (heading -45 deg), its ends sweep
  // the quarter between the two legs. A post there, 0.35 m from the corner, is hit only while it
  // turns; the same post 0.6 m out is beyond the bar's 0.5 m half width.
  TruthCheckConfig bar = legged();
  bar.footprint_length_m = 0.1;
  bar.footprint_width_m = 1.0;
  const std::vector<Vector3d> corner = {{-3.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, -3.0, 0.0}};
  const auto post = [](double r) {
    const double a = 67.0 * M_PI / 180.0;
    Truth truth;
    const double x = r * std::cos(a), y = r * std::sin(a);
    truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).wallAlongY(x, y - 0.02, y + 0.02, 0.0, 2.0, SurfaceLabel::kObstacle);
    return truth;
  };
  const TruthCheck near = post(0.35).check(corner, bar);
  EXPECT_FALSE(near.valid);
  EXPECT_THAT(near.reason, HasSubstr("true obstacle face inside the 0.10 m x 1.00 m footprint"));
  EXPECT_THAT(near.reason, HasSubstr("turning by 45 deg there"));
  EXPECT_THAT(near.reason, HasSubstr("the path at (0, 0, 0)"));
  const TruthCheck far = post(0.6).check(corner, bar);
  EXPECT_TRUE(far.valid) << far.reason;
}

TEST(GroundTruthCheck, RectangleOnAPathWithoutHeadingIsItsCircumscribedDisc) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).wallAlongX(0.5, -5, 5, 0.0, 2.0, SurfaceLabel::kWall);
  const TruthCheck still = truth.check({{0.0, 0.0, 0.0}}, legged());
  EXPECT_FALSE(still.valid);
  EXPECT_THAT(still.reason, HasSubstr("true wall face 0.50 m from the path at (0, 0, 0), inside the 0.60 m footprint"));
}

TEST(GroundTruthCheck, RectangleKeepingItsOwnHeadingIsCheckedAtIt) {
  // The wall 0.30 m beside the path: the body along the path passes; walking the same path
  // sideways (body across it) or turning across it on the way fails; a heading per point is needed.
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad).wallAlongX(0.3, -5, 5, 0.0, 2.0, SurfaceLabel::kWall);
  const std::vector<Vector3d> path = alongX(0.0, 0.0);
  const Vector3d x = Vector3d::UnitX(), y = Vector3d::UnitY();
  EXPECT_TRUE(truth.check(path, legged(), {x, x, x}).valid);
  EXPECT_TRUE(truth.check(path, legged(), {-x, -x, -x}).valid);  // backwards: the same rectangle
  EXPECT_FALSE(truth.check(path, legged(), {x, -x, x}).valid);   // turning round passes across
  const TruthCheck sideways = truth.check(path, legged(), {y, y, y});
  EXPECT_FALSE(sideways.valid);
  EXPECT_THAT(sideways.reason, HasSubstr("footprint turned to the body's heading: "));
  EXPECT_THAT(sideways.reason, HasSubstr("at (-3, 0, 0)"));
  // Turning from along to across between the second and the last point: fine at x = 0, not after.
  const TruthCheck turning = truth.check(path, legged(), {x, x, y});
  EXPECT_FALSE(turning.valid);
  EXPECT_THAT(turning.reason, Not(HasSubstr("at (-3, 0, 0)")));
  EXPECT_THAT(turning.reason, Not(HasSubstr("at (0, 0, 0)")));
  EXPECT_THROW(truth.check(path, legged(), {x, x}), std::invalid_argument);
  EXPECT_THROW(truth.check(path, legged(), {x, Vector3d::UnitZ(), x}), std::invalid_argument);
}

TEST(GroundTruthCheck, EmptyPathIsValid) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  const TruthCheck check = truth.check({}, smallWheeled());
  EXPECT_TRUE(check.valid);
  EXPECT_EQ(check.samples, 0u);
}

TEST(GroundTruthCheck, ValidateReportsEveryProblem) {
  TruthCheckConfig config;
  EXPECT_NO_THROW(config.validate());
  config.footprint_radius_m = 0.0;
  config.max_step_m = 0.6;
  config.min_clearance_m = 0.5;
  config.vertical_tolerance_m = -1.0;
  config.body_slice_m = 0.0;
  try {
    config.validate();
    FAIL() << "validate() accepted an invalid config";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_THAT(what, HasSubstr("footprint_radius_m: 0"));
    EXPECT_THAT(what, HasSubstr("min_clearance_m: 0.5 (expected >= max_step_m 0.6)"));
    EXPECT_THAT(what, HasSubstr("vertical_tolerance_m: -1"));
    EXPECT_THAT(what, HasSubstr("body_slice_m: 0"));
  }
  TruthCheckConfig half = legged();
  half.footprint_width_m = 0.0;
  try {
    half.validate();
    FAIL() << "validate() accepted a rectangle without a width";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("footprint_length_m, footprint_width_m: 1.1, 0 (expected both > 0"));
  }
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  EXPECT_THROW(truth.check(alongX(0.0, 0.0), config), std::invalid_argument);
}

TEST(GroundTruthCheck, OneCheckerJudgesManyPathsAsSeparateChecksDo) {
  // The checker builds its obstacle tree once; nothing of one check may leak into the next.
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kSidewalk).wallAlongX(1.0, -5, 5, 0.0, 2.0, SurfaceLabel::kWall);
  const datasets::TriangleBvh bvh(truth.labeled().mesh);
  const TruthChecker checker(truth.labeled(), bvh);
  TruthCheckConfig narrow = smallWheeled();
  narrow.footprint_radius_m = 0.15;
  const std::vector<std::vector<Vector3d>> paths = {alongX(0.8, 0.0), alongX(0.5, 0.0), alongX(0.8, 0.0),
                                                    alongX(0.0, 0.5), alongX(0.5, 0.0)};
  for (const TruthCheckConfig& config : {smallWheeled(), narrow}) {
    for (const std::vector<Vector3d>& path : paths) {
      const TruthCheck once = truth.check(path, config);
      const TruthCheck reused = checker.check(path, Vector3d::UnitZ(), 1.0, config);
      EXPECT_EQ(reused.valid, once.valid) << once.reason;
      EXPECT_EQ(reused.reason, once.reason);
      EXPECT_EQ(reused.samples, once.samples);
      EXPECT_EQ(reused.max_ground_offset_m, once.max_ground_offset_m);
    }
  }
  // And the answers are the ones the single-path tests above expect.
  EXPECT_FALSE(checker.check(alongX(0.8, 0.0), Vector3d::UnitZ(), 1.0, smallWheeled()).valid);
  EXPECT_TRUE(checker.check(alongX(0.5, 0.0), Vector3d::UnitZ(), 1.0, smallWheeled()).valid);
  EXPECT_TRUE(checker.check(alongX(0.8, 0.0), Vector3d::UnitZ(), 1.0, narrow).valid);
}

TEST(GroundTruthCheck, CheckerRefusesATruthWithoutLabels) {
  Truth truth;
  truth.level(-5, 5, -5, 5, 0.0, SurfaceLabel::kRoad);
  datasets::LabeledMesh unlabeled = truth.labeled();
  unlabeled.labels.pop_back();
  const datasets::TriangleBvh bvh(unlabeled.mesh);
  EXPECT_THROW(TruthChecker(unlabeled, bvh), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::evaluation
