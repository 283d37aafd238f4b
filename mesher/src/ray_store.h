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
  kRayMarked = 1u << 3,      ///< scratch: member of the batch being processed
  kRayPartial = 1u << 4,     ///< `path` is a still-valid prefix; the walk resumes from its end
  /// `path` is a still-valid prefix [0, gap) and a still-valid tail [gap, end); the walk between
  /// them is redone (from the prefix's last cell until it enters the tail's first).
  kRayGap = 1u << 5,
};

/// How a ray's path was walked: straight from the camera, or from a displaced camera.
inline constexpr std::uint8_t kWalkedStraight = 0;

/// A camera-to-point visibility ray and the cells its segment crosses (camera end first).
struct Ray {
  std::uint32_t point = kNone;     ///< PointRegistry index
  std::uint32_t keyframe = kNone;  ///< KeyframeRegistry index
  std::uint8_t flags = 0;
  /// kWalkedStraight, or 1 + the displacement used for a degenerate ray (see RayWalker).
  std::uint8_t walk = kWalkedStraight;
  /// With kRayGap: where the tail starts in `path`.
  std::uint32_t gap = 0;
  std::vector<CellHandle> path;
  /// slots[i]: where this ray's entry sits in the ray list of path[i] (for O(1) removal).
  std::vector<std::uint32_t> slots;

  bool alive() const { return point != kNone; }
};

/// One entry of a cell's ray list: the ray, and which step of its path the cell is.
struct Crossing {
  RayId ray;
  std::uint32_t step;
};

/// Rays with their paths, and for every crossed cell the list of rays crossing it (the inverse
/// index that tells which rays to retrace when cells are destroyed). Path steps and list entries
/// point at each other, so a crossing is added or removed in O(1). Ray ids and list slots are
/// recycled.
class RayStore {
 public:
  RayId create(std::uint32_t point, std::uint32_t keyframe);
  /// Frees a ray. Requires its path empty.
  void destroy(RayId id);

  Ray& operator[](RayId id) { return rays_[id]; }
  const Ray& operator[](RayId id) const { return rays_[id]; }
  std::size_t slotCount() const { return rays_.size(); }
  std::size_t size() const { return rays_.size() - free_rays_.size(); }

  /// Enters path[from, end) of a ray (just appended by a walk) into the cells' ray lists.
  void registerPath(RayId id, std::size_t from);
  /// Shortens a ray's path to its first `length` steps, leaving the dropped cells' lists.
  void truncatePath(RayId id, std::size_t length) { erasePath(id, length, rays_[id].path.size()); }
  void clearPath(RayId id) { truncatePath(id, 0); }
  /// Removes path[from, to) of a ray, leaving those cells' lists; the steps after it move down.
  void erasePath(RayId id, std::size_t from, std::size_t to);
  /// Inserts `cells` into a ray's path before step `at`, entering them into the cells' lists; the
  /// steps from `at` on move up.
  void insertPath(RayId id, std::size_t at, const std::vector<CellHandle>& cells);

  /// Rays crossing `cell` (empty when none).
  const std::vector<Crossing>& crossing(const CellHandle& cell) const;

  /// Estimated bytes held: ray records, path entries, per-cell list entries and slots. O(1).
  std::size_t memoryBytes() const;
  /// Cells on stored paths, summed over rays. O(1).
  std::size_t totalCrossings() const { return path_entries_; }

 private:
  friend class CheckpointAccess;

  /// Enters path[step] of a ray into that cell's list (slots[step] set, grown if needed).
  void enterList(Ray& ray, RayId id, std::size_t step);
  /// Rewrites the step of every list entry of path[from, end) (after steps moved).
  void renumberFrom(const Ray& ray, std::size_t from);

  std::vector<Ray> rays_;
  std::vector<RayId> free_rays_;
  std::vector<std::vector<Crossing>> lists_;
  std::vector<std::uint32_t> free_lists_;
  std::vector<Crossing> empty_;
  std::size_t path_entries_ = 0;
};

}  // namespace terramesh::mesher::internal
