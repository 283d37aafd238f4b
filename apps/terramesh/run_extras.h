#pragma once

// The camera trajectory and the SLAM points of a stream, as files beside a run's mesh, for the
// viewer (docs/viewer.md): OUT/trajectory.csv and OUT/points.ply.
#include <filesystem>
#include <string>

#include "datasets/slam_stream.h"

namespace terramesh::cli {

/// trajectory.csv: header `keyframe,id,x,y,z,qw,qx,qy,qz`, one row per keyframe event in stream
/// order. `keyframe` counts keyframe events from 1 (the numbering of snapshots/mesh_NNNNNN.ply);
/// a corrected keyframe appears again with the same id. Position: camera centre in the world
/// frame, map units; q rotates camera vectors into the world frame.
std::string trajectoryCsv(const datasets::SlamStream& stream);

/// points.ply (binary little endian): element vertex with float x y z (latest position, map
/// units) and uint first_keyframe (keyframe event count, from 1, when the point was first seen),
/// for every point observed and not removed by the end of the stream.
std::string pointsPly(const datasets::SlamStream& stream);

/// Writes both files into `output` atomically (to be called by `terramesh mesh`).
/// @throw std::runtime_error if a file cannot be written.
void writeRunExtras(const datasets::SlamStream& stream, const std::filesystem::path& output);

}  // namespace terramesh::cli
