#pragma once

// Keeps a traversability map current while `terramesh mesh --robot R.yaml` meshes a stream, and
// rewrites the map directory's exports every K keyframes and at the end.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "cli_args.h"
#include "datasets/slam_stream.h"
#include "mesher/mesher.h"
#include "traversability/map_directory.h"
#include "traversability/robot_profile.h"
#include "traversability/traversability_map.h"

namespace terramesh::cli {

/// Options shared by `mesh` and `traverse`: the robot, the grid and the GeoTIFF and HDF5 switches.
struct TraversabilityExportOptions {
  std::optional<std::string> robot;  ///< --robot YAML
  double grid_resolution_m = 0.1;
  bool no_geotiff = false;
  bool no_mesh_map_h5 = false;
};
/// Adds --robot, --grid-resolution-m, --no-geotiff and --no-mesh-map-h5 to `app`, filling `options`.
void addTraversabilityExportOptions(CLI::App& app, TraversabilityExportOptions& options);
/// @throw std::invalid_argument for a bad grid resolution.
traversability::ExportConfig exportConfigFrom(const TraversabilityExportOptions& options);
/// Loads --robot (which must be given) and validates it.
/// @throw terramesh::InputError naming the file and key; std::invalid_argument for a range error.
traversability::RobotProfile robotFrom(const TraversabilityExportOptions& options);

/// The options of `mesh --robot`: the exports, and how often to rewrite them.
struct TraversabilitySessionOptions {
  TraversabilityExportOptions exports;
  std::size_t export_every = 0;  ///< keyframes between exports (0: only at the end)
};
/// Up estimated from a stream's keyframe rotations (traversability::estimateUpFromCameras with the
/// stream's sensor_up_S), and how ("estimated from N keyframe rotations").
struct StreamUp {
  Eigen::Vector3d up_W;
  std::string source;
};
/// nullopt if the stream has no keyframe.
std::optional<StreamUp> upFromKeyframes(const datasets::SlamStream& stream);
/// The map's up for `profile` on `stream`: the profile's gravity, else upFromKeyframes.
/// @throw std::invalid_argument if neither gives one.
StreamUp mapUpFor(const traversability::RobotProfile& profile, const datasets::SlamStream& stream);

/// Parses "X,Y,Z" (the --up option).
/// @throw UsageError naming the option.
Eigen::Vector3d parseUpVector(const std::string& text);

class TraversabilitySession {
 public:
  /// Adds --robot (which enables the session) and --export-every, plus the export options.
  static void addOptions(CLI::App& app, TraversabilitySessionOptions& options);

  /// nullopt without --robot. Up: the profile's gravity, else estimated from every keyframe's
  /// rotation in the stream (estimateUpFromCameras). Validates everything before any output.
  /// @throw UsageError, InputError or std::invalid_argument for bad options, robot or frame.
  static std::optional<TraversabilitySession> fromOptions(const TraversabilitySessionOptions& options,
                                                          const datasets::SlamStream& stream, double metres_per_unit,
                                                          std::filesystem::path output);

  /// Brings the layers up to date with the mesher after one stream event (delta or, when the
  /// history is gone, a full reset), and exports every K keyframes.
  void afterEvent(const mesher::Mesher& mesher, std::size_t event_index, bool is_keyframe);
  /// Continues a run resumed from a checkpoint after `keyframes` keyframes: the layers are rebuilt
  /// from the mesher's surface (reset equals any sequence of deltas exactly, see
  /// TraversabilityMap::apply), so they are those the interrupted run held.
  void resume(const mesher::Mesher& mesher, std::size_t keyframes);
  /// Final update and export; appends a few summary lines.
  void finish(const mesher::Mesher& mesher, std::ostream& summary);

  /// Where the robot stood on the driven-ground samples and how high its sensor rode
  /// (TraversabilityMap::setDrivePoses); set before the first event.
  void setDrivePoses(traversability::DrivePoseLookup lookup, double sensor_height_m) {
    map_->setDrivePoses(std::move(lookup), sensor_height_m);
  }
  /// Called after every export with the map just written and the mesher revision it holds (e.g.
  /// a tile's owned part written elsewhere, mesh --tile).
  using ExportHook = std::function<void(const traversability::LayeredMesh& map, std::uint64_t revision)>;
  void setExportHook(ExportHook hook) { export_hook_ = std::move(hook); }
  /// The map as it stands (its faces, layers and keys).
  traversability::LayeredMesh snapshot() const { return map_->snapshot(); }
  /// The export settings (grid, GeoTIFF, HDF5).
  const traversability::ExportConfig& exportConfig() const { return config_; }
  /// Where "up" came from, for the summary.
  const std::string& upSource() const { return up_source_; }
  const traversability::RobotProfile& profile() const { return profile_; }
  /// Up and scale of the map.
  const traversability::MapFrame& frame() const { return map_->frame(); }

 private:
  TraversabilitySession(traversability::RobotProfile profile, traversability::MapFrame frame,
                        traversability::ExportConfig config, std::filesystem::path output, std::size_t export_every,
                        std::string up_source);
  void update(const mesher::Mesher& mesher, const std::string& event);
  traversability::ExportReport exportNow();

  traversability::RobotProfile profile_;
  traversability::ExportConfig config_;
  std::filesystem::path output_;
  std::size_t export_every_ = 0;
  std::string up_source_;
  std::unique_ptr<traversability::TraversabilityMap> map_;
  std::uint64_t revision_ = 0;
  std::size_t keyframes_ = 0;
  std::size_t exports_ = 0;
  std::uint64_t exported_revision_ = 0;
  traversability::ExportReport last_report_;
  std::size_t full_rebuilds_ = 0;
  std::size_t unconfirmed_points_ = 0;  ///< after the last update
  double update_seconds_ = 0;
  double export_seconds_ = 0;
  std::ostringstream csv_;
  ExportHook export_hook_;
};

}  // namespace terramesh::cli
