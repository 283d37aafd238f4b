#pragma once

#include <filesystem>

#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// Reads terramesh's own line-based SLAM stream format (see docs/formats.md, ".tmstream").
/// @throw terramesh::InputError naming the file, the line and what was expected.
SlamStream readStreamFile(const std::filesystem::path& path);

/// Writes a stream in terramesh's own format, atomically, with full double precision.
/// @throw std::runtime_error if writing fails.
void writeStreamFile(const std::filesystem::path& path, const SlamStream& stream);

/// Reads any supported stream: ".json" as the authors' JSON, ".tmstream" as terramesh's format.
/// @throw terramesh::InputError for an unknown extension or bad content.
SlamStream readAnyStream(const std::filesystem::path& path);

}  // namespace terramesh::datasets
