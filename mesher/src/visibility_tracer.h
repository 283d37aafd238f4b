#pragma once

#include <utility>
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

  /// Withdraws all votes of the rays in `batch` that have any (untraced rays are skipped). Their
  /// paths are cleared; flags other than kRayTraced and kRayPartial are kept.
  void untrace(const std::vector<RayId>& batch);

  /// The cells of the crossings `doomed` (every crossing of them) are about to be destroyed. For
  /// each ray crossing them, withdraws the votes of the stretch of its path from the first doomed
  /// cell to the last and keeps the rest: a prefix and a tail (flagged kRayGap: both still voting,
  /// the stretch between them to be walked again), or a prefix alone when the last cell is doomed
  /// (flagged kRayPartial: walked on from its end). Rays walked from a displaced camera, or whose
  /// first cell is doomed, lose their whole path. Sorts `doomed`; fills `batch` with the rays.
  void truncateAtDoomed(std::vector<Crossing>& doomed, std::vector<RayId>& batch);

  /// Walks and votes for every ray in `batch` that is not fully traced (resuming partial rays);
  /// clears kRayNeedsTrace and kRayNewSegment.
  void trace(const std::vector<RayId>& batch, WalkCounters& counters);

  /// Where the camera of keyframe `keyframe` lies now (updates the keyframe's hint).
  CameraLocation locateCamera(std::uint32_t keyframe);

  /// Walks a ray without storing anything (invariant checks).
  void walkOnly(const Ray& ray, std::vector<CellHandle>& path, WalkCounters& counters);

 private:
  /// Remembers the crossing count of `cell` before this batch changed it.
  void noteChange(const CellHandle& cell, std::uint32_t mark);
  void applyChanges();
  /// Withdraws the votes of path[from, to) of a ray.
  void withdrawRange(Ray& ray, std::size_t from, std::size_t to, std::uint32_t mark);
  /// The stretch [from, to) of a ray's path that truncateAtDoomed withdraws, given the first and
  /// the last step of it that is doomed.
  std::pair<std::size_t, std::size_t> stretchToWithdraw(const Ray& ray, std::size_t first, std::size_t last) const;
  /// Walks and votes for the stretch of a kRayGap ray between its prefix and its tail. False (the
  /// ray unchanged) if that walk is degenerate.
  bool bridgeGap(RayId id, VertexHandle target, std::uint32_t mark, WalkCounters& counters);
  /// Whether the ray ends at a driven-ground sample (its crossings count as driven_crossings).
  bool drivenRay(const Ray& ray) const;
  /// Votes for path[from, end) of a ray; `complete` when the path now ends at the point.
  void addVotes(RayId id, std::size_t from, std::uint32_t mark);

  MapState& state_;
  RayWalker walker_;
  struct Change {
    CellHandle cell;
    std::uint32_t crossings_before;
    std::uint32_t spreading_before;
  };
  std::vector<Change> changed_;
  std::vector<RayId> order_;
  std::vector<CellHandle> between_;
  std::vector<CellHandle> walked_;

};

}  // namespace terramesh::mesher::internal
