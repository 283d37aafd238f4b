#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>

#include "baselines/height_grid.h"
#include "mesher/keyframe.h"

namespace terramesh::baselines {

/// How the OctoMap baseline is built.
struct OctomapConfig {
  /// Voxel edge length.
  double resolution_m = 0.2;
  /// Rays longer than this are cut (OctoMap's maxrange; <= 0: no limit).
  double max_range_m = -1;
  /// Metres per map unit of the keyframes.
  double metres_per_unit = 1.0;
  /// Up (against gravity) in the map frame; the octree is built in a frame G whose z is up.
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// What building the octree cost (returned, never logged).
struct OctomapStats {
  std::size_t keyframes = 0;
  std::size_t points = 0;
  double build_time_s = 0;
  std::size_t memory_bytes = 0;  ///< OcTree::memoryUsage()
  std::size_t leaves = 0;
  std::size_t occupied_leaves = 0;
};

/// An octomap::OcTree built from the same keyframes as the mesh: every keyframe's points
/// inserted with the camera centre as the sensor origin (insertPointCloud, OctoMap's default
/// sensor model: hit 0.7, miss 0.4, clamping 0.12 / 0.97). A keyframe sent again (a corrected
/// pose) is inserted again: OctoMap cannot take back what it integrated; point removals are
/// ignored for the same reason. OctoMap stays inside the library (pimpl). Not thread-safe.
class OctomapBaseline {
 public:
  /// @throw std::invalid_argument if the config does not validate.
  explicit OctomapBaseline(const OctomapConfig& config);
  ~OctomapBaseline();
  OctomapBaseline(OctomapBaseline&&) noexcept;
  OctomapBaseline& operator=(OctomapBaseline&&) noexcept;

  void insertKeyframe(const mesher::Keyframe& keyframe);
  /// Writes the tree as OctoMap's binary .bt (maximum-likelihood occupancy).
  /// @throw std::runtime_error if the file cannot be written.
  void writeBinary(const std::filesystem::path& path) const;
  OctomapStats stats() const;

  /// The 2.5D grid at the octree's resolution over the observed extent: per column the ground is
  /// the top of the highest occupied voxel whose voxel above is observed free; the clearance is
  /// the free height from there to the next occupied voxel above (+inf if none); unknown where
  /// no such voxel exists. Then HeightGrid::classify(robot).
  HeightGrid heightGrid(const GridRobotConfig& robot) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terramesh::baselines
