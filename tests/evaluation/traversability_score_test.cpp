// The scorer against hand-made truths and maps with known answers.
#include "evaluation/traversability_score.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "evaluation/mesh_refinement.h"
#include "evaluation/road_under_path.h"
#include "labeled_mesh_builder.h"

namespace terramesh::evaluation {
namespace {

using datasets::LabeledMesh;
using datasets::SurfaceLabel;
using traversability::FaceClass;
using traversability::LayeredMesh;

/// Truth: level floor z = 0 over [0, 4] x [0, 4]; road (traversable) for x < 2, obstacle tops
/// (not traversable) for x > 2: 8 m^2 each.
GroundTruthTraversability halfRoadTruth() {
  LabeledMesh mesh;
  test::addFloor(mesh, 0, 2, 0, 4, 0, SurfaceLabel::kRoad);
  test::addFloor(mesh, 2, 4, 0, 4, 0, SurfaceLabel::kObstacle);
  RobotLimits robot;
  return labelTraversability(mesh, robot, Eigen::Vector3d::UnitZ(), GroundTruthConfig{});
}

/// A map: unit squares over [0, 4] x [0, 4] at height z, each face classed by `classify(x, y)`
/// of its centroid.
LayeredMesh gridMap(double z, const std::function<FaceClass(double, double)>& classify) {
  LabeledMesh squares;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) test::addFloor(squares, i, i + 1, j, j + 1, z, SurfaceLabel::kRoad);
  }
  LayeredMesh map;
  map.mesh = squares.mesh;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    // The face's centroid lies strictly inside its unit square.
    const Eigen::Vector3d centre = faceCentroid(map.mesh, f);
    traversability::FaceLayers layers;
    layers.face_class = classify(centre.x(), centre.y());
    map.layers.push_back(layers);
  }
  return map;
}

FaceClass truthClass(double x, double /*y*/) { return x < 2 ? FaceClass::kFree : FaceClass::kLethal; }

TEST(TraversabilityScore, MapEqualToTruthScoresOne) {
  const GroundTruthTraversability truth = halfRoadTruth();
  const TraversabilityScore score = scoreTraversability(gridMap(0.1, truthClass), truth, ScoreConfig{});
  EXPECT_NEAR(score.true_positive_m2, 8.0, 1e-9);
  EXPECT_NEAR(score.true_negative_m2, 8.0, 1e-9);
  EXPECT_DOUBLE_EQ(score.precision, 1.0);
  EXPECT_DOUBLE_EQ(score.recall, 1.0);
  EXPECT_DOUBLE_EQ(score.f1, 1.0);
  EXPECT_DOUBLE_EQ(score.coverage, 1.0);
  EXPECT_NEAR(score.truth_traversable_m2, 8.0, 1e-9);
  EXPECT_DOUBLE_EQ(score.unknown_fraction, 0.0);
  EXPECT_NEAR(score.by_label[static_cast<std::size_t>(SurfaceLabel::kRoad)].free_m2, 8.0, 1e-9);
  EXPECT_NEAR(score.by_label[static_cast<std::size_t>(SurfaceLabel::kObstacle)].lethal_m2, 8.0, 1e-9);
}

TEST(TraversabilityScore, FlippedMapScoresZero) {
  const auto flipped = [](double x, double y) {
    return truthClass(x, y) == FaceClass::kFree ? FaceClass::kLethal : FaceClass::kFree;
  };
  const TraversabilityScore score = scoreTraversability(gridMap(0, flipped), halfRoadTruth(), ScoreConfig{});
  EXPECT_DOUBLE_EQ(score.precision, 0.0);
  EXPECT_DOUBLE_EQ(score.recall, 0.0);
  EXPECT_DOUBLE_EQ(score.f1, 0.0);
  EXPECT_NEAR(score.false_positive_m2, 8.0, 1e-9);
  EXPECT_NEAR(score.false_negative_m2, 8.0, 1e-9);
}

TEST(TraversabilityScore, KnownWrongRegionGivesExactPrecisionAndRecall) {
  // Wrong: [2, 3] x [0, 4] free (4 m^2 false positive) and [0, 1] x [0, 1] lethal (1 m^2 false
  // negative). TP = 7, FP = 4, FN = 1.
  const auto wrong = [](double x, double y) {
    if (x > 2 && x < 3) return FaceClass::kFree;
    if (x < 1 && y < 1) return FaceClass::kLethal;
    return truthClass(x, y);
  };
  const TraversabilityScore score = scoreTraversability(gridMap(-0.2, wrong), halfRoadTruth(), ScoreConfig{});
  EXPECT_NEAR(score.precision, 7.0 / 11.0, 1e-12);
  EXPECT_NEAR(score.recall, 7.0 / 8.0, 1e-12);
  EXPECT_NEAR(score.f1, 14.0 / 19.0, 1e-12);
  EXPECT_NEAR(score.true_negative_m2, 4.0, 1e-9);
  const auto road = static_cast<std::size_t>(SurfaceLabel::kRoad);
  const auto obstacle = static_cast<std::size_t>(SurfaceLabel::kObstacle);
  EXPECT_NEAR(score.by_label_and_truth[road][1].lethal_m2, 1.0, 1e-9);
  EXPECT_NEAR(score.by_label_and_truth[road][1].free_m2, 7.0, 1e-9);
  EXPECT_NEAR(score.by_label_and_truth[obstacle][0].free_m2, 4.0, 1e-9);
  EXPECT_NEAR(score.by_label_and_truth[road][0].total(), 0.0, 1e-12);
  // Groups: 1 for the faces of the squares with x in [2, 3], 0 elsewhere.
  const LayeredMesh map = gridMap(-0.2, wrong);
  std::vector<std::uint8_t> groups;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    const double x = faceCentroid(map.mesh, f).x();
    groups.push_back(x > 2 && x < 3 ? 1 : 0);
  }
  const TraversabilityScore grouped = scoreTraversability(map, halfRoadTruth(), ScoreConfig{}, groups);
  ASSERT_EQ(grouped.by_group.size(), 2u);
  EXPECT_NEAR(grouped.by_group[1][0].free_m2, 4.0, 1e-9);
  EXPECT_NEAR(grouped.by_group[1][1].total(), 0.0, 1e-12);
  EXPECT_NEAR(grouped.by_group[0][1].lethal_m2, 1.0, 1e-9);
  EXPECT_THROW(scoreTraversability(map, halfRoadTruth(), ScoreConfig{}, {1, 0}), std::invalid_argument);
  // Whole faces at their centroids give the same answer here (faces do not straddle x = 2).
  ScoreConfig whole;
  whole.sample_edge_m = 0;
  EXPECT_NEAR(scoreTraversability(gridMap(-0.2, wrong), halfRoadTruth(), whole).f1, 14.0 / 19.0, 1e-12);
}

TEST(TraversabilityScore, FacesFartherThanHalfAMetreAreIgnored) {
  const GroundTruthTraversability truth = halfRoadTruth();
  LayeredMesh map = gridMap(0, truthClass);
  // A wrong free sheet 0.8 m above the truth: not scored.
  LayeredMesh far = gridMap(0.8, [](double, double) { return FaceClass::kFree; });
  const auto offset = static_cast<std::uint32_t>(map.mesh.vertices.size());
  map.mesh.vertices.insert(map.mesh.vertices.end(), far.mesh.vertices.begin(), far.mesh.vertices.end());
  for (auto face : far.mesh.faces) {
    for (auto& v : face) v += offset;
    map.mesh.faces.push_back(face);
  }
  map.layers.insert(map.layers.end(), far.layers.begin(), far.layers.end());
  const TraversabilityScore score = scoreTraversability(map, truth, ScoreConfig{});
  EXPECT_DOUBLE_EQ(score.f1, 1.0);
  EXPECT_NEAR(score.ignored_far_m2, 16.0, 1e-9);
  EXPECT_NEAR(score.scored_m2, 16.0, 1e-9);
  // With a 1 m reach the sheet is scored and its obstacle half becomes false positives.
  ScoreConfig wide;
  wide.max_distance_m = 1.0;
  EXPECT_NEAR(scoreTraversability(map, truth, wide).false_positive_m2, 8.0, 1e-9);
}

TEST(TraversabilityScore, UnknownFacesAreExcludedFromPrecisionButLowerCoverage) {
  const GroundTruthTraversability truth = halfRoadTruth();
  // The left half of the road (x < 1) is unknown.
  const auto partly = [](double x, double y) { return x < 1 ? FaceClass::kUnknown : truthClass(x, y); };
  const TraversabilityScore score = scoreTraversability(gridMap(0, partly), truth, ScoreConfig{});
  EXPECT_DOUBLE_EQ(score.precision, 1.0);
  EXPECT_DOUBLE_EQ(score.recall, 1.0);
  EXPECT_NEAR(score.unknown_m2, 4.0, 1e-9);
  EXPECT_NEAR(score.unknown_fraction, 0.25, 1e-12);
  // Truth faces with x < 0.5 have no known face within 0.5 m: about 2 of the 8 m^2 (to within
  // the truth's 0.25 m faces).
  EXPECT_GT(score.coverage, 0.70);
  EXPECT_LT(score.coverage, 0.80);
  EXPECT_NEAR(score.by_label[static_cast<std::size_t>(SurfaceLabel::kRoad)].unknown_m2, 4.0, 1e-9);
}

TEST(RoadUnderPath, FractionsOfTheRoadUnderTheCamera) {
  // Map in units of 0.5 m: free for |y| < 1 m, lethal beyond, at 1.65 m below a camera path
  // along x (y = 0); a second sheet 0.9 m below the camera is not the road.
  traversability::LayeredMesh map;
  map.metres_per_unit = 0.5;
  LabeledMesh sheets;
  for (double y0 = -3; y0 < 3; y0 += 0.5) test::addFloor(sheets, 0, 20, y0, y0 + 0.5, -1.65, SurfaceLabel::kRoad);
  test::addFloor(sheets, 0, 20, -3, 3, -0.9, SurfaceLabel::kRoad);
  for (auto& v : sheets.mesh.vertices) v /= map.metres_per_unit;
  map.mesh = sheets.mesh;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    const double y = map.mesh.vertices[map.mesh.faces[f][0]].y() * map.metres_per_unit;
    traversability::FaceLayers layers;
    const bool upper = f >= map.mesh.faces.size() - 2;
    layers.face_class = upper ? FaceClass::kUnknown : (y >= -1 && y < 1 ? FaceClass::kFree : FaceClass::kLethal);
    // The lethal faces say why: too steep on one side, no heading fits on the other.
    if (layers.face_class == FaceClass::kLethal) {
      layers.reasons = y < 0 ? traversability::reason::kTooSteep : traversability::reason::kNoHeadingFits;
    }
    map.layers.push_back(layers);
  }
  const std::vector<Eigen::Vector3d> path = {{5 / 0.5, 0, 0}, {10 / 0.5, 0, 0}, {15 / 0.5, 0, 0}};
  const RoadUnderPath road = roadUnderPath(map, path, Eigen::Vector3d::UnitZ(), RoadUnderPathConfig{});
  // 10 m of path, 1.5 m each side; the path's ends add half-discs of radius 1.5 m.
  EXPECT_NEAR(road.path_length_m, 10.0, 1e-9);
  EXPECT_NEAR(road.areas.unknown_m2, 0.0, 1e-12);
  EXPECT_GT(road.free_fraction, 0.6);
  EXPECT_LT(road.free_fraction, 0.75);
  EXPECT_NEAR(road.free_fraction + road.lethal_fraction, 1.0, 1e-12);
  // Each lethal side is half the lethal area, and no other reason appears.
  const auto bit = [](std::uint16_t reason) { return static_cast<std::size_t>(std::log2(reason)); };
  EXPECT_NEAR(road.reason_fraction[bit(traversability::reason::kTooSteep)], 0.5 * road.lethal_fraction, 1e-9);
  EXPECT_NEAR(road.reason_fraction[bit(traversability::reason::kNoHeadingFits)], 0.5 * road.lethal_fraction, 1e-9);
  double reasons = 0;
  for (double fraction : road.reason_fraction) reasons += fraction;
  EXPECT_NEAR(reasons, road.lethal_fraction, 1e-9);
  RoadUnderPathConfig whole;
  whole.sample_edge_m = 0;
  EXPECT_THROW(roadUnderPath(map, {path[0]}, Eigen::Vector3d::UnitZ(), whole), std::invalid_argument);
}

TEST(RoadUnderPath, TheTruthJudgesTheStripForTheRobot) {
  // Truth: road over [0, 4] x [0, 4]; for x > 2 a ceiling 0.15 m over it (under the step, so only
  // the clearance rule sees it): ground the robot does not fit on. Map on it: free for x < 2
  // except the uncertain square [1, 2] x [1, 2], lethal beyond. The path runs along x = 2 from
  // y = 1 to 3, 1.65 m up; its strip (1 m each side, half-discs at the ends) is half where the
  // robot fits.
  LabeledMesh low_ceiling;
  test::addFloor(low_ceiling, 0, 4, 0, 4, 0, SurfaceLabel::kRoad);
  test::addFloor(low_ceiling, 2, 4, 0, 4, 0.15, SurfaceLabel::kCeiling);
  const GroundTruthTraversability truth =
      labelTraversability(low_ceiling, RobotLimits{}, Eigen::Vector3d::UnitZ(), GroundTruthConfig{});
  const LayeredMesh map = gridMap(0.0, [](double x, double y) {
    if (x >= 2) return FaceClass::kLethal;
    return x > 1 && y > 1 && y < 2 ? FaceClass::kUncertain : FaceClass::kFree;
  });
  const std::vector<Eigen::Vector3d> path = {{2, 1, 1.65}, {2, 3, 1.65}};
  RoadUnderPathConfig config;
  config.lateral_m = 1.0;
  const RoadUnderPath road = roadUnderPath(map, path, Eigen::Vector3d::UnitZ(), config, &truth);
  const double half_strip_m2 = 2.0 + 0.5 * M_PI;
  EXPECT_NEAR(road.truth_fits_fraction, 0.5, 0.03);
  EXPECT_NEAR(road.where_truth_fits.total(), half_strip_m2, 0.1);
  EXPECT_NEAR(road.where_truth_fits.uncertain_m2, 1.0, 1e-9);
  EXPECT_NEAR(road.where_truth_fits.lethal_m2, 0.0, 1e-12);
  EXPECT_NEAR(road.free_where_truth_fits_fraction, (half_strip_m2 - 1.0) / half_strip_m2, 0.03);
  // On a flat map the columns agree with the pieces.
  EXPECT_NEAR(road.underfoot_free_where_truth_fits_fraction, road.free_where_truth_fits_fraction, 0.02);
  EXPECT_NEAR(road.underfoot_free_fraction, road.free_fraction, 0.02);
  // The whole strip's free share also counts the lethal half where the robot does not fit.
  EXPECT_NEAR(road.free_fraction, 0.5 * road.free_where_truth_fits_fraction, 0.03);
  // Where the truth has no ground (obstacle tops for x > 2), the robot drove over what the truth
  // does not rule out: the whole strip stays in.
  const GroundTruthTraversability obstacle = halfRoadTruth();
  const RoadUnderPath on_obstacle = roadUnderPath(map, path, Eigen::Vector3d::UnitZ(), config, &obstacle);
  EXPECT_NEAR(on_obstacle.truth_fits_fraction, 1.0, 1e-12);
  EXPECT_NEAR(on_obstacle.free_where_truth_fits_fraction, on_obstacle.free_fraction, 1e-12);
  // Without a truth there is no judgement.
  const RoadUnderPath alone = roadUnderPath(map, path, Eigen::Vector3d::UnitZ(), config);
  EXPECT_TRUE(std::isnan(alone.truth_fits_fraction));
  EXPECT_TRUE(std::isnan(alone.free_where_truth_fits_fraction));
  EXPECT_NEAR(alone.free_fraction, road.free_fraction, 1e-12);
}

TEST(RoadUnderPath, UnderfootColumnsWeighWhatCoversTheGround) {
  // A free floor at z = 0 over [0, 8] x [-2, 2] under a path along y = 0 from x = 1 to x = 9,
  // 1.65 m up; its strip (1 m each side, half-discs at the ends) runs past the floor's end into a
  // hole. Under the floor within the band: a steep uncertain membrane (hidden by the floor). Over
  // it: a 0.3 m deck underside facing down (not the road), and an uncertain wall 0.4 m tall whose
  // foot is 0.3 m wide across the strip.
  LabeledMesh sheets;
  test::addFloor(sheets, 0, 8, -2, 2, 0, SurfaceLabel::kRoad);
  const std::size_t floor_faces = sheets.mesh.faces.size();
  test::addQuad(sheets, {2, -0.5, -0.05}, {6, -0.5, -0.05}, {6, 0.3, -0.45}, {2, 0.3, -0.45}, SurfaceLabel::kRoad);
  const std::size_t membrane_faces = sheets.mesh.faces.size();
  test::addQuad(sheets, {6, -1, 0.3}, {6, 1, 0.3}, {7, 1, 0.3}, {7, -1, 0.3}, SurfaceLabel::kCeiling);
  const std::size_t deck_faces = sheets.mesh.faces.size();
  test::addQuad(sheets, {3, 0.3, 0}, {4, 0.3, 0}, {4, 0.6, 0.4}, {3, 0.6, 0.4}, SurfaceLabel::kWall);
  LayeredMesh map;
  map.mesh = sheets.mesh;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    traversability::FaceLayers layers;
    layers.face_class = f < floor_faces                         ? FaceClass::kFree
                        : f < membrane_faces || f >= deck_faces ? FaceClass::kUncertain
                                                                : FaceClass::kLethal;
    map.layers.push_back(layers);
  }
  const std::vector<Eigen::Vector3d> path = {{1, 0, 1.65}, {9, 0, 1.65}};
  RoadUnderPathConfig config;
  config.lateral_m = 1.0;
  const RoadUnderPath road = roadUnderPath(map, path, Eigen::Vector3d::UnitZ(), config);
  const double strip_m2 = 16.0 + M_PI, hole_m2 = 2.0 + 0.5 * M_PI, wall_m2 = 0.3;
  const double total_m2 = road.underfoot.total() + road.underfoot_none_m2;
  EXPECT_NEAR(total_m2, strip_m2, 0.15);
  EXPECT_NEAR(road.underfoot_none_m2, hole_m2, 0.15);
  EXPECT_NEAR(road.underfoot.uncertain_m2, wall_m2, 0.05);
  EXPECT_NEAR(road.underfoot.lethal_m2, 0.0, 1e-12);
  EXPECT_NEAR(road.underfoot_free_fraction, (strip_m2 - hole_m2 - wall_m2) / strip_m2, 0.01);
  EXPECT_NEAR(road.underfoot_none_fraction, hole_m2 / strip_m2, 0.01);
  EXPECT_NEAR(road.underfoot_free_fraction + road.underfoot_uncertain_fraction + road.underfoot_none_fraction, 1.0,
              1e-9);
  // The pieces count the hidden membrane and the wall by their own area (3.58 + 0.5 m^2).
  EXPECT_NEAR(road.areas.uncertain_m2, 4.0 * std::hypot(0.8, 0.4) + 0.5, 0.2);
  EXPECT_TRUE(std::isnan(road.underfoot_free_where_truth_fits_fraction));
  config.column_spacing_m = 0;
  EXPECT_THROW(roadUnderPath(map, path, Eigen::Vector3d::UnitZ(), config), std::invalid_argument);
}

TEST(RoadUnderPath, SurfaceOnTheStripsEdgeIsNotUnderIt) {
  // A free floor under a path along y = 0, with uncertain geometry standing on the strip's edges
  // (y = +-0.25, the robot's half width), where pieces' centroids and columns of the 0.1 m grid
  // lie: vertical walls, and slopes rising outwards from the edges (at a column on the edge, as
  // high as the floor; listed first, so they win that tie). None of it lies over the strip's
  // ground, whichever way "up" leans in the plane of the walls (the cameras' mean up on a ramp).
  LabeledMesh sheets;
  for (const double side : {-1.0, 1.0}) {
    const double y = 0.25 * side, out = 0.75 * side;
    test::addQuad(sheets, {0, y, 0}, {8, y, 0}, {8, out, 1}, {0, out, 1}, SurfaceLabel::kWall);
    test::addQuad(sheets, {0, y, 0}, {8, y, 0}, {8, y, 1}, {0, y, 1}, SurfaceLabel::kWall);
  }
  const std::size_t wall_faces = sheets.mesh.faces.size();
  test::addFloor(sheets, 0, 8, -0.25, 0.25, 0, SurfaceLabel::kRoad);
  LayeredMesh map;
  map.mesh = sheets.mesh;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    traversability::FaceLayers layers;
    layers.face_class = f < wall_faces ? FaceClass::kUncertain : FaceClass::kFree;
    map.layers.push_back(layers);
  }
  const std::vector<Eigen::Vector3d> path = {{1, 0, 1.65}, {7, 0, 1.65}};
  RoadUnderPathConfig config;
  config.lateral_m = 0.25;
  for (const double lean : {0.0, -0.012066, 0.03}) {
    SCOPED_TRACE(lean);
    const RoadUnderPath road = roadUnderPath(map, path, Eigen::Vector3d(lean, 0, 1).normalized(), config);
    // The strip: 6 m by 0.5 m, and half-discs at the ends (columns: 4 of the grid's across it).
    EXPECT_NEAR(road.underfoot.total() + road.underfoot_none_m2, 6.0 * 0.4 + 0.16, 0.05);
    EXPECT_NEAR(road.underfoot_free_fraction, 1.0, 1e-12);
    EXPECT_NEAR(road.areas.total(), 6.0 * 0.5 + M_PI * 0.25 * 0.25, 0.01);
    EXPECT_NEAR(road.free_fraction, 1.0, 1e-12);
  }
  // A hair wider, the strip takes them in.
  config.lateral_m = 0.26;
  const RoadUnderPath wider = roadUnderPath(map, path, Eigen::Vector3d::UnitZ(), config);
  EXPECT_LT(wider.underfoot_free_fraction, 0.9);
  EXPECT_LT(wider.free_fraction, 0.9);
}

TEST(GroundUnderPath, MeasuredGroundUnderThePathTakesTheMapFaceOverIt) {
  // Map in units of 0.5 m, 1.65 m below a camera path along x from 5 to 15 m: free for y < 0,
  // lethal for y >= 0, with a hole at 10 <= x < 11; measured ground 0.05 m under it every 0.1 m
  // over the whole sheet, plus points too far to the side, too high (a car's roof) and too low.
  traversability::LayeredMesh map;
  map.metres_per_unit = 0.5;
  LabeledMesh sheet;
  for (double x0 = 0; x0 < 20; x0 += 1) {
    if (x0 == 10) continue;
    test::addFloor(sheet, x0, x0 + 1, -3, 0, -1.65, SurfaceLabel::kRoad);
    test::addFloor(sheet, x0, x0 + 1, 0, 3, -1.65, SurfaceLabel::kRoad);
  }
  for (auto& v : sheet.mesh.vertices) v /= map.metres_per_unit;
  map.mesh = sheet.mesh;
  for (const auto& face : map.mesh.faces) {
    traversability::FaceLayers layers;
    const double y = (map.mesh.vertices[face[0]] + map.mesh.vertices[face[1]] + map.mesh.vertices[face[2]]).y() / 3;
    layers.face_class = y < 0 ? FaceClass::kFree : FaceClass::kLethal;
    layers.reasons = y < 0 ? 0 : traversability::reason::kLowClearance;
    map.layers.push_back(layers);
  }
  std::vector<Eigen::Vector3d> ground;
  for (double x = 0.05; x < 20; x += 0.1) {
    for (double y = -2.95; y < 3; y += 0.1) ground.emplace_back(x, y, -1.70);
  }
  ground.emplace_back(8, 2.5, -1.70);  // beyond lateral_m
  ground.emplace_back(8, 0.5, -0.6);   // a roof beside the road: out of the height window
  ground.emplace_back(8, -0.5, -2.6);  // below it
  for (Eigen::Vector3d& p : ground) p /= map.metres_per_unit;
  const std::vector<Eigen::Vector3d> path = {{5 / 0.5, 0, 0}, {15 / 0.5, 0, 0}};
  RoadUnderPathConfig config;
  config.lateral_m = 1.0;
  const GroundUnderPath g = groundUnderPath(map, path, Eigen::Vector3d::UnitZ(), config, ground);
  // The band: 10 m x 2 m plus two half-discs of radius 1 m, 0.1 m grid: about 2314 points.
  EXPECT_GT(g.points, 2250u);
  EXPECT_LT(g.points, 2380u);
  EXPECT_EQ(g.points, g.free + g.lethal + g.unknown + g.uncertain + g.missing);
  EXPECT_EQ(g.unknown + g.uncertain, 0u);
  // The hole (1 m of the 10 m path, 2 m wide) has no surface over its points.
  EXPECT_NEAR(static_cast<double>(g.missing), 200.0, 25.0);
  EXPECT_NEAR(g.free_fraction, g.lethal_fraction, 0.02);
  EXPECT_NEAR(g.free_fraction + g.lethal_fraction + g.missing_fraction, 1.0, 1e-12);
  EXPECT_NEAR(g.reason_fraction[2], g.lethal_fraction, 1e-12) << "bit 2: low clearance, every lethal point";
  EXPECT_EQ(g.reason_fraction[0], 0.0);
  EXPECT_NEAR(g.free_height_median_m, 0.05, 1e-9);
  EXPECT_NEAR(g.height_median_m, 0.05, 1e-9);
  EXPECT_NEAR(g.covered_path_m, 10.0, 0.6);
  // Ground only beside the first half of the path covers only that half.
  std::vector<Eigen::Vector3d> first_half;
  for (const Eigen::Vector3d& p : ground) {
    if (p.x() * map.metres_per_unit < 9.8) first_half.push_back(p);
  }
  EXPECT_NEAR(groundUnderPath(map, path, Eigen::Vector3d::UnitZ(), config, first_half).covered_path_m, 5.0, 0.6);
  ground.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  EXPECT_THROW(groundUnderPath(map, path, Eigen::Vector3d::UnitZ(), config, ground), std::invalid_argument);
}

TEST(RoadUnderPath, UpFromCameraRotations) {
  // A KITTI camera looking along +x of a z-up world: x_C = -y_W, y_C = -z_W, z_C = +x_W.
  Eigen::Matrix3d R;
  R.col(0) = -Eigen::Vector3d::UnitY();
  R.col(1) = -Eigen::Vector3d::UnitZ();
  R.col(2) = Eigen::Vector3d::UnitX();
  EXPECT_LT((upFromCameraRotations({Eigen::Quaterniond(R)}) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_THROW(upFromCameraRotations({}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::evaluation
