#pragma once

#include <Eigen/Core>
#include <unordered_set>
#include <vector>

#include "grid_key.h"

namespace terramesh::mesher::internal {

/// The lattice of Steiner points, spacing `step` map units. Cell (i,j,k) spans the nodes i..i+1 on
/// each axis. The grid grows by whole layers of nodes, so it always fills an axis-aligned box of
/// nodes [lo, hi] (inclusive, per axis) - until it is made sparse (the online freeze,
/// Mesher::releaseFarSteiner): then it holds the nodes asked for and not released, and [lo, hi]
/// bounds every node it ever held.
///
/// The lattice is offset from the first camera by an irregular fraction of the step, so that
/// synthetic data on round coordinates does not sit exactly on Steiner nodes or planes.
class SteinerGrid {
 public:
  /// `origin_shift`: added to the origin the first cover call chooses (map units; the
  /// experiment option MesherConfig::steiner_origin_offset_m).
  /// `global_phase`: the first cover call puts the origin on the lattice of multiples of the step
  /// (plus the offsets and the shift) next to its data, so that every grid of that step and shift
  /// has the same nodes (MesherConfig::steiner_global_phase).
  explicit SteinerGrid(double step, const Eigen::Vector3d& origin_shift = Eigen::Vector3d::Zero(),
                       bool global_phase = false);

  double step() const { return step_; }
  bool empty() const { return !initialized_; }

  /// Cell containing `p`. Requires the origin to be set (first call to coverNodes).
  GridKey cellOf(const Eigen::Vector3d& p) const;
  /// Position of lattice node `node`.
  Eigen::Vector3d nodePosition(const GridKey& node) const;
  /// The lattice node nearest to `p` (exact for p = nodePosition(node)). Requires the origin set.
  GridKey nodeOf(const Eigen::Vector3d& p) const;

  /// Grows the grid so that its nodes cover cells key-margin .. key+margin of the cell containing
  /// `p`, and returns the positions of the nodes added (empty if none). The first call fixes the
  /// origin relative to `p`.
  std::vector<Eigen::Vector3d> coverPoint(const Eigen::Vector3d& p, int margin_cells);

  /// Grows the grid to cover the box [min, max] plus margin cells; returns the nodes added.
  std::vector<Eigen::Vector3d> coverBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                                        int margin_cells);

  /// True if cell `key` lies at least `margin_cells` inside the node box.
  bool coversCell(const GridKey& key, int margin_cells) const;

  /// From now on coverBox adds only the nodes of the box asked for, and release() takes nodes out.
  void makeSparse();
  bool sparse() const { return sparse_; }
  /// Takes node `node` out of a sparse grid (its vertex left the triangulation); a later coverBox
  /// over it adds it again.
  void release(const GridKey& node) { present_.erase(node); }

  GridKey lowerNode() const { return lo_; }
  GridKey upperNode() const { return hi_; }
  std::size_t nodeCount() const;

 private:
  friend class CheckpointAccess;

  std::vector<Eigen::Vector3d> growNodeBox(const GridKey& lo, const GridKey& hi);
  /// Sparse: adds the nodes of [lo, hi] not held yet.
  std::vector<Eigen::Vector3d> addNodes(const GridKey& lo, const GridKey& hi);

  double step_;
  Eigen::Vector3d origin_shift_;
  bool global_phase_ = false;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  bool initialized_ = false;
  GridKey lo_;
  GridKey hi_;
  bool sparse_ = false;
  std::unordered_set<GridKey, GridKeyHash> present_;  ///< the nodes of a sparse grid
};

}  // namespace terramesh::mesher::internal
