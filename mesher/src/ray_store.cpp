#include "ray_store.h"

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
  ray.walk = kWalkedStraight;
  ray.path.clear();
  ray.slots.clear();
  return id;
}

void RayStore::destroy(RayId id) {
  Ray& ray = rays_[id];
  assert(ray.path.empty() && !(ray.flags & kRayTraced));
  ray.point = kNone;
  ray.keyframe = kNone;
  ray.flags = 0;
  std::vector<CellHandle>().swap(ray.path);
  std::vector<std::uint32_t>().swap(ray.slots);
  free_rays_.push_back(id);
}

void RayStore::registerPath(RayId id, std::size_t from) {
  Ray& ray = rays_[id];
  assert(ray.slots.size() == from);
  ray.slots.reserve(ray.path.size());
  for (std::size_t step = from; step < ray.path.size(); ++step) enterList(ray, id, step);
  path_entries_ += ray.path.size() - from;
}

void RayStore::enterList(Ray& ray, RayId id, std::size_t step) {
  std::uint32_t& slot = ray.path[step]->info().ray_list;
  if (slot == kNone) {
    if (!free_lists_.empty()) {
      slot = free_lists_.back();
      free_lists_.pop_back();
    } else {
      slot = static_cast<std::uint32_t>(lists_.size());
      lists_.emplace_back();
    }
  }
  std::vector<Crossing>& list = lists_[slot];
  if (ray.slots.size() <= step) ray.slots.resize(step + 1);
  ray.slots[step] = static_cast<std::uint32_t>(list.size());
  list.push_back({id, static_cast<std::uint32_t>(step)});
}

void RayStore::renumberFrom(const Ray& ray, std::size_t from) {
  for (std::size_t step = from; step < ray.path.size(); ++step) {
    lists_[ray.path[step]->info().ray_list][ray.slots[step]].step = static_cast<std::uint32_t>(step);
  }
}

void RayStore::erasePath(RayId id, std::size_t from, std::size_t to) {
  Ray& ray = rays_[id];
  assert(from <= to && to <= ray.path.size() && ray.slots.size() == ray.path.size());
  if (from == to) return;
  for (std::size_t step = from; step < to; ++step) {
    std::uint32_t& list_slot = ray.path[step]->info().ray_list;
    std::vector<Crossing>& list = lists_[list_slot];
    const std::uint32_t position = ray.slots[step];
    assert(position < list.size() && list[position].ray == id);
    // Move the last entry into the hole and tell its ray where it went.
    const Crossing moved = list.back();
    list[position] = moved;
    rays_[moved.ray].slots[moved.step] = position;
    list.pop_back();
    if (list.empty()) {
      std::vector<Crossing>().swap(list);
      free_lists_.push_back(list_slot);
      list_slot = kNone;
    }
  }
  path_entries_ -= to - from;
  const auto first = static_cast<std::ptrdiff_t>(from), last = static_cast<std::ptrdiff_t>(to);
  ray.path.erase(ray.path.begin() + first, ray.path.begin() + last);
  ray.slots.erase(ray.slots.begin() + first, ray.slots.begin() + last);
  renumberFrom(ray, from);
}

void RayStore::insertPath(RayId id, std::size_t at, const std::vector<CellHandle>& cells) {
  Ray& ray = rays_[id];
  assert(at <= ray.path.size() && ray.slots.size() == ray.path.size());
  if (cells.empty()) return;
  const auto where = static_cast<std::ptrdiff_t>(at);
  ray.path.insert(ray.path.begin() + where, cells.begin(), cells.end());
  ray.slots.insert(ray.slots.begin() + where, cells.size(), 0u);
  renumberFrom(ray, at + cells.size());
  for (std::size_t step = at; step < at + cells.size(); ++step) enterList(ray, id, step);
  path_entries_ += cells.size();
}

const std::vector<Crossing>& RayStore::crossing(const CellHandle& cell) const {
  const std::uint32_t slot = cell->info().ray_list;
  return slot == kNone ? empty_ : lists_[slot];
}

std::size_t RayStore::memoryBytes() const {
  // Path steps (handle and slot), list entries (ray and step), allocator headers of the vectors;
  // capacities are not walked (O(1) estimate).
  constexpr std::size_t kAllocationOverhead = 16;
  const std::size_t live_lists = lists_.size() - free_lists_.size();
  return rays_.capacity() * sizeof(Ray) + free_rays_.capacity() * sizeof(RayId) +
         lists_.capacity() * sizeof(std::vector<Crossing>) +
         free_lists_.capacity() * sizeof(std::uint32_t) +
         path_entries_ * (sizeof(CellHandle) + sizeof(std::uint32_t) + sizeof(Crossing)) +
         size() * 2 * kAllocationOverhead + live_lists * kAllocationOverhead;
}

}  // namespace terramesh::mesher::internal
