#pragma once

#include <queue>
#include <unordered_set>
#include <vector>

#include "grid_key.h"
#include "map_state.h"
#include "mesher/update_stats.h"

namespace terramesh::mesher::internal {

/// Manifold growing: carves free cells into O in order of decreasing weight, adding a cell only if
/// the boundary stays a 2-manifold; then (proposed mode) the edge pass, which adds all free cells
/// around an edge of a refused cell at once; then the per-vertex pass that adds all cells around a
/// boundary vertex at once (which lets the surface change genus).
class Grower {
 public:
  explicit Grower(MapState& state) : state_(state) {}

  /// Grows from this update's candidates (cells that became free or were shrunk) and from the
  /// boundary near the change: the hashed vertices of `region` (proposed mode), or the whole
  /// boundary when `region` is null (baseline modes, which scan the boundary list).
  void grow(const std::unordered_set<GridKey, GridKeyHash>* region, UpdateStats& stats);

 private:
  struct QueueEntry {
    std::int32_t weight;
    std::uint32_t uid;
    CellHandle cell;
    bool operator<(const QueueEntry& other) const {
      return weight != other.weight ? weight < other.weight : uid < other.uid;
    }
  };

  bool adjacentToOutside(const CellHandle& cell) const;
  void push(const CellHandle& cell);
  void pushFreeNeighbours(const CellHandle& cell);
  void drainQueue(UpdateStats& stats);
  void genusPass(UpdateStats& stats);
  /// For each cell still refused, tries adding at once all free non-O cells around one of its
  /// edges; growing resumes after each success.
  void edgePass(UpdateStats& stats);
  void scanVertex(const VertexHandle& v);

  MapState& state_;
  std::priority_queue<QueueEntry> queue_;
  std::vector<VertexHandle> touched_vertices_;
  std::vector<CellHandle> scratch_;
  /// Cells refused at the end of the drains of this grow, for the edge pass.
  std::vector<CellHandle> final_refused_;
};

}  // namespace terramesh::mesher::internal
