#pragma once

#include <cstddef>

namespace terramesh::mesher {

/// Wall-clock seconds spent in each step of one update, as in the paper's Table II.
struct StepTimes {
  double steiner_s = 0;      ///< growing the Steiner grid
  double shrink_s = 0;       ///< enclosing set and shrinking
  double insertion_s = 0;    ///< point removal and insertion in the triangulation
  double ray_tracing_s = 0;  ///< trace, retrace and untrace, weight updates
  double grow_s = 0;         ///< manifold growing and the genus pass
  double total_s = 0;        ///< the whole update

  StepTimes& operator+=(const StepTimes& other);
};

/// What one update did. Returned by every Mesher update; never logged.
struct UpdateStats {
  std::size_t new_points = 0;        ///< points inserted for the first time
  std::size_t moved_points = 0;      ///< points removed and re-inserted at a new estimate
  std::size_t removed_points = 0;    ///< points removed from the triangulation
  std::size_t dropped_points = 0;    ///< insertions refused: conflict zone still touched O
  std::size_t duplicate_points = 0;  ///< insertions refused: a vertex already at that position
  std::size_t deferred_points = 0;   ///< moves/removals postponed: the star still touched O
  std::size_t steiner_points = 0;    ///< Steiner vertices added
  std::size_t steiner_released = 0;  ///< Steiner vertices let go (Mesher::releaseFarSteiner)

  /// Input filters (MesherConfig::max_camera_distance_m and min_views).
  std::size_t observations = 0;  ///< point observations in the keyframes of this update
  /// ... farther than max_camera_distance_m from their keyframe's camera: no ray, and the view
  /// does not count towards min_views
  std::size_t observations_too_far = 0;
  /// Points this update looked at and left out of the triangulation for now: fewer than
  /// min_views of their keyframes within max_camera_distance_m (a point counts again in each
  /// update that touches it while it waits)
  std::size_t points_waiting = 0;
  /// ... of which seen by min_views keyframes or more, too many of them too far away
  std::size_t points_waiting_too_far = 0;

  std::size_t rays_traced = 0;     ///< rays walked for the first time (new observations)
  std::size_t rays_retraced = 0;   ///< stored rays walked again after cells they used changed
  std::size_t rays_untraced = 0;   ///< rays whose votes were withdrawn for good
  std::size_t rays_skipped = 0;    ///< observations without a ray (degenerate: zero length)

  std::size_t enclosing_cells = 0;       ///< outside cells in the enclosing set
  std::size_t cells_shrunk = 0;          ///< cells taken out of O before insertion
  std::size_t steiner_cells_shrunk = 0;  ///< ... of which with a Steiner vertex
  std::size_t cells_grown = 0;           ///< cells added to O by growing
  std::size_t genus_pass_cells = 0;      ///< ... of which added by the per-vertex pass
  std::size_t edge_pass_cells = 0;       ///< ... of which added by the edge pass (rings of an edge)
  /// Hashed vertices examined to find those of the enclosing set and of the grown region (local
  /// enclosing set only): the region's buckets with the boundary hash, every vertex without it
  std::size_t boundary_vertices_examined = 0;

  std::size_t walk_steps = 0;        ///< cells entered by ray walks
  std::size_t cache_lookups = 0;     ///< steps where a next-cell cache entry was available
  std::size_t cache_hits = 0;        ///< ... and named the right next cell
  std::size_t walk_fallbacks = 0;    ///< degenerate rays walked from a displaced camera
  std::size_t walk_failures = 0;     ///< rays no displacement could walk (left without votes)
  /// Walks cut by the step bound (cells + 1; a straight walk enters no cell twice): always 0
  /// unless the triangulation is corrupt; such a ray is walked again from a displaced camera.
  std::size_t walk_step_limit_hits = 0;

  StepTimes time;

  UpdateStats& operator+=(const UpdateStats& other);
};

}  // namespace terramesh::mesher
