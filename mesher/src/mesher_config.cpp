#include "mesher/mesher_config.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace terramesh::mesher {

const char* toString(MesherMode mode) {
  switch (mode) {
    case MesherMode::kProposed:
      return "proposed";
    case MesherMode::kLitvinov13:
      return "litvinov13";
    case MesherMode::kRomanoni15:
      return "romanoni15";
  }
  return "unknown";
}

std::optional<MesherMode> parseMesherMode(const std::string& name) {
  for (MesherMode mode : {MesherMode::kProposed, MesherMode::kLitvinov13, MesherMode::kRomanoni15}) {
    if (name == toString(mode)) return mode;
  }
  return std::nullopt;
}

const char* toString(PointPolicy policy) {
  switch (policy) {
    case PointPolicy::kExactMoves:
      return "exact-moves";
    case PointPolicy::kFixedPosition:
      return "fixed";
  }
  return "unknown";
}

std::optional<PointPolicy> parsePointPolicy(const std::string& name) {
  for (PointPolicy policy : {PointPolicy::kExactMoves, PointPolicy::kFixedPosition}) {
    if (name == toString(policy)) return policy;
  }
  return std::nullopt;
}

MesherConfig MesherConfig::forMode(MesherMode mode) {
  MesherConfig config;
  config.setMode(mode);
  return config;
}

void MesherConfig::setMode(MesherMode mode) {
  // Every mode-dependent setting is assigned here, from the proposed mode's defaults, so that a
  // config can be switched from one mode to another.
  const MesherConfig proposed_defaults;
  mode_ = mode;
  weight_crossed = proposed_defaults.weight_crossed;
  weight_neighbour = proposed_defaults.weight_neighbour;
  weight_second_neighbour = proposed_defaults.weight_second_neighbour;
  spread_cap = proposed_defaults.spread_cap;
  free_threshold = proposed_defaults.free_threshold;
  point_policy = proposed_defaults.point_policy;
  incremental_steiner_grid = proposed_defaults.incremental_steiner_grid;
  local_enclosing_set = proposed_defaults.local_enclosing_set;
  boundary_hash = proposed_defaults.boundary_hash;
  next_cell_cache = proposed_defaults.next_cell_cache;
  ray_scheduler = proposed_defaults.ray_scheduler;
  edge_growing_pass = proposed_defaults.edge_growing_pass;
  handle_min_rays = proposed_defaults.handle_min_rays;
  steiner_clearance_steps = proposed_defaults.steiner_clearance_steps;
  if (mode == MesherMode::kProposed) return;
  // The baselines as the paper ran them: none of its techniques, and points inserted once at a
  // fixed position.
  incremental_steiner_grid = false;
  local_enclosing_set = false;
  boundary_hash = false;
  next_cell_cache = false;
  ray_scheduler = false;
  edge_growing_pass = false;
  handle_min_rays = 0;
  steiner_clearance_steps = 0.0;
  point_policy = PointPolicy::kFixedPosition;
  if (mode == MesherMode::kLitvinov13) {
    // Litvinov & Lhuillier 2013: ray counts; a cell is free space once any ray crosses it.
    weight_crossed = 1.0;
    weight_neighbour = 0.0;
    weight_second_neighbour = 0.0;
    free_threshold = 0.0;
  } else {
    // Romanoni & Matteucci 2015: inverse-cone weights, every crossing of a neighbour spreads.
    spread_cap = 0;
  }
}

std::vector<std::string> MesherConfig::problems() const {
  std::vector<std::string> found;
  auto require = [&found](bool ok, const std::string& message) {
    if (!ok) found.push_back(message);
  };
  auto finite = [](double value) { return std::isfinite(value); };
  require(finite(metres_per_unit) && metres_per_unit > 0, "metres_per_unit must be positive");
  require(min_views >= 1, "min_views must be at least 1");
  require(finite(max_camera_distance_m) && max_camera_distance_m > 0,
          "max_camera_distance_m must be positive");
  require(finite(steiner_step_m) && steiner_step_m > 0, "steiner_step_m must be positive");
  require(enclosing_radius_cells >= 1 && enclosing_radius_cells <= 8,
          "enclosing_radius_cells must be in [1, 8]");
  require(std::isfinite(edge_pass_min_weight) && edge_pass_min_weight >= 0 && edge_pass_min_weight <= 1e6,
          "edge_pass_min_weight must be in [0, 1e6]");
  require(handle_min_rays >= 0 && handle_min_rays <= 1000000, "handle_min_rays must be in [0, 1000000]");
  require(surface_history_max_bytes >= (std::size_t{1} << 16) && surface_history_max_bytes <= (std::size_t{1} << 40),
          "surface_history_max_bytes must be in [65536, 2^40] (64 KiB to 1 TiB)");
  require(camera_enclosing_radius_cells >= 0 && camera_enclosing_radius_cells <= 8,
          "camera_enclosing_radius_cells must be in [0, 8]");
  require(steiner_margin_cells >= 1 && steiner_margin_cells <= 16,
          "steiner_margin_cells must be in [1, 16]");
  require(std::isfinite(steiner_clearance_steps) && steiner_clearance_steps >= 0 && steiner_clearance_steps < 0.5,
          "steiner_clearance_steps must be in [0, 0.5)");
  require(steiner_origin_offset_m.allFinite() && steiner_origin_offset_m.cwiseAbs().maxCoeff() <= 1e4,
          "steiner_origin_offset_m must be finite, each component in [-10000, 10000]");
  for (const auto& [value, name] : {std::pair{weight_crossed, "weight_crossed"},
                                    std::pair{weight_neighbour, "weight_neighbour"},
                                    std::pair{weight_second_neighbour, "weight_second_neighbour"}}) {
    require(finite(value) && value >= 0 && value <= 1e4,
            std::string(name) + " must be in [0, 10000]");
  }
  require(!(weight_crossed <= 0), "weight_crossed must be positive");
  require(spread_cap >= 0, "spread_cap must be non-negative (0 means no cap)");
  require(finite(free_threshold) && free_threshold >= 0, "free_threshold must be non-negative");
  require(finite(move_threshold_m) && move_threshold_m >= 0, "move_threshold_m must be non-negative");
  require(driven_ground_up_W.allFinite() &&
              (driven_ground_up_W.isZero(0) || std::abs(driven_ground_up_W.norm() - 1.0) <= 1e-6),
          "driven_ground_up_W must be zero or a unit vector");
  require(finite(driven_underside_depth_m) && driven_underside_depth_m >= 0 && driven_underside_depth_m <= 10,
          "driven_underside_depth_m must be in [0, 10]");
  if (!incremental_steiner_grid) {
    require(fixed_grid_bounds_W.has_value(),
            "fixed_grid_bounds_W is required when incremental_steiner_grid is off");
    if (fixed_grid_bounds_W) {
      const auto& box = *fixed_grid_bounds_W;
      require(box.min_W.allFinite() && box.max_W.allFinite() &&
                  (box.max_W.array() >= box.min_W.array()).all(),
              "fixed_grid_bounds_W must be finite with max >= min");
    }
  }
  return found;
}

void MesherConfig::validate() const {
  const std::vector<std::string> found = problems();
  if (found.empty()) return;
  std::ostringstream message;
  message << "invalid MesherConfig: ";
  for (std::size_t i = 0; i < found.size(); ++i) message << (i ? "; " : "") << found[i];
  throw std::invalid_argument(message.str());
}

}  // namespace terramesh::mesher
