#pragma once
// What a mesh written by `terramesh mesh` says about its own frame, in its PLY header comments:
// the scale, the up vector and the sensor height the run inferred (docs/formats.md, "mesh.ply").
// Commands reading that mesh (traverse, traverse-eval) take them as defaults, flags override.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace terramesh::cli {

struct MeshFrameHints {
  std::optional<double> metres_per_unit;
  std::optional<Eigen::Vector3d> up_W;
  std::string up_source;  ///< how the run found up, e.g. "estimated from 104 keyframe rotations"
  /// The SLAM sensor above the ground contact plane, metres (trajectory evidence on).
  std::optional<double> sensor_height_m;
  std::string sensor_height_source;  ///< e.g. "the data", "--sensor-height-m"
};

/// The comment lines (without "comment ") that record `hints` in a PLY header.
std::vector<std::string> meshFrameComments(const MeshFrameHints& hints);

/// Reads the hints from the header of the PLY file `path` (nothing for other formats, or a file
/// without them).
/// @throw terramesh::InputError naming the file and the header line when a hint is malformed.
MeshFrameHints readMeshFrameHints(const std::filesystem::path& path);

}  // namespace terramesh::cli
