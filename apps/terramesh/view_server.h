#pragma once

// The HTTP side of `terramesh view`: which files of a run folder the page may read, the manifest
// that tells the page what the run holds, and OctoMap voxels as a flat binary (docs/viewer.md).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace terramesh::cli {

/// The file `request` (a URL path below a served root, already percent-decoded, without the
/// leading "/") names inside `root`, or nullopt when the request must be refused: an empty,
/// absolute or backslashed path, a ".." or "." segment, a NUL byte, or a target (after symlinks)
/// outside `root` or not a regular file.
std::optional<std::filesystem::path> resolveInside(const std::filesystem::path& root, const std::string& request);

/// MIME type from a file name's extension (application/octet-stream when unknown).
std::string contentTypeFor(const std::filesystem::path& file);

/// Extra data the server holds in memory for a run that lacks the files.
struct RunExtras {
  std::string trajectory_csv;  ///< trajectory.csv content (run_extras.h), empty if none
  std::string points_ply;      ///< points.ply content, empty if none
  std::string voxels_bin;      ///< voxels.bin content, empty if none
  std::string voxels_source;   ///< the .bt/.ot file the voxels came from
};

/// JSON describing a run folder: the files the viewer knows (mesh.ply, traversability.ply,
/// keyframes.csv, summary.txt, map_frame.yaml, trajectory.csv, points.ply, path*.csv, path*.ply,
/// voxels.bin, snapshots/mesh_NNNNNN.ply with their keyframe numbers) as URLs for the page.
std::string runManifestJson(const std::filesystem::path& run_dir, const RunExtras& extras);

/// voxels.bin from an OctoMap file (.bt or .ot): 8 bytes "TMVOXEL1", uint32 count, uint32 0,
/// then per occupied leaf float32 x, y, z (centre), size (edge length), all little endian, in
/// the octree's frame and units (baselines::OctomapBaseline: metres, +z along up; docs/viewer.md).
/// @throw terramesh::InputError if the file cannot be read as an OcTree.
std::string octomapToVoxels(const std::filesystem::path& file);

struct ViewServerConfig {
  std::filesystem::path run_dir;     ///< the run folder served under /run/
  std::filesystem::path bundle_dir;  ///< index.html and the bundled scripts, served under /
  int port = 8765;                   ///< 0 picks a free port
};

/// Binds to 127.0.0.1 only, calls `on_listening(port)` once bound, then serves until the
/// process ends.
/// @throw std::runtime_error if the port cannot be bound.
void serveRun(const ViewServerConfig& config, const RunExtras& extras, const std::function<void(int)>& on_listening);

}  // namespace terramesh::cli
