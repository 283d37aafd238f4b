// A tiled map as a planner loads it: the tile index read back with field errors, the tiles around a
// region, and owned maps joined with their shared border vertices welded (docs/tiles.md, "Planning
// across tiles").
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/input_error.h"
#include "free_floor.h"
#include "test_support/temp_dir.h"
#include "tiling/tile_index.h"
#include "traversability/map_directory.h"

namespace terramesh::tiling {
namespace {

/// The floor from x0 to x1 (10 m wide, 1 m grid), raised by `dz`, with Steiner flags as a written
/// map has them.
traversability::LayeredMesh floorPart(double x0, double x1, double dz = 0) {
  traversability::LayeredMesh map = test_floor::freeFloor(x0, x1, dz);
  map.mesh.is_steiner.assign(map.mesh.vertices.size(), 0);
  return map;
}

/// Three 12 m tiles of a 30 x 10 m floor, written as `tiles merge` lays them out, and their index.
class TileIndexTest : public ::testing::Test {
 protected:
  void SetUp() override {
    writeTile(0, floorPart(0, 12), 0, 12);
    writeTile(1, floorPart(12, 24), 12, 24);
    writeTile(2, floorPart(24, 30), 24, 36);
    writeIndex(index_json_);
  }

  void writeTile(std::size_t i, const traversability::LayeredMesh& part, double min_x, double max_x,
                 const traversability::RobotProfile& profile = {}) {
    const std::string name = "tile_00" + std::to_string(i);
    traversability::ExportConfig config;
    config.write_geotiff = false;
    config.write_mesh_map_h5 = false;
    traversability::writeMapDirectory(dir_.path() / name / "map", part, profile, config);
    nlohmann::json tile = {
        {"index", i},
        {"name", name},
        {"bounds_m", {{"min_x", min_x}, {"min_y", 0.0}, {"max_x", max_x}, {"max_y", 12.0}}},
        {"faces", part.mesh.faces.size()},
        {"files", {name + "/map/robot.yaml", name + "/map/traversability.ply"}}};
    if (index_json_["tiles"].size() <= i) {
      index_json_["tiles"].push_back(tile);
    } else {
      index_json_["tiles"][i] = tile;
    }
  }

  void writeIndex(const nlohmann::json& index) const {
    std::ofstream(dir_.path() / "tiles.json") << index.dump(2);
  }

  test::TempDir dir_;
  nlohmann::json index_json_ = {
      {"format", "terramesh tile index"},
      {"version", 1},
      {"frame",
       {{"up", {0, 0, 1}}, {"metres_per_unit", 1.0}, {"plan_x", {1, 0, 0}}, {"plan_y", {0, 1, 0}}}},
      {"tile_m", 12.0},
      {"tiles", nlohmann::json::array()}};
};

TEST_F(TileIndexTest, TilesMeetingARegion) {
  const TileIndex index = readTileIndex(dir_.path() / "tiles.json");
  ASSERT_EQ(index.tiles.size(), 3u);
  EXPECT_EQ(index.tiles[1].name, "tile_001");
  EXPECT_EQ(index.tiles[1].map_dir, dir_.path() / "tile_001" / "map");
  EXPECT_EQ(tilesMeeting(index, PlanRect{1, 1, 5, 5}), (std::vector<std::size_t>{0}));
  EXPECT_EQ(tilesMeeting(index, PlanRect{11, 1, 13, 5}), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(tilesMeeting(index, PlanRect{-50, -50, 50, 50}), (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_TRUE(tilesMeeting(index, PlanRect{40, 1, 45, 5}).empty());
  const PlanRect extent = index.extentOfFaces();
  EXPECT_DOUBLE_EQ(extent.max_x_m, 36.0);
}

TEST_F(TileIndexTest, JoinedTilesShareTheirBorderVertices) {
  const TileIndex index = readTileIndex(dir_.path() / "tiles.json");
  const JoinedTiles joined = joinTiles(index, {0, 1, 2});
  const traversability::LayeredMesh whole = floorPart(0, 30);
  EXPECT_EQ(joined.map.mesh.faces.size(), whole.mesh.faces.size());
  EXPECT_EQ(joined.map.layers.size(), whole.mesh.faces.size());
  EXPECT_EQ(joined.map.mesh.vertices.size(), whole.mesh.vertices.size());
  EXPECT_EQ(joined.map.mesh.is_steiner.size(), whole.mesh.vertices.size());
  EXPECT_EQ(joined.welded_vertices, 22u);  // x = 12 and x = 24, 11 vertices each
  EXPECT_EQ(joined.border_edges, 20u);     // 10 edges along each border
  // Two tiles side by side are not joined where the second lies a hair higher.
  writeTile(1, floorPart(12, 24, 1e-9), 12, 24);
  const JoinedTiles apart = joinTiles(readTileIndex(dir_.path() / "tiles.json"), {0, 1});
  EXPECT_EQ(apart.welded_vertices, 0u);
  EXPECT_EQ(apart.border_edges, 0u);
}

TEST_F(TileIndexTest, BadIndexAndTilesNameTheFieldOrFile) {
  nlohmann::json bad = index_json_;
  bad["tiles"][1]["files"] = {"tile_001/map/robot.yaml"};
  writeIndex(bad);
  try {
    readTileIndex(dir_.path() / "tiles.json");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("tiles[1].files"), std::string::npos) << error.what();
  }
  bad = index_json_;
  bad["frame"]["up"] = {0, 0, 0};
  writeIndex(bad);
  EXPECT_THROW(readTileIndex(dir_.path() / "tiles.json"), InputError);
  writeIndex(index_json_);
  traversability::RobotProfile other;
  other.name = "another robot";
  writeTile(2, floorPart(24, 30), 24, 36, other);
  writeIndex(index_json_);
  const TileIndex index = readTileIndex(dir_.path() / "tiles.json");
  try {
    joinTiles(index, {0, 2});
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("tile_002/map/robot.yaml"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(joinTiles(index, {}), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::tiling
