#include "baselines/voxel_surface.h"

#include <octomap/OcTree.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <memory>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>
#include <variant>

#include "baselines/octomap_baseline.h"
#include "common/grid_key.h"
#include "common/input_error.h"
#include "common/plan_frame.h"

namespace terramesh::baselines {

Eigen::Matrix3d OctomapFrame::rotation_G_W() const {
  return geometry::rotationUpToZ(up_W);
}

void OctomapFrame::validate() const {
  std::ostringstream problems;
  if (!up_W.allFinite() || up_W.norm() == 0) problems << " up_W: not a non-zero finite vector;";
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    problems << " metres_per_unit: " << metres_per_unit << " (expected > 0);";
  }
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("OctomapFrame:" + text);
}

OctomapBuild buildOctomap(const datasets::SlamStream& stream, double resolution_m, double max_range_m,
                          const OctomapFrame& frame, const std::filesystem::path& bt_path) {
  frame.validate();
  OctomapConfig config;
  config.resolution_m = resolution_m;
  config.max_range_m = max_range_m;
  config.metres_per_unit = frame.metres_per_unit;
  config.up_W = frame.up_W;
  OctomapBaseline baseline(config);
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) baseline.insertKeyframe(*keyframe);
  }
  std::filesystem::path temporary = bt_path;
  temporary += ".partial.bt";
  baseline.writeBinary(temporary);
  std::filesystem::rename(temporary, bt_path);
  const OctomapStats stats = baseline.stats();
  OctomapBuild build;
  build.keyframes = stats.keyframes;
  build.points = stats.points;
  build.occupied_leaves = stats.occupied_leaves;
  build.memory_bytes = stats.memory_bytes;
  build.seconds = stats.build_time_s;
  return build;
}

namespace {

/// geometry::spatialHash3 of the sign-extended indices.
struct KeyHash {
  std::size_t operator()(const std::array<int, 3>& k) const noexcept {
    return static_cast<std::size_t>(geometry::spatialHash3(
        static_cast<std::uint64_t>(k[0]), static_cast<std::uint64_t>(k[1]), static_cast<std::uint64_t>(k[2])));
  }
};

}  // namespace

mesher::TriangleMesh voxelSurfaceFromBt(const std::filesystem::path& bt_path, const OctomapFrame& frame) {
  frame.validate();
  if (!std::filesystem::is_regular_file(bt_path)) throw InputError(bt_path.string(), "file", "an existing .bt file");
  octomap::OcTree tree(0.1);
  if (!tree.readBinary(bt_path.string())) throw InputError(bt_path.string(), "header", "an OctoMap binary tree (.bt)");
  const double res = tree.getResolution();
  const unsigned depth = tree.getTreeDepth();

  // Every occupied voxel at the finest resolution, by key.
  std::unordered_set<std::array<int, 3>, KeyHash> occupied;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const octomap::OcTreeKey key = it.getKey();
    const int cells = 1 << (depth - it.getDepth());
    // A leaf above the finest depth covers cells^3 voxels starting at its key with the low bits cleared.
    const int mask = ~(cells - 1);
    for (int a = 0; a < cells; ++a) {
      for (int b = 0; b < cells; ++b) {
        for (int c = 0; c < cells; ++c) {
          occupied.insert({(key[0] & mask) + a, (key[1] & mask) + b, (key[2] & mask) + c});
        }
      }
    }
  }

  mesher::TriangleMesh mesh;
  std::unordered_map<std::array<int, 3>, std::uint32_t, KeyHash> corner_index;
  const Eigen::Matrix3d R_W_G = frame.rotation_G_W().transpose();
  // OctoMap's key of the voxel whose lower corner is the origin: 2^(depth - 1) (its tree_max_val).
  const int centre = 1 << (depth - 1);
  auto corner = [&](const std::array<int, 3>& c) {
    const auto [it, inserted] = corner_index.emplace(c, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) {
      const Eigen::Vector3d p_G((c[0] - centre) * res, (c[1] - centre) * res, (c[2] - centre) * res);
      mesh.vertices.push_back(R_W_G * p_G / frame.metres_per_unit);
    }
    return it->second;
  };
  // Deterministic order: sort the voxels.
  std::vector<std::array<int, 3>> voxels(occupied.begin(), occupied.end());
  std::sort(voxels.begin(), voxels.end());
  for (const std::array<int, 3>& v : voxels) {
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (const int side : {1, -1}) {
        std::array<int, 3> neighbour = v;
        neighbour[axis] += side;
        if (occupied.count(neighbour) != 0) continue;
        std::array<int, 3> base = v;
        if (side > 0) base[axis] += 1;
        std::array<int, 3> bu = base, buw = base, bw = base;
        bu[u] += 1;
        buw[u] += 1;
        buw[w] += 1;
        bw[w] += 1;
        // Counter-clockwise seen from outside: e_u x e_w = +e_axis.
        const std::uint32_t c0 = corner(base), c1 = corner(side > 0 ? bu : bw), c2 = corner(buw),
                            c3 = corner(side > 0 ? bw : bu);
        mesh.faces.push_back({c0, c1, c2});
        mesh.faces.push_back({c0, c2, c3});
      }
    }
  }
  return mesh;
}

std::vector<OctreeLeaf> readOccupiedLeaves(const std::filesystem::path& file) {
  std::unique_ptr<octomap::OcTree> tree;
  if (file.extension() == ".bt") {
    tree = std::make_unique<octomap::OcTree>(0.1);
    if (!tree->readBinary(file.string())) throw InputError(file.string(), "header", "unreadable (expected an OctoMap binary tree, .bt)");
  } else {
    std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(file.string()));
    auto* as_octree = dynamic_cast<octomap::OcTree*>(any.get());
    if (!as_octree) throw InputError(file.string(), "header", "unreadable (expected an OctoMap OcTree, .ot)");
    any.release();
    tree.reset(as_octree);
  }
  std::vector<OctreeLeaf> leaves;
  for (auto leaf = tree->begin_leafs(), end = tree->end_leafs(); leaf != end; ++leaf) {
    if (tree->isNodeOccupied(*leaf)) leaves.push_back({Eigen::Vector3d(leaf.getX(), leaf.getY(), leaf.getZ()), leaf.getSize()});
  }
  return leaves;
}

}  // namespace terramesh::baselines
