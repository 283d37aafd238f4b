#pragma once

#include <unordered_map>
#include <vector>

#include "cgal_types.h"
#include "grid_key.h"

namespace terramesh::mesher::internal {

/// The vertices of O-cells (vertices with at least one incident cell in O: the vertices of dO
/// and the vertices inside O), bucketed by the Steiner cell that contains them. Every O-cell with
/// a vertex in a set of Steiner cells is incident to a hashed vertex of those cells, so shrinking
/// and growing can start from the cells near a change instead of scanning the whole set. Vertex
/// handles are stable (vertices are removed only through `erase`), which is why vertices rather
/// than churning cells are hashed.
///
/// With `spatial` off (the boundary-hash ablation and the baseline modes) the same buckets are
/// kept, but `forEachVertexIn` finds the vertices of a region by testing every hashed vertex, as a
/// single list would have to: the same vertices are visited in the same order, only the work
/// (`forEachVertexIn`'s count) differs.
class BoundaryHash {
 public:
  explicit BoundaryHash(bool spatial) : spatial_(spatial) {}

  bool spatial() const { return spatial_; }

  /// Adds `v` under `key`. Requires v not hashed.
  void insert(VertexHandle v, const GridKey& key);
  /// Removes `v`, hashed under `key`. Requires v hashed under that key.
  void erase(VertexHandle v, const GridKey& key);

  /// Vertices hashed under `key`, or null (in both modes; for invariant checks).
  const std::vector<VertexHandle>* bucket(const GridKey& key) const;

  /// Calls `visit(v)` for every hashed vertex whose key is in `keys`: key by key in the iteration
  /// order of `keys`, each bucket in its order (so the order does not depend on `spatial`).
  /// Returns how many hashed vertices were examined: the sizes of those buckets when spatial,
  /// every hashed vertex otherwise.
  template <class KeySet, class Visit>
  std::size_t forEachVertexIn(const KeySet& keys, Visit visit) const {
    std::size_t examined = 0;
    if (!spatial_) {
      // No spatial index: every vertex is tested for membership in the region.
      std::size_t inside = 0;
      for (const auto& [key, vertices] : buckets_) {
        for (std::size_t i = 0; i < vertices.size(); ++i) inside += keys.count(key);
        examined += vertices.size();
      }
      if (inside == 0) return examined;
    }
    for (const GridKey& key : keys) {
      const auto it = buckets_.find(key);
      if (it == buckets_.end()) continue;
      if (spatial_) examined += it->second.size();
      for (const VertexHandle& v : it->second) visit(v);
    }
    return examined;
  }
  template <class Visit>
  void forEachVertex(Visit visit) const {
    for (const auto& [key, vertices] : buckets_) {
      for (const VertexHandle& v : vertices) visit(v);
    }
  }

  std::size_t size() const { return size_; }
  std::size_t bucketCount() const { return buckets_.size(); }
  std::size_t memoryBytes() const;

 private:
  friend class CheckpointAccess;

  bool spatial_;
  std::size_t size_ = 0;
  std::unordered_map<GridKey, std::vector<VertexHandle>, GridKeyHash> buckets_;
};

}  // namespace terramesh::mesher::internal
