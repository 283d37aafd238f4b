#include "shrinking.h"

#include <deque>

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
  // Every O-cell with a vertex in the keys is incident to a hashed (boundary) vertex there.
  for (const GridKey& key : keys) {
    const std::vector<VertexHandle>* bucket = state_.hash.bucket(key);
    if (bucket == nullptr) continue;
    for (const VertexHandle& v : *bucket) addEnclosedCellsOf(v);
  }
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

void Shrinker::peel(UpdateStats& stats) {
  stats.enclosing_cells += enclosed_.size();
  OutsideSet& outside = state_.outside;
  std::deque<CellHandle> queue;
  for (const CellHandle& cell : enclosed_) {
    if (touchesBoundary(cell)) {
      cell->info().flags |= kCellQueued;
      queue.push_back(cell);
    }
  }
  // Peel from the boundary inwards; cells refused now may pass once cells around them are gone,
  // so refused cells are retried until a pass removes nothing.
  std::vector<CellHandle> refused;
  while (true) {
    bool progress = false;
    while (!queue.empty()) {
      const CellHandle cell = queue.front();
      queue.pop_front();
      cell->info().flags &= static_cast<std::uint8_t>(~kCellQueued);
      if (!cell->info().outside()) continue;
      if (!outside.canRemove(cell)) {
        refused.push_back(cell);
        continue;
      }
      outside.remove(cell);
      progress = true;
      ++stats.cells_shrunk;
      if (hasSteinerVertex(cell)) ++stats.steiner_cells_shrunk;
      for (int i = 0; i < 4; ++i) {
        const CellHandle n = cell->neighbor(i);
        const std::uint8_t flags = n->info().flags;
        if ((flags & kCellOutside) && (flags & kCellEnclosed) && !(flags & kCellQueued)) {
          n->info().flags |= kCellQueued;
          queue.push_back(n);
        }
      }
    }
    if (!progress || refused.empty()) break;
    for (const CellHandle& cell : refused) {
      if (cell->info().outside() && !(cell->info().flags & kCellQueued)) {
        cell->info().flags |= kCellQueued;
        queue.push_back(cell);
      }
    }
    refused.clear();
  }
  for (const CellHandle& cell : enclosed_) {
    cell->info().flags &= static_cast<std::uint8_t>(~(kCellEnclosed | kCellQueued));
  }
  // Shrunk cells are free space waiting to be grown back once the new points are in.
  for (const CellHandle& cell : enclosed_) {
    if (!cell->info().outside() && state_.weights.isFree(cell)) state_.candidates.add(cell);
  }
  enclosed_.clear();
}

}  // namespace terramesh::mesher::internal
