#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "baselines/pcl_surfaces.h"
#include "datasets/slam_stream.h"
#include "mesher/mesher_config.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::cli {

/// One map representation `terramesh compare` builds.
struct MapSpec {
  enum class Kind { kMesher, kOctomap, kPcl };
  Kind kind = Kind::kMesher;
  std::string name;  ///< for tables, e.g. "OctoMap 0.2 m"
  std::string slug;  ///< for file names, e.g. "octomap-0.2"
  mesher::MesherMode mode = mesher::MesherMode::kProposed;
  double resolution_m = 0.2;
  baselines::PclMethod pcl = baselines::PclMethod::kGreedyProjection;
};

/// The methods of a comma-separated list of slugs ("all": every one): proposed, litvinov13,
/// romanoni15, octomap-0.1, octomap-0.2, octomap-0.5, greedy, poisson, marching-cubes.
/// @throw UsageError naming an unknown slug.
std::vector<MapSpec> parseMethods(const std::string& list);

/// What every builder shares.
struct BuildContext {
  const datasets::SlamStream* stream = nullptr;
  /// The mesher's configuration in a mode (from the command's mesher options).
  std::function<mesher::MesherConfig(mesher::MesherMode)> mesher_config;
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  double metres_per_unit = 1.0;
  /// Camera-to-point distance limit of every method, metres (the mesher's max_camera_distance_m).
  double max_distance_m = 40.0;
  int min_views = 2;
  baselines::PclSurfaceConfig pcl;
  /// Where native files and surfaces go.
  std::filesystem::path maps_dir;
};

/// A map as built, and its surface for the surface measures.
struct BuiltMap {
  bool ok = false;
  std::string error;
  double build_s = 0;         ///< the method's own build (insertions, reconstruction)
  double to_surface_s = 0;    ///< turning it into a triangle surface (OctoMap only)
  double peak_rss_mb = 0;     ///< of the child process that built it
  double extra_peak_mb = 0;   ///< ... above what it held at the start
  std::uintmax_t size_bytes = 0;
  std::filesystem::path native_file;   ///< the method's own output (PLY, .bt)
  std::filesystem::path surface_file;  ///< the surface measured, our PLY with `steiner` flags
  std::string parameters;
  /// Map frame and units; is_steiner flags Steiner / unsupported vertices where the method has any.
  mesher::TriangleMesh surface;
};

/// Builds one map in a child process (time and peak memory of that process), writes its native
/// file and surface into context.maps_dir, then reads the surface back.
/// @throw std::runtime_error if the child cannot be started.
BuiltMap buildMap(const MapSpec& spec, const BuildContext& context);

}  // namespace terramesh::cli
