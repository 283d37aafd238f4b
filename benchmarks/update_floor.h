// The floor of a keyframe update (docs/benchmarks.md, "The floor"): the work no incremental
// mesher of this kind can skip. Per keyframe: CGAL's batch insertion (spatially sorted) of the
// points that reach `min_views` keyframes in range, then a walk of every ray to an inserted point
// (the mesher's own RayWalker, next-cell cache as configured). No weights, no manifold, no Steiner
// lattice (eight far corners keep every camera inside the hull), no moving or removed points.
#pragma once

#include <cstddef>
#include <vector>

#include "datasets/slam_stream.h"
#include "mesher/mesher_config.h"

namespace terramesh::bench {

struct FloorRun {
  /// Thread CPU per keyframe, milliseconds (insertion and walks; the stream's other events skipped).
  std::vector<double> keyframe_ms;
  std::size_t points_inserted = 0;
  std::size_t rays_walked = 0;
  /// Rays no displacement of the camera resolved (left unwalked; the mesher counts the same).
  std::size_t walk_failures = 0;
};

/// Runs the floor over the first `max_keyframes` keyframes of `stream` (0: all), with the
/// config's `min_views`, `max_camera_distance_m`, `metres_per_unit` and `next_cell_cache`.
/// @throw std::invalid_argument if the stream has no keyframe.
FloorRun measureFloor(const datasets::SlamStream& stream, const mesher::MesherConfig& config,
                      std::size_t max_keyframes);

}  // namespace terramesh::bench
