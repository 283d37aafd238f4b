#pragma once

#include <filesystem>
#include <string>

#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// Reads the incremental JSON export of the paper's authors (manifold_reconstructor), versions
/// "0.1" (views[].key, observations[].key) and "0.2"/"0.3" (views[].viewId,
/// observations[].pointId). Each view becomes one keyframe event, in file order; a view whose key
/// repeats an earlier one replaces it. `extrinsic.rotation` is read as camera-to-world.
/// @throw terramesh::InputError naming the file and the JSON field (or line and column, for syntax
///        errors), also for a point listed twice in one view (the mesher would reject it).
SlamStream readSlamJson(const std::filesystem::path& path);

/// Writes keyframe events in the authors' JSON format ("0.1" or "0.3"), atomically. Removal
/// events have no representation there and are skipped.
/// @throw std::invalid_argument for another version; std::runtime_error if writing fails.
void writeSlamJson(const std::filesystem::path& path, const SlamStream& stream,
                   const std::string& version = "0.3");

}  // namespace terramesh::datasets
