#include "mesher/update_stats.h"

namespace terramesh::mesher {

StepTimes& StepTimes::operator+=(const StepTimes& other) {
  steiner_s += other.steiner_s;
  shrink_s += other.shrink_s;
  insertion_s += other.insertion_s;
  ray_tracing_s += other.ray_tracing_s;
  grow_s += other.grow_s;
  total_s += other.total_s;
  return *this;
}

UpdateStats& UpdateStats::operator+=(const UpdateStats& other) {
  new_points += other.new_points;
  moved_points += other.moved_points;
  removed_points += other.removed_points;
  dropped_points += other.dropped_points;
  duplicate_points += other.duplicate_points;
  deferred_points += other.deferred_points;
  steiner_points += other.steiner_points;
  steiner_released += other.steiner_released;
  observations += other.observations;
  observations_too_far += other.observations_too_far;
  points_waiting += other.points_waiting;
  points_waiting_too_far += other.points_waiting_too_far;
  rays_traced += other.rays_traced;
  rays_retraced += other.rays_retraced;
  rays_untraced += other.rays_untraced;
  rays_skipped += other.rays_skipped;
  enclosing_cells += other.enclosing_cells;
  cells_shrunk += other.cells_shrunk;
  steiner_cells_shrunk += other.steiner_cells_shrunk;
  cells_grown += other.cells_grown;
  genus_pass_cells += other.genus_pass_cells;
  edge_pass_cells += other.edge_pass_cells;
  boundary_vertices_examined += other.boundary_vertices_examined;
  walk_steps += other.walk_steps;
  cache_lookups += other.cache_lookups;
  cache_hits += other.cache_hits;
  walk_fallbacks += other.walk_fallbacks;
  walk_failures += other.walk_failures;
  walk_step_limit_hits += other.walk_step_limit_hits;
  time += other.time;
  return *this;
}

}  // namespace terramesh::mesher
