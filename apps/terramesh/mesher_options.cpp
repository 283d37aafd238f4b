#include "mesher_options.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>

namespace terramesh::cli {

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

/// Parses "X,Y,Z" (three finite numbers) for --steiner-origin-offset-m.
Eigen::Vector3d parseOffset(const std::string& text) {
  Eigen::Vector3d offset;
  std::size_t start = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t comma = axis < 2 ? text.find(',', start) : text.size();
    std::size_t used = 0;
    const std::string field = comma == std::string::npos ? std::string() : text.substr(start, comma - start);
    try {
      offset[axis] = std::stod(field, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (field.empty() || used != field.size() || !std::isfinite(offset[axis])) {
      throw UsageError("--steiner-origin-offset-m: expected three numbers X,Y,Z (metres), got \"" + text + "\"");
    }
    start = comma + 1;
  }
  return offset;
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

void addMesherOptions(CLI::App& app, MesherOptions& options) {
  app.add_option("--metres-per-unit", options.metres_per_unit,
                 "size of one map unit in metres (default: from the stream, else 1; about 16.59 for the ORB-SLAM "
                 "KITTI 00 export)")
      ->option_text("S");
  app.add_option("--min-views", options.min_views,
                 "keyframes that must see a point before it is inserted (default 2, or what the stream advises: "
                 "1 for LiDAR)")
      ->option_text("N");
  app.add_option("--max-distance-m", options.max_distance_m,
                 "ignore observations farther than D metres from their camera; auto: twice the 95th percentile "
                 "of the stream's camera-to-point distances (default for COLMAP, OpenMVG and Bundler models "
                 "without --metres-per-unit; else 40)")
      ->option_text("D|auto")
      ->check(CLI::Number | CLI::IsMember({"auto"}));
  app.add_option("--steiner-step-m", options.steiner_step_m,
                 "spacing of the Steiner grid (default 10, or what the stream advises: 2 for LiDAR)")
      ->option_text("M");
  app.add_option("--free-threshold", options.free_threshold,
                 "a cell is free space when its weight exceeds this (default 20; 0 in litvinov13)")
      ->option_text("T");
  app.add_option("--move-threshold-m", options.move_threshold_m, "moves of a point up to this are ignored");
  app.add_option("--point-policy", options.point_policy,
                 "exact-moves: inserted points follow their SLAM estimates (default in proposed); fixed: inserted "
                 "once, never moved (default in the baselines, as the paper ran them)")
      ->option_text("P");
  app.add_option("--spread-cap", options.spread_cap,
                 "crossings of a neighbour that count towards a cell's weight; 0: all (default 1; 0 in "
                 "romanoni15, as its authors' code)")
      ->option_text("N");
  app.add_option("--enclosing-radius-cells", options.enclosing_radius_cells,
                 "proposed: the enclosing set spans the Steiner cells within N cells of a changed point");
  app.add_option("--camera-enclosing-radius-cells", options.camera_enclosing_radius_cells,
                 "proposed: and those within N cells of the update's cameras (0: off, as in the paper; 2 carves "
                 "more accurately near the camera at some cost, see docs/accuracy.md)");
  app.add_option("--handle-min-rays", options.handle_min_rays,
                 "proposed: a pass that would add a handle (tunnel) to the surface needs a cell crossed by N "
                 "rays (0: off)")
      ->option_text("N");
  app.add_option("--disable", options.disable,
                 "ablation: comma-separated techniques to switch off: incremental-steiner-grid, "
                 "local-enclosing-set, boundary-hash, next-cell-cache, ray-scheduler, edge-pass")
      ->option_text("LIST");
  app.add_option("--steiner-origin-offset-m", options.steiner_origin_offset_m,
                 "experiment: shift the Steiner lattice by X,Y,Z metres from where the mesher places it "
                 "(default 0,0,0; for studying how its placement changes the surface, docs/accuracy.md)")
      ->option_text("X,Y,Z");
  app.add_option("--steiner-clearance-steps", options.steiner_clearance_steps,
                 "leave out the Steiner nodes closer than F grid steps to a point, in [0, 0.5) (default: the "
                 "mode's; 0 keeps every node, as in the baselines)")
      ->option_text("F");
}

bool autoMaxDistance(const MesherOptions& options, const datasets::SlamStream& stream) {
  if (options.max_distance_m) return *options.max_distance_m == "auto";
  return stream.recommend_auto_max_distance && !options.metres_per_unit;
}

std::vector<std::string> describeInferredSettings(const MesherOptions& options, const datasets::SlamStream& stream,
                                                  const mesher::MesherConfig& config) {
  std::vector<std::string> lines;
  std::ostringstream scale;
  scale << "scale: " << config.metres_per_unit << " m per map unit";
  if (options.metres_per_unit) {
    scale << ", from --metres-per-unit";
  } else if (stream.scale_known) {
    scale << ", as the input states it (--metres-per-unit overrides)";
  } else {
    scale << " assumed: the input states no scale (--metres-per-unit sets it)";
  }
  lines.push_back(scale.str());
  std::string views = "min_views: " + std::to_string(config.min_views);
  if (options.min_views) {
    views += ", from --min-views";
  } else if (stream.recommended_min_views > 0) {
    views += ", as the input advises (--min-views overrides)";
  } else {
    views += ", the mesher's default: the input advises none (--min-views overrides)";
  }
  lines.push_back(views);
  std::ostringstream step;
  step << "Steiner lattice: " << config.steiner_step_m << " m";
  if (options.steiner_step_m) {
    step << ", from --steiner-step-m";
  } else if (stream.recommended_steiner_step_m > 0) {
    step << ", as the input advises (--steiner-step-m overrides)";
  } else {
    step << ", the mesher's default: the input advises none (--steiner-step-m overrides)";
  }
  lines.push_back(step.str());
  const Eigen::Vector3d& up = stream.sensor_up_S;
  std::ostringstream axis;
  // (+ 0.0: no "-0" in the text.)
  axis << "sensor up axis: " << up.x() + 0.0 << "," << up.y() + 0.0 << "," << up.z() + 0.0 << " in the sensor frame"
       << (up == -Eigen::Vector3d::UnitY() ? " (a camera: x right, y down)"
           : up == Eigen::Vector3d::UnitZ() ? " (a scanner: z up)"
                                             : "")
       << ", from the input; up in the map follows from it over every keyframe (the profile's gravity "
          "or traverse's --up overrides)";
  lines.push_back(axis.str());
  return lines;
}

mesher::MesherConfig mesherConfigFrom(const MesherOptions& options, mesher::MesherMode mode,
                                      const datasets::SlamStream& stream) {
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mode);
  config.metres_per_unit = options.metres_per_unit ? *options.metres_per_unit
                           : stream.scale_known    ? stream.metres_per_unit
                                                   : 1.0;
  datasets::applyMeshingAdvice(stream, config);
  if (options.min_views) config.min_views = *options.min_views;
  if (autoMaxDistance(options, stream)) {
    const double distance_units =
        datasets::observationDistanceQuantile(stream, kAutoMaxDistanceQuantile);
    // No observation: nothing to filter, any positive distance will do.
    if (distance_units > 0.0) {
      config.max_camera_distance_m = kAutoMaxDistanceFactor * distance_units * config.metres_per_unit;
    }
  } else if (options.max_distance_m) {
    config.max_camera_distance_m = std::stod(*options.max_distance_m);
  }
  if (options.steiner_step_m) config.steiner_step_m = *options.steiner_step_m;
  if (options.free_threshold) config.free_threshold = *options.free_threshold;
  config.move_threshold_m = options.move_threshold_m;
  if (options.point_policy) {
    const auto policy = mesher::parsePointPolicy(*options.point_policy);
    if (!policy) throw UsageError("--point-policy: expected exact-moves or fixed");
    config.point_policy = *policy;
  }
  if (options.spread_cap) config.spread_cap = *options.spread_cap;
  config.enclosing_radius_cells = options.enclosing_radius_cells;
  config.camera_enclosing_radius_cells = options.camera_enclosing_radius_cells;
  if (options.handle_min_rays) config.handle_min_rays = *options.handle_min_rays;
  if (options.disable) disableTechniques(*options.disable, config);
  if (options.steiner_clearance_steps) config.steiner_clearance_steps = *options.steiner_clearance_steps;
  if (options.steiner_origin_offset_m) config.steiner_origin_offset_m = parseOffset(*options.steiner_origin_offset_m);
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
