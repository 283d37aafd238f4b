#pragma once

#include <vector>

#include "map_state.h"
#include "ray_walk.h"

namespace terramesh::mesher::internal {

/// Adds and withdraws the votes of rays: walks their segments, keeps paths, per-cell ray lists,
/// crossing counts and weights in step. Weight changes are applied per batch, on the topology the
/// batch walked, so weights always equal a recomputation from the crossing counts.
class VisibilityTracer {
 public:
  explicit VisibilityTracer(MapState& state)
      : state_(state), walker_(state.tri, state.config.next_cell_cache) {}

  /// Withdraws the votes of the traced rays in `batch` (untraced rays are skipped). Their paths are
  /// cleared; flags other than kRayTraced are kept.
  void untrace(const std::vector<RayId>& batch);

  /// Walks and votes for every untraced ray in `batch`; clears kRayNeedsTrace and kRayNewSegment.
  void trace(const std::vector<RayId>& batch, WalkCounters& counters);

  /// Where the camera of keyframe `keyframe` lies now (updates the keyframe's hint).
  CameraLocation locateCamera(std::uint32_t keyframe);

  /// Walks a ray without storing anything (invariant checks).
  void walkOnly(const Ray& ray, std::vector<CellHandle>& path, WalkCounters& counters);

 private:
  /// Remembers the crossing count of `cell` before this batch changed it.
  void noteChange(const CellHandle& cell, std::uint32_t mark);
  void applyChanges();

  MapState& state_;
  RayWalker walker_;
  struct Change {
    CellHandle cell;
    std::uint32_t crossings_before;
    std::uint32_t spreading_before;
  };
  std::vector<Change> changed_;
  std::vector<RayId> order_;
};

}  // namespace terramesh::mesher::internal
