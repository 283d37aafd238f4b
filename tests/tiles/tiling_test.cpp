// The tiling library: the plan's grid and owners, each tile's input, owned parts that partition a
// map, the plan and record files, and class agreement against analytic expectations.
#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <set>

#include "common/input_error.h"
#include "free_floor.h"
#include "test_support/temp_dir.h"
#include "test_support/traversability_scenes.h"
#include "tiling/tile_files.h"
#include "tiling/tile_input.h"
#include "tiling/tile_map.h"
#include "tiling/tile_plan.h"

namespace terramesh::tiling {
namespace {

using mesher::Keyframe;
using mesher::KeyframeId;
using mesher::PointId;
using mesher::PointObservation;

Keyframe keyframeAt(std::uint64_t id, double x, const std::vector<std::pair<std::uint64_t, Eigen::Vector3d>>& seen) {
  Keyframe keyframe;
  keyframe.id = KeyframeId{id};
  keyframe.position_W_C = Eigen::Vector3d(x, 0, 1.5);
  for (const auto& [point, position] : seen) keyframe.observations.push_back(PointObservation{PointId{point}, position});
  return keyframe;
}

/// A straight drive along x: keyframes at x = 0, 10, ..., 100, each seeing a point 15 m ahead of
/// it and the point beside it, at y = +-3.
datasets::SlamStream straightStream() {
  datasets::SlamStream stream;
  for (int k = 0; k <= 10; ++k) {
    const double x = 10.0 * k;
    stream.events.push_back(keyframeAt(k, x, {{100 + k, Eigen::Vector3d(x, 3, 0)}, {200 + k, Eigen::Vector3d(x + 15, -3, 0)}}));
  }
  return stream;
}

TilePlan straightPlan(double tile_m = 40, double overlap_m = 5, double guard_m = 0) {
  TilingConfig config;
  config.tile_m = tile_m;
  config.overlap_m = overlap_m;
  config.guard_m = guard_m;
  return planTiles(straightStream(), Eigen::Vector3d::UnitZ(), 1.0, config);
}

TEST(TilingConfig, ValidateListsEveryProblem) {
  TilingConfig config;
  EXPECT_NO_THROW(config.validate());
  config.tile_m = 0;
  config.overlap_m = -1;
  config.guard_m = std::numeric_limits<double>::quiet_NaN();
  try {
    config.validate();
    FAIL() << "no throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("tile_m"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("overlap_m"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("guard_m"), std::string::npos);
  }
}

TEST(PlanRect, SegmentAndDistance) {
  const PlanRect rect{0, 0, 10, 10};
  EXPECT_TRUE(rect.meetsSegment({-5, 5}, {15, 5}));    // through
  EXPECT_TRUE(rect.meetsSegment({5, 5}, {50, 50}));    // from inside
  EXPECT_FALSE(rect.meetsSegment({-5, -5}, {-1, 20})); // beside
  EXPECT_FALSE(rect.meetsSegment({-5, 12}, {12, 20}));  // above the corner
  EXPECT_DOUBLE_EQ(rect.distanceM({13, 14}), 5.0);
  EXPECT_DOUBLE_EQ(rect.distanceM({3, 4}), 0.0);
  EXPECT_TRUE(rect.intersection(PlanRect{10, 0, 20, 10}).empty());
}

TEST(PlanTiles, GridFromTheExtentCornerAndOneOwnerEverywhere) {
  const TilePlan plan = straightPlan();
  // Extent x from 0 to 115 (the last point), y from -3 to 3: 3 columns of 40 m, one row.
  ASSERT_EQ(plan.tiles.size(), 3u);
  for (std::size_t i = 0; i < plan.tiles.size(); ++i) {
    EXPECT_EQ(plan.tiles[i].index, i);
    EXPECT_EQ(plan.tiles[i].name, tileName(i));
    EXPECT_DOUBLE_EQ(plan.tiles[i].bounds.min_x_m, 40.0 * static_cast<double>(i));
    EXPECT_DOUBLE_EQ(plan.tiles[i].bounds.min_y_m, -3.0);
  }
  for (double x = -20; x < 140; x += 0.7) {
    for (double y = -30; y < 30; y += 1.3) {
      const std::size_t owner = plan.ownerOf({x, y});
      const bool inside = plan.tiles[owner].bounds.contains({x, y});
      std::size_t holders = 0;
      for (const TileSpec& tile : plan.tiles) holders += tile.bounds.contains({x, y}) ? 1 : 0;
      EXPECT_EQ(inside, holders == 1) << x << ", " << y;
      for (const TileSpec& tile : plan.tiles) {
        EXPECT_LE(plan.tiles[owner].bounds.distanceM({x, y}), tile.bounds.distanceM({x, y}));
      }
    }
  }
}

TEST(PlanTiles, TheSeamIsTheBandWithinHalfTheOverlapOfTheSharedEdge) {
  const TilePlan plan = straightPlan();  // 40 m squares from (0, -3), overlap 5 m
  const PlanRect seam = plan.seamBounds(0, 1);
  EXPECT_DOUBLE_EQ(seam.min_x_m, 37.5);
  EXPECT_DOUBLE_EQ(seam.max_x_m, 42.5);
  EXPECT_DOUBLE_EQ(seam.min_y_m, -5.5);
  EXPECT_DOUBLE_EQ(seam.max_y_m, 39.5);  // square tiles: y up to 37
  EXPECT_TRUE(plan.seamBounds(0, 2).empty());  // 40 m apart: no seam
}

TEST(SelectTileInput, PointsInTheInputBoundsAndRaysCrossingThem) {
  const datasets::SlamStream stream = straightStream();
  const TilePlan plan = straightPlan();
  const TileInput input = selectTileInput(stream, plan, 1);  // x in [40, 80), input [35, 85)
  std::set<std::uint64_t> keyframes, points;
  for (const datasets::StreamEvent& event : input.stream.events) {
    const auto& keyframe = std::get<Keyframe>(event);
    keyframes.insert(keyframe.id.value);
    for (const PointObservation& observation : keyframe.observations) {
      const double x = observation.position_W.x();
      const bool point_inside = x >= 35 && x < 85;
      const bool ray_crosses = keyframe.position_W_C.x() < 85 && x >= 35;
      EXPECT_TRUE(point_inside || ray_crosses) << observation.point.value;
      points.insert(observation.point.value);
    }
  }
  // Cameras at 40..80 (in), 30 (its point ahead at 45), 20 (its ray to 35 reaches the bounds).
  EXPECT_EQ(keyframes, (std::set<std::uint64_t>{2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(points.count(210), 0u);  // from x = 100 to 115: never over the tile
  EXPECT_EQ(points.count(108), 1u);
  EXPECT_EQ(input.keyframes, keyframes.size());
  EXPECT_EQ(input.points, points.size());
  EXPECT_THROW(selectTileInput(stream, plan, 3), std::out_of_range);
}

TEST(SelectTileInput, TheGuardWidensTheInputNotTheOverlap) {
  const datasets::SlamStream stream = straightStream();
  const TilePlan plan = straightPlan(40, 5, 10);  // tile 1: x in [40, 80), overlap [35, 85), input [25, 95)
  EXPECT_DOUBLE_EQ(plan.overlapBounds(1).min_x_m, 35);
  EXPECT_DOUBLE_EQ(plan.overlapBounds(1).max_x_m, 85);
  EXPECT_DOUBLE_EQ(plan.inputBounds(1).min_x_m, 25);
  EXPECT_DOUBLE_EQ(plan.inputBounds(1).max_x_m, 95);
  const TileInput input = selectTileInput(stream, plan, 1);
  std::set<std::uint64_t> keyframes;
  for (const datasets::StreamEvent& event : input.stream.events) keyframes.insert(std::get<Keyframe>(event).id.value);
  // Without the guard 2..8 (the test above); now the camera at 90 too, and the one at 10 (its
  // ray to 25 reaches the input).
  EXPECT_EQ(keyframes, (std::set<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
  // The seam stays within half the overlap of the border.
  EXPECT_DOUBLE_EQ(plan.seamBounds(0, 1).min_x_m, 37.5);
  EXPECT_DOUBLE_EQ(plan.seamBounds(0, 1).max_x_m, 42.5);
  EXPECT_EQ(plan.tiles[1].keyframes, keyframes.size());
}

TEST(SelectTileInput, EveryViewOfAPointItKeeps) {
  // Point 300 lies beyond tile 1's input [35, 85) at x = 88. Keyframe 6 (x = 60) sees it through
  // the input; keyframe 10 (x = 100) sees it from beyond, on a ray that never crosses the input.
  datasets::SlamStream stream = straightStream();
  const Eigen::Vector3d beyond(88, 0, 0);
  std::get<Keyframe>(stream.events[6]).observations.push_back(PointObservation{PointId{300}, beyond});
  std::get<Keyframe>(stream.events[10]).observations.push_back(PointObservation{PointId{300}, beyond});
  const TileInput input = selectTileInput(stream, straightPlan(), 1);
  std::size_t views = 0;
  for (const datasets::StreamEvent& event : input.stream.events) {
    const auto& keyframe = std::get<Keyframe>(event);
    for (const PointObservation& observation : keyframe.observations) {
      if (observation.point.value == 300) ++views;
      // Keyframe 10 brings that view alone: its own points lie beyond the input, off its rays.
      if (keyframe.id.value == 10) {
        EXPECT_EQ(observation.point.value, 300u);
      }
    }
  }
  // Both views, so the tile's mesher counts them (min_views) as the whole stream's does.
  EXPECT_EQ(views, 2u);
  EXPECT_EQ(input.keyframes, 8u);  // 2..8 as before, and 10
}

TEST(SelectTileInput, RemovalsFollowTheTile) {
  datasets::SlamStream stream = straightStream();
  stream.events.push_back(datasets::PointRemoval{{PointId{100}, PointId{110}}});
  stream.events.push_back(datasets::KeyframeRemoval{KeyframeId{10}});
  const TilePlan plan = straightPlan();
  const TileInput first = selectTileInput(stream, plan, 0);
  const auto& removal = std::get<datasets::PointRemoval>(first.stream.events.at(first.stream.events.size() - 1));
  ASSERT_EQ(removal.points.size(), 1u);
  EXPECT_EQ(removal.points.front().value, 100u);
  const TileInput last = selectTileInput(stream, plan, 2);
  EXPECT_TRUE(std::holds_alternative<datasets::KeyframeRemoval>(last.stream.events.back()));
}

/// A flat 30 x 10 m floor of free faces (1 m grid), up +z.
traversability::LayeredMesh flatMap() { return test_floor::freeFloor(0, 30); }

TEST(OwnedPart, PartsPartitionTheFacesByCentroid) {
  traversability::LayeredMesh map = flatMap();
  for (std::size_t f = 0; f < map.layers.size(); ++f) map.layers[f].rays = static_cast<std::uint32_t>(f);
  TilingConfig config;
  config.tile_m = 12;
  config.overlap_m = 2;
  datasets::SlamStream stream;
  stream.events.push_back(keyframeAt(0, 0, {{1, Eigen::Vector3d(0, 0, 0)}, {2, Eigen::Vector3d(30, 10, 0)}}));
  const TilePlan plan = planTiles(stream, Eigen::Vector3d::UnitZ(), 1.0, config);
  std::multiset<std::uint32_t> seen;
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) {
    const traversability::LayeredMesh owned = ownedPart(map, plan, t);
    ASSERT_EQ(owned.layers.size(), owned.mesh.faces.size());
    for (std::size_t f = 0; f < owned.mesh.faces.size(); ++f) {
      const auto& face = owned.mesh.faces[f];
      const Eigen::Vector3d centroid =
          (owned.mesh.vertices[face[0]] + owned.mesh.vertices[face[1]] + owned.mesh.vertices[face[2]]) / 3.0;
      EXPECT_EQ(plan.ownerOf(centroid.head<2>()), t);
      seen.insert(owned.layers[f].rays);  // the face's own layers came along
    }
  }
  EXPECT_EQ(seen.size(), map.layers.size());
  EXPECT_EQ(std::set<std::uint32_t>(seen.begin(), seen.end()).size(), map.layers.size());
}

TEST(AppendMap, JoinsAndRefusesAnotherFrame) {
  traversability::LayeredMesh joined;
  const traversability::LayeredMesh part = flatMap();
  appendMap(joined, part);
  appendMap(joined, part);
  EXPECT_EQ(joined.mesh.faces.size(), 2 * part.mesh.faces.size());
  EXPECT_EQ(joined.layers.size(), 2 * part.layers.size());
  EXPECT_EQ(joined.mesh.faces.back()[2], part.mesh.faces.back()[2] + part.mesh.vertices.size());
  traversability::LayeredMesh scaled = part;
  scaled.metres_per_unit = 2;
  EXPECT_THROW(appendMap(joined, scaled), std::invalid_argument);
}

TEST(ClassAgreement, AreaOfChangedClasses) {
  const traversability::LayeredMesh a = flatMap();
  traversability::LayeredMesh b = a;
  // Faces with centroid x < 6 (a fifth of the floor) become uncertain in b.
  for (std::size_t f = 0; f < b.mesh.faces.size(); ++f) {
    const auto& face = b.mesh.faces[f];
    if ((b.mesh.vertices[face[0]].x() + b.mesh.vertices[face[1]].x() + b.mesh.vertices[face[2]].x()) / 3 < 6) {
      b.layers[f].face_class = traversability::FaceClass::kUncertain;
    }
  }
  const traversability::LevelConfig levels;
  const ClassAgreement self = classAgreement(a, a, PlanRect{0, 0, 30, 10}, levels, 0.25);
  EXPECT_DOUBLE_EQ(self.fraction(), 1.0);
  EXPECT_NEAR(self.compared_m2, 300.0, 1e-9);
  const ClassAgreement changed = classAgreement(a, b, PlanRect{0, 0, 30, 10}, levels, 0.25);
  EXPECT_NEAR(changed.fraction(), 24.0 / 30.0, 1e-9);
  EXPECT_NEAR(changed.freeFraction(), 24.0 / 30.0, 1e-9);  // uncertain is not free
  EXPECT_DOUBLE_EQ(self.freeFraction(), 1.0);
  const ClassAgreement beside = classAgreement(a, b, PlanRect{10, 0, 30, 10}, levels, 0.25);
  EXPECT_DOUBLE_EQ(beside.fraction(), 1.0);
  EXPECT_NEAR(beside.compared_m2, 200.0, 1e-9);
  EXPECT_DOUBLE_EQ(self.only_a_m2, 0.0);
  // A map of the floor from x = 10 on: the 100 m^2 before it are a's alone, and nothing is b's alone.
  traversability::LayeredMesh part;
  part.mesh = test::heightFieldMesh(10, 30, 0, 10, 1.0, [](double, double) { return 0.0; });
  part.layers.assign(part.mesh.faces.size(), a.layers.front());
  const ClassAgreement missing = classAgreement(a, part, PlanRect{0, 0, 30, 10}, levels, 0.25);
  EXPECT_NEAR(missing.compared_m2, 200.0, 1e-9);
  EXPECT_NEAR(missing.only_a_m2, 100.0, 1e-9);
  EXPECT_DOUBLE_EQ(missing.fraction(), 1.0);
  EXPECT_DOUBLE_EQ(classAgreement(part, a, PlanRect{0, 0, 30, 10}, levels, 0.25).only_a_m2, 0.0);
  EXPECT_THROW(classAgreement(a, b, PlanRect{0, 0, 1, 1}, levels, 0), std::invalid_argument);
}

TEST(TileFiles, PlanRoundTripAndFieldErrors) {
  const test::TempDir dir;
  const TilePlan plan = straightPlan();
  writeTilePlan(dir / "plan.json", plan);
  const TilePlan read = readTilePlan(dir / "plan.json");
  ASSERT_EQ(read.tiles.size(), plan.tiles.size());
  EXPECT_EQ(read.tiles[1].bounds.max_x_m, plan.tiles[1].bounds.max_x_m);
  EXPECT_EQ(read.tiles[2].points, plan.tiles[2].points);
  EXPECT_EQ(read.extent.max_x_m, plan.extent.max_x_m);
  EXPECT_EQ(read.up_W, plan.up_W);
  EXPECT_EQ(read.config.overlap_m, plan.config.overlap_m);
  EXPECT_EQ(read.config.guard_m, plan.config.guard_m);
  // The same plan again writes the same bytes.
  writeTilePlan(dir / "again.json", read);
  std::ifstream first(dir / "plan.json"), second(dir / "again.json");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(first), {}), std::string(std::istreambuf_iterator<char>(second), {}));

  std::ifstream in(dir / "plan.json");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  // A name is "tile_" and three or more digits, and names one tile only (a frozen drive's tiles keep
  // the names of the order it reached them in, so tile_009 may stand second).
  for (const char* name : {"\"tile_000\"", "\"tile_1\"", "\"../x_001\""}) {
    std::string renamed = text;
    renamed.replace(renamed.find("\"tile_001\""), 10, name);
    std::ofstream(dir / "bad.json") << renamed;
    try {
      readTilePlan(dir / "bad.json");
      FAIL() << "no throw for " << name;
    } catch (const InputError& error) {
      EXPECT_EQ(error.where(), "tiles[1].name") << name;
    }
  }
  std::string renamed = text;
  renamed.replace(renamed.find("\"tile_001\""), 10, "\"tile_009\"");
  std::ofstream(dir / "good.json") << renamed;
  EXPECT_EQ(readTilePlan(dir / "good.json").tiles[1].name, "tile_009");
  EXPECT_THROW(readTilePlan(dir / "missing.json"), InputError);
}

TEST(TileFiles, RecordRoundTripAndMissingTile) {
  const test::TempDir dir;
  const TilePlan plan = straightPlan();
  const std::filesystem::path plan_path = dir / "plan.json";
  EXPECT_THROW(readTileRecord(plan_path, plan.tiles[0]), InputError);
  std::filesystem::create_directories(tileDirectory(plan_path, plan.tiles[0]));
  TileRecord record;
  record.index = 0;
  record.revision = 42;
  record.faces = 7;
  record.level_heights_m = {0.25};
  record.files = {"level_0.yaml", "level_0.pgm"};
  writeTileRecord(plan_path, plan.tiles[0], record);
  const TileRecord read = readTileRecord(plan_path, plan.tiles[0]);
  EXPECT_EQ(read.revision, 42u);
  EXPECT_EQ(read.faces, 7u);
  EXPECT_EQ(read.level_heights_m, record.level_heights_m);
  EXPECT_EQ(read.files, (std::vector<std::string>{"level_0.pgm", "level_0.yaml"}));  // sorted
  EXPECT_THROW(readTileRecord(plan_path, plan.tiles[1]), InputError);
}

}  // namespace
}  // namespace terramesh::tiling
