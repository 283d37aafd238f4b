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
}

void RayStore::removeMarkedCrossings(CellHandle cell) {
  std::uint32_t& slot = cell->info().ray_list;
  if (slot == kNone) return;
  std::vector<RayId>& list = lists_[slot];
  list.erase(std::remove_if(list.begin(), list.end(),
                            [this](RayId id) { return (rays_[id].flags & kRayMarked) != 0; }),
             list.end());
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
  std::size_t bytes = rays_.capacity() * sizeof(Ray) + free_rays_.capacity() * sizeof(RayId) +
                      lists_.capacity() * sizeof(std::vector<RayId>) +
                      free_lists_.capacity() * sizeof(std::uint32_t);
  for (const Ray& ray : rays_) bytes += ray.path.capacity() * sizeof(CellHandle);
  for (const auto& list : lists_) bytes += list.capacity() * sizeof(RayId);
  return bytes;
}

std::size_t RayStore::totalCrossings() const {
  std::size_t total = 0;
  for (const Ray& ray : rays_) total += ray.path.size();
  return total;
}

}  // namespace terramesh::mesher::internal
