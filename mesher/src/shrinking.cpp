#include "shrinking.h"


namespace terramesh::mesher::internal {
namespace {

bool touchesBoundary(const CellHandle& cell) {
  for (int i = 0; i < 4; ++i) {
    if (!cell->neighbor(i)->info().outside()) return true;
  }
  return false;
}

bool hasSteinerVertex(const CellHandle& cell) {
  for (int i = 0; i < 4; ++i) {
    if (cell->vertex(i)->info().steiner) return true;
  }
  return false;
}

}  // namespace

std::unordered_set<GridKey, GridKeyHash> Shrinker::enclosingKeys(
    const std::vector<Eigen::Vector3d>& positions, int radius) const {
  std::unordered_set<GridKey, GridKeyHash> keys;
  std::unordered_set<GridKey, GridKeyHash> centres;
  for (const Eigen::Vector3d& p : positions) centres.insert(state_.grid.cellOf(p));
  for (const GridKey& c : centres) {
    for (int di = -radius; di <= radius; ++di) {
      for (int dj = -radius; dj <= radius; ++dj) {
        for (int dk = -radius; dk <= radius; ++dk) keys.insert({c.i + di, c.j + dj, c.k + dk});
      }
    }
  }
  return keys;
}

void Shrinker::addEnclosedCellsOf(VertexHandle v) {
  scratch_.clear();
  state_.tri.incident_cells(v, std::back_inserter(scratch_));
  for (const CellHandle& cell : scratch_) {
    if (!cell->info().outside() || (cell->info().flags & kCellEnclosed)) continue;
    cell->info().flags |= kCellEnclosed;
    enclosed_.push_back(cell);
  }
}

void Shrinker::shrinkInKeys(const std::unordered_set<GridKey, GridKeyHash>& keys,
                            UpdateStats& stats) {
  enclosed_.clear();
  // Every O-cell with a vertex in the keys is incident to a hashed vertex (of an O-cell) there.
  stats.boundary_vertices_examined +=
      state_.hash.forEachVertexIn(keys, [this](const VertexHandle& v) { addEnclosedCellsOf(v); });
  peel(stats);
}

void Shrinker::shrinkInSpheres(const std::vector<Eigen::Vector3d>& centres, double radius,
                               UpdateStats& stats) {
  enclosed_.clear();
  const double radius2 = radius * radius;
  std::vector<VertexHandle> inside;
  state_.hash.forEachVertex([&](const VertexHandle& v) {
    const Eigen::Vector3d p = toEigen(v->point());
    for (const Eigen::Vector3d& c : centres) {
      if ((p - c).squaredNorm() <= radius2) {
        inside.push_back(v);
        return;
      }
    }
  });
  for (const VertexHandle& v : inside) addEnclosedCellsOf(v);
  peel(stats);
}

void Shrinker::removeCell(const CellHandle& cell, std::vector<CellHandle>& queue,
                          UpdateStats& stats) {
  state_.outside.remove(cell);
  ++stats.cells_shrunk;
  if (hasSteinerVertex(cell)) ++stats.steiner_cells_shrunk;
  // Its enclosed O-neighbours now touch the boundary.
  for (int i = 0; i < 4; ++i) {
    const CellHandle n = cell->neighbor(i);
    const std::uint8_t flags = n->info().flags;
    if ((flags & kCellOutside) && (flags & kCellEnclosed) && !(flags & kCellQueued)) {
      n->info().flags |= kCellQueued;
      queue.push_back(n);
    }
  }
}

std::vector<CellHandle> Shrinker::peelQueue(std::vector<CellHandle>& queue, UpdateStats& stats) {
  // A refused cell's test can only change once O changes around one of its vertices: each pass
  // marks the vertices of the cells it removes, and refused cells touching one are tried again.
  std::vector<CellHandle> refused;
  while (true) {
    const std::uint32_t changed = state_.nextVertexMark();
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const CellHandle cell = queue[head];
      cell->info().flags &= static_cast<std::uint8_t>(~kCellQueued);
      if (!cell->info().outside()) continue;
      if (!state_.outside.canRemove(cell)) {
        refused.push_back(cell);
        continue;
      }
      for (int i = 0; i < 4; ++i) cell->vertex(i)->info().mark = changed;
      removeCell(cell, queue, stats);
    }
    queue.clear();
    std::vector<CellHandle> still_refused;
    for (const CellHandle& cell : refused) {
      if (!cell->info().outside()) continue;
      bool touched = false;
      for (int i = 0; i < 4 && !touched; ++i) touched = cell->vertex(i)->info().mark == changed;
      if (touched && !(cell->info().flags & kCellQueued)) {
        cell->info().flags |= kCellQueued;
        queue.push_back(cell);
      } else if (!touched) {
        still_refused.push_back(cell);
      }
    }
    refused.swap(still_refused);
    if (queue.empty()) break;
  }
  return refused;
}

std::size_t Shrinker::removeStars(const std::vector<CellHandle>& refused,
                                  std::vector<CellHandle>& queue, UpdateStats& stats) {
  std::size_t removed = 0;
  const std::uint32_t mark = state_.nextVertexMark();
  std::vector<CellHandle> to_remove;
  for (const CellHandle& cell : refused) {
    if (!cell->info().outside()) continue;
    for (int i = 0; i < 4; ++i) {
      const VertexHandle v = cell->vertex(i);
      if (v->info().mark == mark) continue;
      v->info().mark = mark;
      scratch_.clear();
      state_.tri.incident_cells(v, std::back_inserter(scratch_));
      to_remove.clear();
      for (const CellHandle& c : scratch_) {
        const std::uint8_t flags = c->info().flags;
        if ((flags & kCellOutside) && (flags & kCellEnclosed)) to_remove.push_back(c);
      }
      if (to_remove.size() < 2 || !state_.outside.canRemoveAll(to_remove)) continue;
      for (const CellHandle& c : to_remove) removeCell(c, queue, stats);
      removed += to_remove.size();
    }
  }
  return removed;
}

void Shrinker::peel(UpdateStats& stats) {
  stats.enclosing_cells += enclosed_.size();
  std::vector<CellHandle> queue;
  for (const CellHandle& cell : enclosed_) {
    if (touchesBoundary(cell)) {
      cell->info().flags |= kCellQueued;
      queue.push_back(cell);
    }
  }
  // Peel single cells from the boundary inwards; where that is stuck, remove whole stars.
  while (true) {
    const std::vector<CellHandle> refused = peelQueue(queue, stats);
    if (refused.empty() || removeStars(refused, queue, stats) == 0) break;
  }
  for (const CellHandle& cell : queue) cell->info().flags &= static_cast<std::uint8_t>(~kCellQueued);
  for (const CellHandle& cell : enclosed_) {
    cell->info().flags &= static_cast<std::uint8_t>(~(kCellEnclosed | kCellQueued));
  }
  // Shrunk cells are free space waiting to be grown back once the new points are in.
  for (const CellHandle& cell : enclosed_) {
    if (!cell->info().outside() && state_.isFree(cell)) state_.candidates.add(cell);
  }
  enclosed_.clear();
}

}  // namespace terramesh::mesher::internal
