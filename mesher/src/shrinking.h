#pragma once

#include <unordered_set>
#include <vector>

#include "grid_key.h"
#include "map_state.h"
#include "mesher/update_stats.h"

namespace terramesh::mesher::internal {

/// The enclosing set E and the shrinking of O inside it, done before points are inserted or
/// removed so that their conflict zones are (likely) free of O.
class Shrinker {
 public:
  explicit Shrinker(MapState& state) : state_(state) {}

  /// The paper's enclosing set: cells with a vertex in the Steiner cells within `radius_cells` of
  /// the cell of each position. Returns the keys of those Steiner cells.
  std::unordered_set<GridKey, GridKeyHash> enclosingKeys(
      const std::vector<Eigen::Vector3d>& positions, int radius_cells) const;

  /// Shrinks O inside the enclosing set given by `keys` (proposed mode: seeds from the hash).
  void shrinkInKeys(const std::unordered_set<GridKey, GridKeyHash>& keys, UpdateStats& stats);

  /// Baseline enclosing set: cells with a vertex inside a sphere of `radius` around a camera.
  /// Finds its cells by scanning the whole boundary list.
  void shrinkInSpheres(const std::vector<Eigen::Vector3d>& centres, double radius,
                       UpdateStats& stats);

 private:
  /// Peels the O-cells in `enclosed` (flagged kCellEnclosed) from the boundary inwards.
  void peel(UpdateStats& stats);
  /// Removes cells one at a time from `queue` while that keeps dO manifold; returns the refused.
  std::vector<CellHandle> peelQueue(std::vector<CellHandle>& queue, UpdateStats& stats);
  /// The inverse of growing's per-vertex pass: removes every enclosed O-cell around a vertex at
  /// once (undoing handles no single removal can). Returns the cells removed.
  std::size_t removeStars(const std::vector<CellHandle>& refused, std::vector<CellHandle>& queue,
                          UpdateStats& stats);
  void removeCell(const CellHandle& cell, std::vector<CellHandle>& queue, UpdateStats& stats);
  void addEnclosedCellsOf(VertexHandle v);

  MapState& state_;
  std::vector<CellHandle> enclosed_;
  std::vector<CellHandle> scratch_;
};

}  // namespace terramesh::mesher::internal
