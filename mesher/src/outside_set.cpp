#include "outside_set.h"

#include <cassert>

namespace terramesh::mesher::internal {

bool OutsideSet::canAdd(CellHandle cell) {
  assert(!cell->info().outside() && !tri_.is_infinite(cell));
  int glued = 0;
  int glued_facet = -1;
  for (int i = 0; i < 4; ++i) {
    if (cell->neighbor(i)->info().outside()) {
      ++glued;
      glued_facet = i;
    }
  }
  // A cell glued by a single face whose apex is not on dO replaces one boundary triangle by three
  // around a new vertex: always manifold.
  if (glued == 1 && cell->vertex(glued_facet)->info().outside_cells == 0) return true;
  // A cell closing a cavity (all faces glued) removes a tetrahedral bubble: always manifold.
  if (glued == 4) return true;
  auto inside = [&cell](const CellHandle& c) { return c == cell || c->info().outside(); };
  for (int i = 0; i < 4; ++i) {
    const VertexHandle v = cell->vertex(i);
    const std::size_t members = v->info().outside_cells;
    if (members == 0) continue;  // only `cell` around v afterwards: a disk
    if (!test_.isRegular(v, cell, members + 1, inside)) return false;
  }
  return true;
}

bool OutsideSet::canRemove(CellHandle cell) {
  assert(cell->info().outside());
  auto inside = [&cell](const CellHandle& c) { return c != cell && c->info().outside(); };
  for (int i = 0; i < 4; ++i) {
    const VertexHandle v = cell->vertex(i);
    const std::size_t members = v->info().outside_cells;
    if (members == 1) continue;  // v leaves dO altogether
    // The O-cells around v form a disk, so one of them shares a facet around v with `cell`.
    CellHandle start;
    for (int j = 0; j < 4 && start == CellHandle(); ++j) {
      if (j != i && cell->neighbor(j)->info().outside()) start = cell->neighbor(j);
    }
    if (start == CellHandle() || !test_.isRegular(v, start, members - 1, inside)) return false;
  }
  return true;
}

bool OutsideSet::canAddAll(const std::vector<CellHandle>& cells) {
  return pendingChangeKeepsManifold(cells, true);
}

bool OutsideSet::canRemoveAll(const std::vector<CellHandle>& cells) {
  return pendingChangeKeepsManifold(cells, false);
}

bool OutsideSet::pendingChangeKeepsManifold(const std::vector<CellHandle>& cells, bool adding) {
  for (const CellHandle& c : cells) c->info().flags |= kCellPending;
  auto inside = [adding](const CellHandle& c) {
    const bool pending = (c->info().flags & kCellPending) != 0;
    return adding ? (c->info().outside() || pending) : (c->info().outside() && !pending);
  };
  const std::uint32_t vertex_mark = epochs_.nextVertexMark();
  bool ok = true;
  for (std::size_t a = 0; a < cells.size() && ok; ++a) {
    for (int i = 0; i < 4 && ok; ++i) {
      const VertexHandle v = cells[a]->vertex(i);
      if (v->info().mark == vertex_mark) continue;
      v->info().mark = vertex_mark;
      // Members of the changed set around v, and a start cell for the search.
      std::size_t changed = 0;
      CellHandle start;
      for (const CellHandle& c : cells) {
        int iv = -1;
        if (!c->has_vertex(v, iv)) continue;
        ++changed;
        if (adding) {
          start = c;
        } else {
          for (int j = 0; j < 4 && start == CellHandle(); ++j) {
            if (j != iv && inside(c->neighbor(j))) start = c->neighbor(j);
          }
        }
      }
      const std::size_t before = v->info().outside_cells;
      const std::size_t members = adding ? before + changed : before - changed;
      if (members == 0) continue;
      ok = start != CellHandle() && test_.isRegular(v, start, members, inside);
    }
  }
  for (const CellHandle& c : cells) c->info().flags &= static_cast<std::uint8_t>(~kCellPending);
  return ok;
}

void OutsideSet::add(CellHandle cell) {
  assert(!cell->info().outside());
  cell->info().flags |= kCellOutside;
  ++size_;
  for (int i = 0; i < 4; ++i) vertexGainedCell(cell->vertex(i));
}

void OutsideSet::remove(CellHandle cell) {
  assert(cell->info().outside());
  cell->info().flags &= static_cast<std::uint8_t>(~kCellOutside);
  --size_;
  for (int i = 0; i < 4; ++i) vertexLostCell(cell->vertex(i));
}

bool OutsideSet::isRegular(VertexHandle v) {
  const std::size_t members = v->info().outside_cells;
  if (members == 0) return true;
  std::vector<CellHandle> star;
  tri_.incident_cells(v, std::back_inserter(star));
  std::size_t counted = 0;
  CellHandle start;
  for (const CellHandle& c : star) {
    if (!c->info().outside()) continue;
    ++counted;
    start = c;
  }
  if (counted != members) return false;
  return test_.isRegular(v, start, members, [](const CellHandle& c) { return c->info().outside(); });
}

void OutsideSet::vertexGainedCell(VertexHandle v) {
  if (v->info().outside_cells++ == 0) hash_.insert(v, keyOf(v));
}

void OutsideSet::vertexLostCell(VertexHandle v) {
  assert(v->info().outside_cells > 0);
  if (--v->info().outside_cells == 0) hash_.erase(v, keyOf(v));
}

}  // namespace terramesh::mesher::internal
