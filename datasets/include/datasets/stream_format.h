#pragma once

#include <filesystem>

#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// Reads terramesh's own line-based SLAM stream format (see docs/formats.md, ".tmstream").
/// @throw terramesh::InputError naming the file, the line and what was expected (also for a point
///        listed twice in one keyframe, which the mesher would reject).
SlamStream readStreamFile(const std::filesystem::path& path);

/// Writes a stream in terramesh's own format, atomically, with full double precision.
/// @throw std::runtime_error if writing fails.
void writeStreamFile(const std::filesystem::path& path, const SlamStream& stream);

}  // namespace terramesh::datasets
