#pragma once

#include <unordered_map>
#include <vector>

#include "cgal_types.h"
#include "grid_key.h"

namespace terramesh::mesher::internal {

/// The vertices of the surface dO (vertices with at least one incident cell in O), bucketed by the
/// Steiner cell that contains them. The boundary tetrahedra of a region are the O-cells incident
/// to the hashed vertices of its Steiner cells, so shrinking and growing can start from the cells
/// near a change instead of scanning the whole boundary. Vertex handles are stable (vertices are
/// removed only through `erase`), which is why vertices rather than churning cells are hashed.
///
/// With `spatial` off (the baseline modes) every vertex goes into one bucket: the boundary is a
/// single list that can only be scanned whole.
class BoundaryHash {
 public:
  explicit BoundaryHash(bool spatial) : spatial_(spatial) {}

  bool spatial() const { return spatial_; }

  /// Adds `v` under `key`. Requires v not hashed.
  void insert(VertexHandle v, const GridKey& key);
  /// Removes `v`, hashed under `key`. Requires v hashed under that key.
  void erase(VertexHandle v, const GridKey& key);

  /// Vertices hashed under `key` (all vertices when not spatial).
  const std::vector<VertexHandle>* bucket(const GridKey& key) const;
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
  GridKey effectiveKey(const GridKey& key) const { return spatial_ ? key : GridKey{}; }

  bool spatial_;
  std::size_t size_ = 0;
  std::unordered_map<GridKey, std::vector<VertexHandle>, GridKeyHash> buckets_;
};

}  // namespace terramesh::mesher::internal
