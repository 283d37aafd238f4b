#pragma once

#include "cli_args.h"
#include "datasets/slam_stream.h"
#include "mesher/mesher_config.h"

namespace terramesh::cli {

/// Declares the options that set MesherConfig fields (shared by `mesh` and `bench`).
void declareMesherOptions(ArgParser& parser);

/// `--max-distance-m auto`: kAutoMaxDistanceFactor times the kAutoMaxDistanceQuantile quantile of
/// the stream's camera-to-point distances (observationDistanceQuantile). It cuts only outliers
/// (points far beyond the usual viewing distance), whatever the model's unit.
constexpr double kAutoMaxDistanceQuantile = 0.95;
constexpr double kAutoMaxDistanceFactor = 2.0;

/// Whether the camera-distance filter comes from the data: `--max-distance-m auto`, or no
/// --max-distance-m and no --metres-per-unit for a stream that recommends it (SfM models).
bool autoMaxDistance(const ArgParser& parser, const datasets::SlamStream& stream);

/// Builds the configuration for `mode` from the parsed options and the stream: the map scale
/// comes from --metres-per-unit, else from the stream if it states one, else 1; the camera
/// distance from --max-distance-m, or the data when autoMaxDistance; the baselines' fixed grid
/// covers the stream's bounding box.
/// @throw UsageError for invalid values (with every problem listed).
mesher::MesherConfig mesherConfigFromArgs(const ArgParser& parser, mesher::MesherMode mode,
                                          const datasets::SlamStream& stream);

/// Bounding box of every camera centre and observed position in the stream.
mesher::AxisAlignedBox streamBounds(const datasets::SlamStream& stream);

}  // namespace terramesh::cli
