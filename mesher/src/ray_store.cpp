#include "ray_store.h"

#include <algorithm>
#include <cassert>

namespace terramesh::mesher::internal {

RayId RayStore::create(std::uint32_t point, std::uint32_t keyframe) {
  RayId id;
  if (!free_rays_.empty()) {
    id = free_rays_.back();
    free_rays_.pop_back();
  } else {
    id = static_cast<RayId>(rays_.size());
    rays_.emplace_back();
  }
  Ray& ray = rays_[id];
  ray.point = point;
  ray.keyframe = keyframe;
  ray.flags = 0;
  ray.path.clear();
  return id;
}

void RayStore::destroy(RayId id) {
  Ray& ray = rays_[id];
  assert(!(ray.flags & kRayTraced));
  path_entries_ -= ray.path.size();
  ray.point = kNone;
  ray.keyframe = kNone;
  ray.flags = 0;
  std::vector<CellHandle>().swap(ray.path);
  free_rays_.push_back(id);
}

void RayStore::addCrossing(CellHandle cell, RayId ray) {
  std::uint32_t& slot = cell->info().ray_list;
  if (slot == kNone) {
    if (!free_lists_.empty()) {
      slot = free_lists_.back();
      free_lists_.pop_back();
    } else {
      slot = static_cast<std::uint32_t>(lists_.size());
      lists_.emplace_back();
    }
  }
  lists_[slot].push_back(ray);
  ++list_entries_;
}

void RayStore::clearPath(RayId id) {
  path_entries_ -= rays_[id].path.size();
  rays_[id].path.clear();
}

void RayStore::removeMarkedCrossings(CellHandle cell) {
  std::uint32_t& slot = cell->info().ray_list;
  if (slot == kNone) return;
  std::vector<RayId>& list = lists_[slot];
  const auto end = std::remove_if(list.begin(), list.end(),
                                  [this](RayId id) { return (rays_[id].flags & kRayMarked) != 0; });
  list_entries_ -= static_cast<std::size_t>(list.end() - end);
  list.erase(end, list.end());
  if (list.empty()) {
    std::vector<RayId>().swap(list);
    free_lists_.push_back(slot);
    slot = kNone;
  }
}

const std::vector<RayId>& RayStore::crossing(const CellHandle& cell) const {
  const std::uint32_t slot = cell->info().ray_list;
  return slot == kNone ? empty_ : lists_[slot];
}

std::size_t RayStore::memoryBytes() const {
  // Vectors hold their entries plus an allocator header; capacities are not tracked (that would
  // need a walk over every ray), so entries are counted at their size.
  constexpr std::size_t kAllocationOverhead = 16;
  const std::size_t live_lists = lists_.size() - free_lists_.size();
  return rays_.capacity() * sizeof(Ray) + free_rays_.capacity() * sizeof(RayId) +
         lists_.capacity() * sizeof(std::vector<RayId>) + free_lists_.capacity() * sizeof(std::uint32_t) +
         path_entries_ * sizeof(CellHandle) + size() * kAllocationOverhead +
         list_entries_ * sizeof(RayId) + live_lists * kAllocationOverhead;
}

}  // namespace terramesh::mesher::internal
