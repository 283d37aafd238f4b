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
    if (v->info().outside_cells == 0) continue;  // only `cell` around v afterwards: a disk
    if (!test_.isRegular(tri_, v, inside)) return false;
  }
  return true;
}

bool OutsideSet::canRemove(CellHandle cell) {
  assert(cell->info().outside());
  auto inside = [&cell](const CellHandle& c) { return c != cell && c->info().outside(); };
  for (int i = 0; i < 4; ++i) {
    const VertexHandle v = cell->vertex(i);
    if (v->info().outside_cells == 1) continue;  // v leaves dO altogether
    if (!test_.isRegular(tri_, v, inside)) return false;
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
  bool ok = true;
  for (const CellHandle& c : cells) {
    for (int i = 0; i < 4 && ok; ++i) ok = test_.isRegular(tri_, c->vertex(i), inside);
    if (!ok) break;
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
  return test_.isRegular(tri_, v, [](const CellHandle& c) { return c->info().outside(); });
}

void OutsideSet::vertexGainedCell(VertexHandle v) {
  if (v->info().outside_cells++ == 0) hash_.insert(v, keyOf(v));
}

void OutsideSet::vertexLostCell(VertexHandle v) {
  assert(v->info().outside_cells > 0);
  if (--v->info().outside_cells == 0) hash_.erase(v, keyOf(v));
}

}  // namespace terramesh::mesher::internal
