#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "cgal_types.h"
#include "mark_epochs.h"

namespace terramesh::mesher::internal {

/// Tests whether a vertex is regular on the boundary of a cell set S: the cells of S around it
/// form a single disk, so its boundary facets form one fan (or there are none). In the link of
/// the vertex (a triangulated sphere whose triangles are the incident cells) this means: the cells
/// of S are connected through facets around the vertex and their boundary edges form exactly one
/// simple cycle.
///
/// Only the cells of S are visited: a search through the facets around the vertex from one cell
/// of S, compared with how many cells of S the vertex has (the caller knows it from the per-vertex
/// counter). Holds scratch buffers; not thread-safe.
class VertexRegularityTest {
 public:
  explicit VertexRegularityTest(MarkEpochs& epochs) : epochs_(epochs) {}

  /// @param start a cell of S incident to `v`.
  /// @param members how many cells of S are incident to `v`.
  /// @param inside membership of S (O with tentative changes).
  template <class Inside>
  bool isRegular(VertexHandle v, CellHandle start, std::size_t members, Inside inside) {
    const std::uint32_t mark = epochs_.nextCellMark();
    stack_.clear();
    edges_.clear();
    start->info().mark = mark;
    stack_.push_back(start);
    std::size_t visited = 0;
    while (!stack_.empty()) {
      const CellHandle cell = stack_.back();
      stack_.pop_back();
      ++visited;
      const int iv = cell->index(v);
      for (int j = 0; j < 4; ++j) {
        if (j == iv) continue;
        const CellHandle next = cell->neighbor(j);
        if (inside(next)) {
          if (next->info().mark != mark) {
            next->info().mark = mark;
            stack_.push_back(next);
          }
          continue;
        }
        // Facet j contains v and lies on the boundary: its other two vertices are a link edge.
        Delaunay::Vertex* ends[2];
        int n = 0;
        for (int k = 0; k < 4; ++k) {
          if (k != iv && k != j) ends[n++] = &*cell->vertex(k);
        }
        edges_.emplace_back(ends[0], ends[1]);
      }
    }
    if (visited != members) return false;  // S around v is not connected through facets
    return edgesFormOneCycle();
  }

 private:
  bool edgesFormOneCycle();

  /// A link vertex and the (at most two) boundary edges ending at it.
  struct LinkSlot {
    const Delaunay::Vertex* vertex = nullptr;
    std::uint32_t generation = 0;
    std::uint32_t degree = 0;
    std::uint32_t edge[2] = {0, 0};
  };
  /// The slot of `vertex` in the open-addressing table of this test (created if new).
  LinkSlot& slotOf(const Delaunay::Vertex* vertex);

  MarkEpochs& epochs_;
  std::vector<CellHandle> stack_;
  std::vector<std::pair<Delaunay::Vertex*, Delaunay::Vertex*>> edges_;
  std::vector<LinkSlot> table_;
  std::uint32_t generation_ = 0;
};

}  // namespace terramesh::mesher::internal
