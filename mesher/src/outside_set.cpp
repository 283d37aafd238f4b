#include "outside_set.h"

#include <array>
#include <cassert>

namespace terramesh::mesher::internal {

// Single-cell changes use a local rule. In the link of a vertex v (a triangulated sphere, one
// triangle t per incident cell) the O-cells form a disk R (or nothing, or everything). Adding a cell
// adds t to R: R + t is a disk iff t shares two or three edges with R, or exactly one edge and its
// opposite link vertex is not on R (else the surface pinches there). An edge of t shared with R is a
// facet of the cell around v whose neighbour is in O; the opposite link vertex w is on R iff some
// O-cell contains the edge (v, w). Removing a cell is the same rule for the complement of R.

bool OutsideSet::anyAroundEdge(const CellHandle& cell, int i, int j, bool in_outside) const {
  const auto start = tri_.incident_cells(cell, i, j);
  auto around = start;
  do {
    const CellHandle c = around;
    if (c != cell && c->info().outside() == in_outside) return true;
  } while (++around != start);
  return false;
}

bool OutsideSet::canAdd(CellHandle cell) {
  assert(!cell->info().outside() && !tri_.is_infinite(cell));
  for (int i = 0; i < 4; ++i) {
    if (cell->vertex(i)->info().outside_cells == 0) continue;  // R empty: t alone is a disk
    int glued = 0;
    int glued_facet = -1;
    for (int j = 0; j < 4; ++j) {
      if (j != i && cell->neighbor(j)->info().outside()) {
        ++glued;
        glued_facet = j;
      }
    }
    if (glued == 0) return false;  // t would touch R at vertices only
    if (glued == 1 && anyAroundEdge(cell, i, glued_facet, true)) return false;  // pinch
  }
  return true;
}

bool OutsideSet::canRemove(CellHandle cell) {
  assert(cell->info().outside());
  for (int i = 0; i < 4; ++i) {
    const VertexHandle v = cell->vertex(i);
    const std::size_t members = v->info().outside_cells;
    if (members == 1) continue;  // v leaves dO altogether
    int open = 0;
    int open_facet = -1;
    for (int j = 0; j < 4; ++j) {
      if (j != i && !cell->neighbor(j)->info().outside()) {
        ++open;
        open_facet = j;
      }
    }
    if (open == 1 && anyAroundEdge(cell, i, open_facet, false)) return false;  // pinch
    // Every facet of the cell around v glued to O: fine only if v is interior to O (the removal
    // opens a cavity there), not if it would punch a hole into the disk.
    if (open == 0 && members != v->info().degree) return false;
  }
  return true;
}

bool OutsideSet::canAddAll(const std::vector<CellHandle>& cells, VertexHandle* failed) {
  return pendingChangeKeepsManifold(cells, true, failed);
}

bool OutsideSet::canRemoveAll(const std::vector<CellHandle>& cells) {
  return pendingChangeKeepsManifold(cells, false);
}

bool OutsideSet::pendingChangeKeepsManifold(const std::vector<CellHandle>& cells, bool adding, VertexHandle* failed) {
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
      if (!ok && failed != nullptr) *failed = v;
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
  if (log_ != nullptr) logFacets(cell, true);
}

void OutsideSet::remove(CellHandle cell) {
  assert(cell->info().outside());
  cell->info().flags &= static_cast<std::uint8_t>(~kCellOutside);
  --size_;
  for (int i = 0; i < 4; ++i) vertexLostCell(cell->vertex(i));
  if (log_ != nullptr) logFacets(cell, false);
}

void OutsideSet::logFacets(const CellHandle& cell, bool entering) {
  // A facet of `cell` is on the surface iff exactly one of its two cells is in O; it is wound with
  // its normal into the O side (CGAL's vertex_triple_index winds it into `cell`).
  // Keys and hashes are taken once per vertex and shared by the three facets through it.
  std::array<VertexKey, 4> keys;
  std::array<std::uint64_t, 4> hashes;
  for (int v = 0; v < 4; ++v) {
    const auto slot = static_cast<std::size_t>(v);
    keys[slot] = vertexKey(cell->vertex(v));
    hashes[slot] = SurfaceLog::vertexHash(keys[slot]);
  }
  for (int i = 0; i < 4; ++i) {
    const auto a = static_cast<std::size_t>(Delaunay::vertex_triple_index(i, 0));
    const auto b = static_cast<std::size_t>(Delaunay::vertex_triple_index(i, 1));
    const auto c = static_cast<std::size_t>(Delaunay::vertex_triple_index(i, 2));
    const std::uint64_t hash = SurfaceLog::faceHash(hashes[a], hashes[b], hashes[c]);
    if (cell->neighbor(i)->info().outside()) {
      log_->faceEvent({keys[a], keys[c], keys[b]}, hash, !entering);  // wound into the neighbour
    } else {
      log_->faceEvent({keys[a], keys[b], keys[c]}, hash, entering);
    }
  }
}

void OutsideSet::touchFacesOf(const CellHandle& cell) {
  if (log_ == nullptr) return;
  for (int i = 0; i < 4; ++i) {
    if (cell->neighbor(i)->info().outside() == cell->info().outside()) continue;
    for (int k = 0; k < 3; ++k) log_->touch(vertexKey(cell->vertex(Delaunay::vertex_triple_index(i, k))));
  }
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
