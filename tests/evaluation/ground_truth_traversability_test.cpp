// The per-robot ground-truth labeller on hand-made labelled meshes with known answers.
#include "evaluation/ground_truth_traversability.h"

#include <gtest/gtest.h>

#include <cmath>

#include "datasets/triangle_bvh.h"
#include "evaluation/mesh_refinement.h"
#include "labeled_mesh_builder.h"

namespace terramesh::evaluation {
namespace {

using datasets::LabeledMesh;
using datasets::SurfaceLabel;
using test::addFloor;
using test::addQuad;

RobotLimits robot(double radius, double slope, double step, double height) {
  RobotLimits limits;
  limits.footprint_radius_m = radius;
  limits.max_slope_deg = slope;
  limits.max_step_m = step;
  limits.height_m = height;
  return limits;
}

/// The answer for the ground-truth face under `point`.
TruthReason reasonAt(const GroundTruthTraversability& truth, const Eigen::Vector3d& point) {
  const datasets::TriangleBvh bvh(truth.mesh.mesh);
  const auto nearest = bvh.closestPoint(point);
  EXPECT_LT(nearest.distance, 1e-9) << "the query point is not on the truth";
  EXPECT_EQ(truth.traversable[nearest.face] != 0, truth.reasons[nearest.face] == TruthReason::kTraversable);
  return truth.reasons[nearest.face];
}

GroundTruthTraversability label(const LabeledMesh& mesh, const RobotLimits& limits) {
  return labelTraversability(mesh, limits, Eigen::Vector3d::UnitZ(), GroundTruthConfig{});
}

/// Road z = 0 for x < 0, a 0.15 m curb riser at x = 0 facing the road, the curb top beyond.
LabeledMesh curbScene() {
  LabeledMesh mesh;
  addFloor(mesh, -3, 0, -1, 1, 0, SurfaceLabel::kRoad);
  addQuad(mesh, {0, -1, 0}, {0, 1, 0}, {0, 1, 0.15}, {0, -1, 0.15}, SurfaceLabel::kCurb);
  addFloor(mesh, 0, 3, -1, 1, 0.15, SurfaceLabel::kCurb);
  return mesh;
}

TEST(GroundTruthTraversability, CurbOf15cmIsPassableForStep20cmButNot10cm) {
  const LabeledMesh mesh = curbScene();
  const GroundTruthTraversability climber = label(mesh, robot(0.3, 20, 0.2, 1.0));
  const GroundTruthTraversability low = label(mesh, robot(0.3, 20, 0.1, 1.0));
  const Eigen::Vector3d curb_top(0.1, 0.05, 0.15), road_by_curb(-0.1, 0.05, 0);
  EXPECT_EQ(reasonAt(climber, curb_top), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(climber, road_by_curb), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(low, curb_top), TruthReason::kCurbTooHigh);
  EXPECT_EQ(reasonAt(low, road_by_curb), TruthReason::kStepInFootprint);
  // Beyond the footprint radius both robots are fine; the riser is a wall for both.
  EXPECT_EQ(reasonAt(low, {1.5, 0.05, 0.15}), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(low, {-1.5, 0.05, 0}), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(climber, {0, 0.05, 0.07}), TruthReason::kTooSteep);
}

TEST(GroundTruthTraversability, FloorUnderLowCeilingIsNotTraversable) {
  LabeledMesh mesh;
  addFloor(mesh, 0, 4, 0, 4, 0, SurfaceLabel::kRoad);
  // Ceiling over x in [0, 2] at 0.8 m, facing down.
  addQuad(mesh, {0, 0, 0.8}, {0, 4, 0.8}, {2, 4, 0.8}, {2, 0, 0.8}, SurfaceLabel::kCeiling);
  ASSERT_NEAR(mesh.slope_deg.back(), 180.0, 1e-4);
  const GroundTruthTraversability tall = label(mesh, robot(0.3, 20, 0.2, 1.0));
  EXPECT_EQ(reasonAt(tall, {1, 2, 0}), TruthReason::kLowClearance);
  EXPECT_EQ(reasonAt(tall, {3.5, 2, 0}), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(tall, {1, 2, 0.8}), TruthReason::kNotGround);
  const GroundTruthTraversability small = label(mesh, robot(0.3, 20, 0.2, 0.5));
  EXPECT_EQ(reasonAt(small, {1, 2, 0}), TruthReason::kTraversable);
}

TEST(GroundTruthTraversability, FloorNextToWallWithinFootprintIsNotTraversable) {
  LabeledMesh mesh;
  addFloor(mesh, 0, 2, 0, 4, 0, SurfaceLabel::kSidewalk);
  addQuad(mesh, {2, 0, 0}, {2, 4, 0}, {2, 4, 2}, {2, 0, 2}, SurfaceLabel::kWall);  // faces -x
  const GroundTruthTraversability wide = label(mesh, robot(0.3, 20, 0.2, 1.0));
  EXPECT_EQ(reasonAt(wide, {1.85, 2.05, 0}), TruthReason::kStepInFootprint);
  EXPECT_EQ(reasonAt(wide, {1.5, 2.05, 0}), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(wide, {2, 2.05, 1}), TruthReason::kNotGround);
  const GroundTruthTraversability narrow = label(mesh, robot(0.05, 20, 0.2, 1.0));
  EXPECT_EQ(reasonAt(narrow, {1.7, 2.05, 0}), TruthReason::kTraversable);
}

TEST(GroundTruthTraversability, RectangleFitsAlongACorridorWhereItsCircumscribedDiscDoesNot) {
  // A 1.2 m wide corridor along y between walls at x = 0 and x = 1.2.
  LabeledMesh mesh;
  addFloor(mesh, 0, 1.2, -3, 3, 0, SurfaceLabel::kRoad);
  addQuad(mesh, {0, 3, 0}, {0, -3, 0}, {0, -3, 2}, {0, 3, 2}, SurfaceLabel::kWall);      // faces +x
  addQuad(mesh, {1.2, -3, 0}, {1.2, 3, 0}, {1.2, 3, 2}, {1.2, -3, 2}, SurfaceLabel::kWall);  // faces -x
  RobotLimits narrow = robot(0, 20, 0.2, 1.0);
  narrow.footprint_length_m = 2.0;
  narrow.footprint_width_m = 0.8;
  narrow.footprint_radius_m = 0.5 * std::hypot(2.0, 0.8);
  const Eigen::Vector3d middle(0.6, 0.05, 0);
  EXPECT_EQ(reasonAt(label(mesh, narrow), middle), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(label(mesh, robot(narrow.footprint_radius_m, 20, 0.2, 1.0)), middle),
            TruthReason::kStepInFootprint);
  RobotLimits wide = narrow;
  wide.footprint_width_m = 1.4;
  wide.footprint_radius_m = 0.5 * std::hypot(2.0, 1.4);
  EXPECT_EQ(reasonAt(label(mesh, wide), middle), TruthReason::kStepInFootprint);
}

TEST(GroundTruthTraversability, RampOf8DegreesNeedsMaxSlopeAbove8) {
  LabeledMesh mesh;
  const double rise = 4 * std::tan(8 * M_PI / 180);
  addQuad(mesh, {0, 0, 0}, {4, 0, rise}, {4, 2, rise}, {0, 2, 0}, SurfaceLabel::kRamp);
  ASSERT_NEAR(mesh.slope_deg.front(), 8.0, 1e-4);
  const Eigen::Vector3d middle(2.05, 1, 2.05 * rise / 4);
  EXPECT_EQ(reasonAt(label(mesh, robot(0.3, 20, 0.2, 1.0)), middle), TruthReason::kTraversable);
  EXPECT_EQ(reasonAt(label(mesh, robot(0.3, 5, 0.2, 1.0)), middle), TruthReason::kTooSteep);
}

TEST(GroundTruthTraversability, HeightsAreMeasuredFromTheSlopedPlaneTheRobotStandsOn) {
  // A uniform 8 degree slope: over a 2.5 m footprint radius it rises 0.35 m above the centre's
  // level, but nothing rises above the plane the robot stands on.
  LabeledMesh mesh;
  const double rise = 12 * std::tan(8 * M_PI / 180);
  addQuad(mesh, {0, 0, 0}, {12, 0, rise}, {12, 6, rise}, {0, 6, 0}, SurfaceLabel::kRamp);
  const Eigen::Vector3d middle(6.05, 3.05, 6.05 * rise / 12);
  EXPECT_EQ(reasonAt(label(mesh, robot(2.5, 20, 0.1, 1.0)), middle), TruthReason::kTraversable);
}

TEST(GroundTruthTraversability, ObstacleTopIsNotGroundAndOnlyCandidatesAreRefined) {
  LabeledMesh mesh;
  addFloor(mesh, 0, 3, 0, 3, 0, SurfaceLabel::kObstacle);
  addFloor(mesh, 3, 6, 0, 3, 0, SurfaceLabel::kRoad);
  const GroundTruthTraversability truth = label(mesh, robot(0.3, 20, 0.2, 1.0));
  EXPECT_EQ(reasonAt(truth, {1, 1, 0}), TruthReason::kNotGround);
  EXPECT_EQ(reasonAt(truth, {4.5, 1.5, 0}), TruthReason::kTraversable);
  std::size_t obstacle_faces = 0;
  for (const SurfaceLabel l : truth.mesh.labels) obstacle_faces += l == SurfaceLabel::kObstacle;
  EXPECT_EQ(obstacle_faces, 2u);                        // kept whole
  EXPECT_GT(truth.mesh.mesh.faces.size(), 100u);        // the road split to 0.25 m edges
  const auto areas = truth.areaByReason();
  EXPECT_NEAR(areas[static_cast<std::size_t>(TruthReason::kNotGround)], 9.0, 1e-9);
  EXPECT_NEAR(areas[static_cast<std::size_t>(TruthReason::kTraversable)], 9.0, 1e-9);
  EXPECT_TRUE(isGroundLabel(SurfaceLabel::kVegetation));
  EXPECT_FALSE(isGroundLabel(SurfaceLabel::kCeiling));
}

TEST(GroundTruthTraversability, UpIsEstimatedFromLevelFaces) {
  LabeledMesh mesh = curbScene();
  EXPECT_LT((estimateUpFromSlopes(mesh) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  LabeledMesh walls;
  addQuad(walls, {2, 0, 0}, {2, 4, 0}, {2, 4, 2}, {2, 0, 2}, SurfaceLabel::kWall);
  EXPECT_THROW(estimateUpFromSlopes(walls), std::invalid_argument);
}

TEST(MeshRefinement, PiecesCoverEachFaceWithItsWinding) {
  LabeledMesh mesh;
  addFloor(mesh, 0, 2, 0, 1, 0, SurfaceLabel::kRoad);
  const RefinedMesh refined = refineMesh(mesh.mesh, 0.3);
  double area = 0;
  for (std::size_t f = 0; f < refined.mesh.faces.size(); ++f) {
    area += faceArea(refined.mesh, f);
    const auto& face = refined.mesh.faces[f];
    const Eigen::Vector3d& a = refined.mesh.vertices[face[0]];
    const Eigen::Vector3d n = (refined.mesh.vertices[face[1]] - a).cross(refined.mesh.vertices[face[2]] - a);
    EXPECT_GT(n.z(), 0);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE((refined.mesh.vertices[face[(k + 1) % 3]] - refined.mesh.vertices[face[k]]).norm(), 0.3 + 1e-12);
    }
  }
  EXPECT_NEAR(area, 2.0, 1e-12);
  EXPECT_EQ(refineMesh(mesh.mesh, 0).mesh.faces.size(), 2u);
}

}  // namespace
}  // namespace terramesh::evaluation
