#pragma once

#include <optional>
#include <string>

#include "cli_args.h"
#include "datasets/stream_reader.h"

namespace terramesh::cli {

/// How to read the input stream (options shared by `mesh` and `bench`): the format, Bundler's
/// image list, and for KITTI LiDAR sequences the poses file, frame range and thinning.
struct InputOptions {
  std::string input_format = "auto";
  std::optional<std::string> image_list;
  std::optional<std::string> poses;
  std::optional<std::string> frames;  ///< "A[:B[:S]]"
  std::size_t max_returns_per_scan = 0;
  std::optional<double> max_range_m;
};

/// Adds the input options to `app`, filling `options` when it parses.
void addInputOptions(CLI::App& app, InputOptions& options);

/// The read options from the parsed values.
/// @throw UsageError for an unknown format, a malformed --frames or invalid KITTI options (every
/// problem listed).
datasets::StreamReadOptions streamReadOptionsFrom(const InputOptions& options);

}  // namespace terramesh::cli
