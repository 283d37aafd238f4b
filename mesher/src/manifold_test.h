#pragma once

#include <utility>
#include <vector>

#include "cgal_types.h"

namespace terramesh::mesher::internal {

/// Tests whether a vertex is regular on the boundary of a cell set: the boundary facets around it
/// form a single disk (or there are none). In the link of the vertex (a triangulated sphere whose
/// triangles are the incident cells) this means the boundary edges form exactly one simple cycle.
///
/// Holds scratch buffers so repeated tests do not allocate. Not thread-safe.
class VertexRegularityTest {
 public:
  /// `inside(cell)` tells whether a cell belongs to the set (O, possibly with tentative changes).
  template <class Inside>
  bool isRegular(const Delaunay& tri, VertexHandle v, Inside inside) {
    cells_.clear();
    tri.incident_cells(v, std::back_inserter(cells_));
    edges_.clear();
    for (const CellHandle& cell : cells_) {
      if (!inside(cell)) continue;
      const int iv = cell->index(v);
      for (int j = 0; j < 4; ++j) {
        if (j == iv || inside(cell->neighbor(j))) continue;
        // Facet j contains v; its two other vertices form an edge of the link.
        Delaunay::Vertex* ends[2];
        int n = 0;
        for (int k = 0; k < 4; ++k) {
          if (k != iv && k != j) ends[n++] = &*cell->vertex(k);
        }
        edges_.emplace_back(ends[0], ends[1]);
      }
    }
    return edgesFormOneCycle();
  }

 private:
  bool edgesFormOneCycle() const;

  std::vector<CellHandle> cells_;
  std::vector<std::pair<Delaunay::Vertex*, Delaunay::Vertex*>> edges_;
};

}  // namespace terramesh::mesher::internal
