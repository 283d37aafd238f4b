#include "point_registry.h"

#include <cassert>

namespace terramesh::mesher::internal {

std::uint32_t PointRegistry::findOrCreatePoint(PointId id) {
  const auto [it, created] = point_index_.try_emplace(id, kNone);
  if (!created) return it->second;
  std::uint32_t index;
  if (!free_points_.empty()) {
    index = free_points_.back();
    free_points_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(points_.size());
    points_.emplace_back();
  }
  points_[index] = PointRecord{};
  points_[index].id = id;
  points_[index].alive = true;
  it->second = index;
  return index;
}

std::uint32_t PointRegistry::findPoint(PointId id) const {
  const auto it = point_index_.find(id);
  return it == point_index_.end() ? kNone : it->second;
}

void PointRegistry::erasePoint(std::uint32_t index) {
  PointRecord& record = points_[index];
  assert(record.alive && !record.inserted() && record.rays.empty());
  point_index_.erase(record.id);
  record = PointRecord{};
  free_points_.push_back(index);
}

std::uint32_t PointRegistry::findOrCreateKeyframe(KeyframeId id, bool& created) {
  const auto [it, inserted] = keyframe_index_.try_emplace(id, kNone);
  created = inserted;
  if (!inserted) return it->second;
  std::uint32_t index;
  if (!free_keyframes_.empty()) {
    index = free_keyframes_.back();
    free_keyframes_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(keyframes_.size());
    keyframes_.emplace_back();
  }
  keyframes_[index] = KeyframeRecord{};
  keyframes_[index].id = id;
  keyframes_[index].alive = true;
  it->second = index;
  return index;
}

std::uint32_t PointRegistry::findKeyframe(KeyframeId id) const {
  const auto it = keyframe_index_.find(id);
  return it == keyframe_index_.end() ? kNone : it->second;
}

void PointRegistry::eraseKeyframe(std::uint32_t index) {
  KeyframeRecord& record = keyframes_[index];
  assert(record.alive);
  keyframe_index_.erase(record.id);
  record = KeyframeRecord{};
  free_keyframes_.push_back(index);
}

std::size_t PointRegistry::pointBytes() const {
  std::size_t bytes = points_.capacity() * sizeof(PointRecord) +
                      keyframes_.capacity() * sizeof(KeyframeRecord);
  for (const PointRecord& p : points_) {
    bytes += p.keyframes.capacity() * sizeof(std::uint32_t) + p.rays.capacity() * sizeof(RayId);
  }
  for (const KeyframeRecord& k : keyframes_) bytes += k.points.capacity() * sizeof(std::uint32_t);
  return bytes;
}

std::size_t PointRegistry::indexBytes() const {
  // libstdc++ unordered_map: a bucket pointer per bucket and a node (next, key, value, hash).
  const std::size_t node = sizeof(void*) + sizeof(std::uint64_t) * 2 + sizeof(std::size_t);
  return (point_index_.bucket_count() + keyframe_index_.bucket_count()) * sizeof(void*) +
         (point_index_.size() + keyframe_index_.size()) * node;
}

}  // namespace terramesh::mesher::internal
