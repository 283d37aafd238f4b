#pragma once

// The camera trajectory and the SLAM points of a stream, as files beside a run's mesh, for the
// viewer (docs/viewer.md): OUT/trajectory.csv and OUT/points.ply.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "datasets/slam_stream.h"

namespace terramesh::cli {

/// trajectory.csv: header `keyframe,id,x,y,z,qw,qx,qy,qz`, one row per keyframe event in stream
/// order. `keyframe` counts keyframe events from 1 (the numbering of snapshots/mesh_NNNNNN.ply);
/// a corrected keyframe appears again with the same id. Position: camera centre in the world
/// frame, map units; q rotates camera vectors into the world frame.
std::string trajectoryCsv(const datasets::SlamStream& stream);

/// A keyframe's pose as trajectory.csv lists it.
struct TrajectoryRow {
  std::uint64_t id = 0;
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation_W_C = Eigen::Quaterniond::Identity();
};

/// Reads a trajectory.csv: each keyframe once, in the order of its first row, at its last row's
/// pose (a corrected keyframe's latest estimate). Quaternions are normalized.
/// @throw terramesh::InputError naming the file, the line and the field for a missing or
/// malformed header or row, a non-finite value or a quaternion far from unit norm.
std::vector<TrajectoryRow> readTrajectoryCsv(const std::filesystem::path& path);

/// points.ply (binary little endian): element vertex with float x y z (latest position, map
/// units) and uint first_keyframe (keyframe event count, from 1, when the point was first seen),
/// for every point observed and not removed by the end of the stream.
std::string pointsPly(const datasets::SlamStream& stream);

/// Writes both files into `output` atomically (to be called by `terramesh mesh`).
/// @throw std::runtime_error if a file cannot be written.
void writeRunExtras(const datasets::SlamStream& stream, const std::filesystem::path& output);

}  // namespace terramesh::cli
