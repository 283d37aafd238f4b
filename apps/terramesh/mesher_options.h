#pragma once

#include "cli_args.h"
#include "datasets/slam_stream.h"
#include "mesher/mesher_config.h"

namespace terramesh::cli {

/// Declares the options that set MesherConfig fields (shared by `mesh` and `bench`).
void declareMesherOptions(ArgParser& parser);

/// Builds the configuration for `mode` from the parsed options and the stream: the map scale
/// comes from --metres-per-unit, else from the stream if it states one, else 1; the baselines'
/// fixed grid covers the stream's bounding box.
/// @throw UsageError for invalid values (with every problem listed).
mesher::MesherConfig mesherConfigFromArgs(const ArgParser& parser, mesher::MesherMode mode,
                                          const datasets::SlamStream& stream);

/// Bounding box of every camera centre and observed position in the stream.
mesher::AxisAlignedBox streamBounds(const datasets::SlamStream& stream);

}  // namespace terramesh::cli
