#pragma once

#include <cstdint>

#include "cgal_types.h"

namespace terramesh::mesher::internal {

/// Source of fresh values for the scratch marks of cells and vertices (CellInfo::mark,
/// VertexInfo::mark): a pass takes a new epoch and treats "mark == epoch" as visited, so marks
/// never need clearing. All passes share one source so their epochs never collide.
class MarkEpochs {
 public:
  explicit MarkEpochs(Delaunay& tri) : tri_(tri) {}

  std::uint32_t nextCellMark() {
    if (++cell_epoch_ == 0) {
      for (auto cell = tri_.all_cells_begin(); cell != tri_.all_cells_end(); ++cell) cell->info().mark = 0;
      cell_epoch_ = 1;
    }
    return cell_epoch_;
  }

  std::uint32_t nextVertexMark() {
    if (++vertex_epoch_ == 0) {
      for (auto v = tri_.all_vertices_begin(); v != tri_.all_vertices_end(); ++v) v->info().mark = 0;
      vertex_epoch_ = 1;
    }
    return vertex_epoch_;
  }

 private:
  Delaunay& tri_;
  std::uint32_t cell_epoch_ = 0;
  std::uint32_t vertex_epoch_ = 0;
};

}  // namespace terramesh::mesher::internal
