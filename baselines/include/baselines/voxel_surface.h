#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "datasets/slam_stream.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::baselines {

/// How OctoMap's frame G relates to the map frame W: the same rotation OctomapBaseline
/// uses (z of G along up_W) and the scale to metres.
struct OctomapFrame {
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  double metres_per_unit = 1.0;
  /// Rotation of W into G: the shortest rotation taking up_W to +z.
  Eigen::Matrix3d rotation_G_W() const;
  /// @throw std::invalid_argument if up_W is zero or not finite, or the scale is not > 0.
  void validate() const;
};

/// What building an octree from a stream took.
struct OctomapBuild {
  std::size_t keyframes = 0;
  std::size_t points = 0;
  std::size_t occupied_leaves = 0;
  std::size_t memory_bytes = 0;  ///< OcTree::memoryUsage()
  double seconds = 0;            ///< insertion time
};

/// Inserts every keyframe event of `stream` into an octree of `resolution_m` through
/// OctomapBaseline (camera centre as sensor origin, rays cut at `max_range_m`, <= 0 for
/// none) and writes it as OctoMap's binary `.bt` to `bt_path` (atomically).
/// @throw std::invalid_argument for a bad resolution or frame; std::runtime_error if the file
///        cannot be written.
OctomapBuild buildOctomap(const datasets::SlamStream& stream, double resolution_m, double max_range_m,
                          const OctomapFrame& frame, const std::filesystem::path& bt_path);

/// The surface of the occupied voxels of a `.bt` file: every face of an occupied voxel (at the
/// tree's finest resolution) whose neighbour across it is not occupied (free or unknown), as two
/// triangles wound counter-clockwise seen from outside. Voxel corners are shared, so voxels
/// touching along an edge or a corner only give non-manifold edges or vertices, as they are.
/// Returned in the map frame W and map units (G -> W through `frame`); no Steiner flags.
/// O(occupied voxels).
/// @throw terramesh::InputError if the file is not a readable OctoMap binary tree.
mesher::TriangleMesh voxelSurfaceFromBt(const std::filesystem::path& bt_path, const OctomapFrame& frame);

/// One occupied leaf of an octree: its centre and edge length, in the octree's frame G and units.
struct OctreeLeaf {
  Eigen::Vector3d centre_G = Eigen::Vector3d::Zero();
  double size = 0;
};

/// The occupied leaves of an OctoMap file (`.bt` binary tree, or `.ot` holding an OcTree), in the
/// tree's leaf order. O(leaves).
/// @throw terramesh::InputError if the file cannot be read as an OcTree.
std::vector<OctreeLeaf> readOccupiedLeaves(const std::filesystem::path& file);

}  // namespace terramesh::baselines
