#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli_args.h"
#include "datasets/slam_stream.h"
#include "mesher/mesher_config.h"

namespace terramesh::cli {

/// The options that set MesherConfig fields (shared by `mesh` and `bench`); unset ones keep the
/// mode's default or what the stream advises.
struct MesherOptions {
  std::optional<double> metres_per_unit;
  std::optional<int> min_views;
  std::optional<std::string> max_distance_m;  ///< metres, or "auto"
  std::optional<double> steiner_step_m;
  std::optional<double> free_threshold;
  double move_threshold_m = 0;
  std::optional<std::string> point_policy;
  std::optional<int> spread_cap;
  int enclosing_radius_cells = 2;
  int camera_enclosing_radius_cells = 0;
  std::optional<int> handle_min_rays;
  std::optional<std::string> disable;  ///< comma-separated technique names
  std::optional<std::string> steiner_origin_offset_m;  ///< "X,Y,Z" metres (experiment option)
  std::optional<double> steiner_clearance_steps;
};

/// Adds the mesher options to `app`, filling `options` when it parses.
void addMesherOptions(CLI::App& app, MesherOptions& options);

/// `--max-distance-m auto`: kAutoMaxDistanceFactor times the kAutoMaxDistanceQuantile quantile of
/// the stream's camera-to-point distances (observationDistanceQuantile). It cuts only outliers
/// (points far beyond the usual viewing distance), whatever the model's unit.
constexpr double kAutoMaxDistanceQuantile = 0.95;
constexpr double kAutoMaxDistanceFactor = 2.0;

/// Whether the camera-distance filter comes from the data: `--max-distance-m auto`, or no
/// --max-distance-m and no --metres-per-unit for a stream that recommends it (SfM models).
bool autoMaxDistance(const MesherOptions& options, const datasets::SlamStream& stream);

/// Builds the configuration for `mode` from the parsed options and the stream: the map scale
/// comes from --metres-per-unit, else from the stream if it states one, else 1; the camera
/// distance from --max-distance-m, or the data when autoMaxDistance; the baselines' fixed grid
/// covers the stream's bounding box.
/// @throw UsageError for invalid values (with every problem listed).
mesher::MesherConfig mesherConfigFrom(const MesherOptions& options, mesher::MesherMode mode,
                                      const datasets::SlamStream& stream);

/// What mesherConfigFrom took from the data rather than from a flag, one sentence each, with the
/// flag that overrides it: the scale, the views a point needs, the Steiner lattice's spacing, the
/// sensor's up axis.
std::vector<std::string> describeInferredSettings(const MesherOptions& options, const datasets::SlamStream& stream,
                                                  const mesher::MesherConfig& config);

/// Bounding box of every camera centre and observed position in the stream.
mesher::AxisAlignedBox streamBounds(const datasets::SlamStream& stream);

}  // namespace terramesh::cli
