#pragma once

#include "cli_args.h"
#include "datasets/stream_reader.h"

namespace terramesh::cli {

/// Declares the options that say how to read the input stream (shared by `mesh` and `bench`):
/// the format, Bundler's image list, and for KITTI LiDAR sequences the poses file, frame range
/// and thinning.
void declareInputOptions(ArgParser& parser);

/// The read options from the parsed arguments.
/// @throw UsageError for an unknown format or invalid KITTI options (every problem listed).
datasets::StreamReadOptions streamReadOptionsFromArgs(const ArgParser& parser);

}  // namespace terramesh::cli
