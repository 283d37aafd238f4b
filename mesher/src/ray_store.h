#pragma once

#include <cstdint>
#include <vector>

#include "cgal_types.h"

namespace terramesh::mesher::internal {

using RayId = std::uint32_t;

enum RayFlag : std::uint8_t {
  kRayTraced = 1u << 0,      ///< votes are in the cells of `path`
  kRayNeedsTrace = 1u << 1,  ///< must be (re)walked at the end of the update
  kRayNewSegment = 1u << 2,  ///< its segment is new or changed since it was last traced
  kRayMarked = 1u << 3,      ///< scratch: member of the batch being untraced
};

/// A camera-to-point visibility ray and the cells its segment crosses (camera end first).
struct Ray {
  std::uint32_t point = kNone;     ///< PointRegistry index
  std::uint32_t keyframe = kNone;  ///< KeyframeRegistry index
  std::uint8_t flags = 0;
  std::vector<CellHandle> path;

  bool alive() const { return point != kNone; }
};

/// Rays with their paths, and for every crossed cell the list of rays crossing it (the inverse
/// index that tells which rays to retrace when cells are destroyed). Ray ids and list slots are
/// recycled.
class RayStore {
 public:
  RayId create(std::uint32_t point, std::uint32_t keyframe);
  /// Frees a ray. Requires it untraced.
  void destroy(RayId id);

  Ray& operator[](RayId id) { return rays_[id]; }
  const Ray& operator[](RayId id) const { return rays_[id]; }
  std::size_t slotCount() const { return rays_.size(); }
  std::size_t size() const { return rays_.size() - free_rays_.size(); }

  /// Records that `ray` crosses `cell` (the ray's path holds the cell too: see setPath).
  void addCrossing(CellHandle cell, RayId ray);
  /// Clears a ray's path, keeping the crossing totals in step.
  void clearPath(RayId id);
  /// Accounts for a path just filled by a walk (its size joins the crossing totals).
  void notePathFilled(RayId id) { path_entries_ += rays_[id].path.size(); }
  /// Removes every ray flagged kRayMarked from the list of `cell`; frees the list when empty.
  void removeMarkedCrossings(CellHandle cell);
  /// Rays crossing `cell` (empty when none).
  const std::vector<RayId>& crossing(const CellHandle& cell) const;

  /// Estimated bytes held: ray records, path entries, per-cell list entries and slots. O(1).
  std::size_t memoryBytes() const;
  /// Cells on stored paths, summed over rays. O(1).
  std::size_t totalCrossings() const { return path_entries_; }

 private:
  std::vector<Ray> rays_;
  std::vector<RayId> free_rays_;
  std::vector<std::vector<RayId>> lists_;
  std::vector<std::uint32_t> free_lists_;
  std::vector<RayId> empty_;
  std::size_t path_entries_ = 0;
  std::size_t list_entries_ = 0;
};

}  // namespace terramesh::mesher::internal
