#include "boundary_hash.h"

#include <cassert>

namespace terramesh::mesher::internal {

void BoundaryHash::insert(VertexHandle v, const GridKey& key) {
  assert(v->info().hash_slot == kNone);
  std::vector<VertexHandle>& vertices = buckets_[key];
  v->info().hash_slot = static_cast<std::uint32_t>(vertices.size());
  vertices.push_back(v);
  ++size_;
}

void BoundaryHash::erase(VertexHandle v, const GridKey& key) {
  const auto it = buckets_.find(key);
  assert(it != buckets_.end());
  std::vector<VertexHandle>& vertices = it->second;
  const std::uint32_t slot = v->info().hash_slot;
  assert(slot < vertices.size() && vertices[slot] == v);
  vertices[slot] = vertices.back();
  vertices[slot]->info().hash_slot = slot;
  vertices.pop_back();
  v->info().hash_slot = kNone;
  --size_;
  if (vertices.empty()) buckets_.erase(it);
}

const std::vector<VertexHandle>* BoundaryHash::bucket(const GridKey& key) const {
  const auto it = buckets_.find(key);
  return it == buckets_.end() ? nullptr : &it->second;
}

std::size_t BoundaryHash::memoryBytes() const {
  // Table slots, one node per bucket (key, vector header, links) and one handle per vertex;
  // vector capacities are not walked (O(1) estimate).
  return buckets_.bucket_count() * sizeof(void*) +
         buckets_.size() * (sizeof(GridKey) + sizeof(std::vector<VertexHandle>) + 2 * sizeof(void*)) +
         size_ * sizeof(VertexHandle);
}

}  // namespace terramesh::mesher::internal
