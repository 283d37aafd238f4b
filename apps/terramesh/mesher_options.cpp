#include "mesher_options.h"

#include <algorithm>
#include <limits>

namespace terramesh::cli {

void declareMesherOptions(ArgParser& parser) {
  parser
      .option("--metres-per-unit", "S",
              "size of one map unit in metres (default: from the stream, else 1; about 16.59 for "
              "the ORB-SLAM KITTI 00 export)")
      .option("--min-views", "N",
              "keyframes that must see a point before it is inserted (default 2, or what the "
              "stream advises: 1 for LiDAR)")
      .option("--max-distance-m", "D",
              "ignore observations farther than D metres from their camera; auto: twice the 95th "
              "percentile of the stream's camera-to-point distances (default for COLMAP, OpenMVG "
              "and Bundler models without --metres-per-unit; else 40)")
      .option("--steiner-step-m", "L", "spacing of the Steiner grid", "10")
      .option("--free-threshold", "T", "a cell is free space when its weight exceeds this "
              "(default 20; 0 in litvinov13)")
      .option("--move-threshold-m", "M", "moves of a point up to this are ignored", "0")
      .option("--enclosing-radius-cells", "N",
              "proposed: the enclosing set spans the Steiner cells within N cells of a changed point", "2")
      .option("--camera-enclosing-radius-cells", "N",
              "proposed: and those within N cells of the update's cameras (0: off, as in the paper; "
              "2 carves more accurately near the camera at some cost, see docs/accuracy.md)", "0")
      .option("--disable", "LIST",
              "ablation: comma-separated techniques to switch off: incremental-steiner-grid, "
              "local-enclosing-set, boundary-hash, next-cell-cache, ray-scheduler, edge-pass");
}

namespace {

/// Switches off the techniques named in `list` (comma-separated).
void disableTechniques(const std::string& list, mesher::MesherConfig& config) {
  const std::pair<const char*, bool mesher::MesherConfig::*> switches[] = {
      {"incremental-steiner-grid", &mesher::MesherConfig::incremental_steiner_grid},
      {"local-enclosing-set", &mesher::MesherConfig::local_enclosing_set},
      {"boundary-hash", &mesher::MesherConfig::boundary_hash},
      {"next-cell-cache", &mesher::MesherConfig::next_cell_cache},
      {"ray-scheduler", &mesher::MesherConfig::ray_scheduler},
      {"edge-pass", &mesher::MesherConfig::edge_growing_pass}};
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    bool known = false;
    for (const auto& [technique, member] : switches) {
      if (name == technique) {
        config.*member = false;
        known = true;
      }
    }
    if (!known) throw UsageError("--disable: unknown technique \"" + name + "\"");
    start = comma + 1;
  }
}

}  // namespace

mesher::AxisAlignedBox streamBounds(const datasets::SlamStream& stream) {
  mesher::AxisAlignedBox box;
  box.min_W.setConstant(std::numeric_limits<double>::infinity());
  box.max_W.setConstant(-std::numeric_limits<double>::infinity());
  auto extend = [&box](const Eigen::Vector3d& p) {
    box.min_W = box.min_W.cwiseMin(p);
    box.max_W = box.max_W.cwiseMax(p);
  };
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      extend(keyframe->position_W_C);
      for (const auto& observation : keyframe->observations) extend(observation.position_W);
    }
  }
  if (!box.min_W.allFinite()) {
    box.min_W.setZero();
    box.max_W.setZero();
  }
  return box;
}

bool autoMaxDistance(const ArgParser& parser, const datasets::SlamStream& stream) {
  if (parser.has("--max-distance-m")) return parser.get("--max-distance-m") == "auto";
  return stream.recommend_auto_max_distance && !parser.has("--metres-per-unit");
}

mesher::MesherConfig mesherConfigFromArgs(const ArgParser& parser, mesher::MesherMode mode,
                                          const datasets::SlamStream& stream) {
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mode);
  config.metres_per_unit = parser.has("--metres-per-unit") ? parser.getDouble("--metres-per-unit")
                           : stream.scale_known             ? stream.metres_per_unit
                                                            : 1.0;
  if (parser.has("--min-views")) {
    config.min_views = static_cast<int>(parser.getInt("--min-views"));
  } else if (stream.recommended_min_views > 0) {
    config.min_views = stream.recommended_min_views;
  }
  if (autoMaxDistance(parser, stream)) {
    const double distance_units =
        datasets::observationDistanceQuantile(stream, kAutoMaxDistanceQuantile);
    // No observation: nothing to filter, any positive distance will do.
    if (distance_units > 0.0) {
      config.max_camera_distance_m = kAutoMaxDistanceFactor * distance_units * config.metres_per_unit;
    }
  } else if (parser.has("--max-distance-m")) {
    config.max_camera_distance_m = parser.getDouble("--max-distance-m");
  }
  config.steiner_step_m = parser.getDouble("--steiner-step-m");
  if (parser.has("--free-threshold")) config.free_threshold = parser.getDouble("--free-threshold");
  config.move_threshold_m = parser.getDouble("--move-threshold-m");
  config.enclosing_radius_cells = static_cast<int>(parser.getInt("--enclosing-radius-cells"));
  config.camera_enclosing_radius_cells = static_cast<int>(parser.getInt("--camera-enclosing-radius-cells"));
  if (parser.has("--disable")) disableTechniques(parser.get("--disable"), config);
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = streamBounds(stream);
  const std::vector<std::string> problems = config.problems();
  if (!problems.empty()) {
    std::string message = "invalid options:";
    for (const std::string& problem : problems) message += " " + problem + ";";
    message.pop_back();
    throw UsageError(message);
  }
  return config;
}

}  // namespace terramesh::cli
