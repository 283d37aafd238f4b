// The server side of `terramesh view` without a browser: which requests reach a file, the run
// manifest, OctoMap voxels and the trajectory / points extras.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "common/input_error.h"
#include "datasets/slam_stream.h"
#include "run_extras.h"
#include "test_support/temp_dir.h"
#include "traversability/layer_registry.h"
#include "view_server.h"

namespace terramesh::cli {
namespace {

namespace fs = std::filesystem;

void writeText(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

TEST(ResolveInside, ServesFilesBelowTheRootOnly) {
  terramesh::test::TempDir dir;
  const fs::path root = dir / "run";
  writeText(root / "mesh.ply", "ply");
  writeText(root / "snapshots" / "mesh_000004.ply", "ply");
  writeText(dir / "secret.txt", "secret");
  fs::create_symlink(dir / "secret.txt", root / "link_out.txt");
  fs::create_symlink(root / "mesh.ply", root / "link_in.ply");
  fs::create_directories(root / "sub");

  EXPECT_EQ(resolveInside(root, "mesh.ply"), fs::canonical(root / "mesh.ply"));
  EXPECT_EQ(resolveInside(root, "snapshots/mesh_000004.ply"), fs::canonical(root / "snapshots/mesh_000004.ply"));
  EXPECT_EQ(resolveInside(root, "link_in.ply"), fs::canonical(root / "mesh.ply"));
  for (const std::string& bad : std::vector<std::string>{"", "../secret.txt", "snapshots/../../secret.txt", "/etc/passwd", "./mesh.ply",
                                "snapshots/..", "..", "link_out.txt", "sub", "missing.ply", "..\\secret.txt",
                                std::string("mesh.ply\0x", 10)}) {
    EXPECT_FALSE(resolveInside(root, bad).has_value()) << '"' << bad << '"';
  }
}

TEST(RunManifest, ListsWhatTheRunHolds) {
  terramesh::test::TempDir dir;
  writeText(dir / "mesh.ply", "ply");
  writeText(dir / "keyframes.csv", "event\n");
  writeText(dir / "path.csv", "x,y,z\n");
  writeText(dir / "path_car.csv", "x,y,z\n");
  writeText(dir / "snapshots" / "mesh_000012.ply", "ply");
  writeText(dir / "snapshots" / "mesh_000004.ply", "ply");
  writeText(dir / "snapshots" / "notes.txt", "");
  RunExtras extras;
  extras.trajectory_csv = "keyframe\n";
  const auto manifest = nlohmann::json::parse(runManifestJson(dir.path(), extras));
  EXPECT_EQ(manifest["mesh"], "run/mesh.ply");
  EXPECT_TRUE(manifest["traversability"].is_null());
  EXPECT_EQ(manifest["trajectory"], "api/trajectory.csv");
  EXPECT_TRUE(manifest["points"].is_null());
  EXPECT_EQ(manifest["paths"], nlohmann::json({"run/path.csv", "run/path_car.csv"}));
  ASSERT_EQ(manifest["snapshots"].size(), 2u);
  EXPECT_EQ(manifest["snapshots"][0]["keyframe"], 4);
  EXPECT_EQ(manifest["snapshots"][1]["url"], "run/snapshots/mesh_000012.ply");
  // The layers the viewer labels: the registry's, in its order, with their fixed ranges.
  const std::vector<traversability::LayerInfo>& registry = traversability::faceLayerRegistry();
  ASSERT_EQ(manifest["layers"].size(), registry.size());
  for (std::size_t i = 0; i < registry.size(); ++i) {
    EXPECT_EQ(manifest["layers"][i]["name"], registry[i].name);
    EXPECT_EQ(manifest["layers"][i]["description"], registry[i].description);
  }
  EXPECT_EQ(manifest["layers"][0]["name"], "cost");
  EXPECT_EQ(manifest["layers"][0]["range"], nlohmann::json({0.0, 1.0}));
  EXPECT_FALSE(manifest["layers"][1].contains("range")) << "slope_deg takes the data's range";
  EXPECT_TRUE(manifest["tile_index"].is_null());
}

TEST(RunManifest, ATiledMapsFolderNamesItsIndex) {
  terramesh::test::TempDir dir;
  writeText(dir / "tiles.json", "{}");
  const auto manifest = nlohmann::json::parse(runManifestJson(dir.path(), RunExtras{}));
  EXPECT_EQ(manifest["tile_index"], "run/tiles.json");
  EXPECT_TRUE(manifest["mesh"].is_null());
}

TEST(OctomapVoxels, OccupiedLeavesWithCentresAndSizes) {
  terramesh::test::TempDir dir;
  octomap::OcTree tree(0.5);
  const std::set<std::tuple<int, int, int>> occupied = {{0, 0, 0}, {3, -2, 1}, {-4, 5, 2}};
  for (const auto& [i, j, k] : occupied) tree.updateNode(octomap::point3d(0.5f * i + 0.25f, 0.5f * j + 0.25f, 0.5f * k + 0.25f), true);
  tree.updateNode(octomap::point3d(2.25f, 2.25f, 2.25f), false);  // free: not a voxel
  const fs::path file = dir / "map.bt";
  ASSERT_TRUE(tree.writeBinary(file.string()));

  const std::string voxels = octomapToVoxels(file);
  ASSERT_GE(voxels.size(), 16u);
  EXPECT_EQ(voxels.substr(0, 8), "TMVOXEL1");
  std::uint32_t count = 0;
  std::memcpy(&count, voxels.data() + 8, 4);
  ASSERT_EQ(count, occupied.size());
  ASSERT_EQ(voxels.size(), 16 + 16 * count);
  std::set<std::tuple<int, int, int>> found;
  for (std::uint32_t v = 0; v < count; ++v) {
    float xyzs[4];
    std::memcpy(xyzs, voxels.data() + 16 + 16 * v, 16);
    EXPECT_FLOAT_EQ(xyzs[3], 0.5f);
    found.emplace(static_cast<int>(std::floor(xyzs[0] / 0.5f)), static_cast<int>(std::floor(xyzs[1] / 0.5f)),
                  static_cast<int>(std::floor(xyzs[2] / 0.5f)));
  }
  EXPECT_EQ(found, occupied);

  writeText(dir / "broken.bt", "not an octree");
  EXPECT_THROW(octomapToVoxels(dir / "broken.bt"), InputError);
}

TEST(RunExtras, TrajectoryAndPointsFollowTheStream) {
  datasets::SlamStream stream;
  const auto keyframe = [](std::uint64_t id, double x, std::vector<std::pair<std::uint64_t, double>> points) {
    mesher::Keyframe k;
    k.id = mesher::KeyframeId{id};
    k.position_W_C = Eigen::Vector3d(x, 0, 1);
    for (const auto& [point, px] : points) k.observations.push_back({mesher::PointId{point}, Eigen::Vector3d(px, 1, 0)});
    return k;
  };
  stream.events.push_back(keyframe(7, 0.0, {{1, 1.0}, {2, 2.0}}));
  stream.events.push_back(keyframe(8, 1.0, {{2, 2.5}, {3, 3.0}}));
  stream.events.push_back(datasets::PointRemoval{{mesher::PointId{1}}});
  stream.events.push_back(keyframe(7, 0.5, {{3, 3.5}}));  // corrected pose of keyframe 7

  EXPECT_EQ(trajectoryCsv(stream),
            "keyframe,id,x,y,z,qw,qx,qy,qz\n1,7,0,0,1,1,0,0,0\n2,8,1,0,1,1,0,0,0\n3,7,0.5,0,1,1,0,0,0\n");
  const std::string ply = pointsPly(stream);
  const std::string header_end = "end_header\n";
  const std::size_t body = ply.find(header_end) + header_end.size();
  ASSERT_NE(ply.find("element vertex 2\n"), std::string::npos);
  ASSERT_EQ(ply.size(), body + 2 * 16);
  float xyz[3];
  std::uint32_t first = 0;
  std::memcpy(xyz, ply.data() + body, 12);
  std::memcpy(&first, ply.data() + body + 12, 4);
  EXPECT_FLOAT_EQ(xyz[0], 2.5f);  // point 2, latest position, first seen by keyframe event 1
  EXPECT_EQ(first, 1u);
  std::memcpy(xyz, ply.data() + body + 16, 12);
  std::memcpy(&first, ply.data() + body + 28, 4);
  EXPECT_FLOAT_EQ(xyz[0], 3.5f);
  EXPECT_EQ(first, 2u);
}

}  // namespace
}  // namespace terramesh::cli
