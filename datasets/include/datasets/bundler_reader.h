#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// Where the image list of a Bundler file may be, in the order findBundlerList tries them: the
/// file's name with "bundle" replaced by "list" beside it (OpenSfM: `bundle_r000.out` ->
/// `list_r000.out`), the same with the extension `.txt`, `list.txt` beside it, and `list.txt` in
/// its parent directory (Bundler writes `bundle/bundle.out` beside `list.txt`). No duplicates.
std::vector<std::filesystem::path> bundlerListCandidates(const std::filesystem::path& bundle_path);

/// The first of bundlerListCandidates(bundle_path) that is a regular file; nullopt when none is.
std::optional<std::filesystem::path> findBundlerList(const std::filesystem::path& bundle_path);

/// Reads a Bundler v0.3 bundle file (`# Bundle file v0.3`, then cameras `f k1 k2` / R (3 rows) /
/// t and points `X Y Z` / `R G B` / `N (CAMERA KEY X Y)...`) and, when there is one, its image
/// list (one image a line, the first field is the file name; as many lines as cameras). Meshing
/// needs no image names: without a list the stream is the same, with no keyframe_names. Bundler's camera looks down -z
/// with y up (x_C = R x_W + t); the keyframes use x right, y down, z forward, so they take the
/// centre -R^T t and the rotation (diag(1,-1,-1) R)^T. One keyframe event per reconstructed
/// camera (f != 0; Bundler zeroes the others), in camera order; keyframe id = camera index, point
/// id = point index, keyframe_names from the list. A camera listed twice in one point's view list
/// (two features of one image) counts once. Units are the model's (scale unknown).
/// @param list_path the image list; empty: findBundlerList(bundle_path), and none if it finds none.
/// @throw terramesh::InputError naming the file and the line: missing or wrong header, an
///        unreadable list_path, list and camera counts that differ, a non-rotation, a non-finite number, a
///        camera index out of range or not reconstructed, a truncated file or trailing data.
SlamStream readBundler(const std::filesystem::path& bundle_path,
                       const std::filesystem::path& list_path = {});

}  // namespace terramesh::datasets
