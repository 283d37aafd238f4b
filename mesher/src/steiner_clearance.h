#pragma once

#include <Eigen/Core>
#include <vector>

#include "map_state.h"
#include "triangulation_editor.h"

namespace terramesh::mesher::internal {

/// Keeps lattice nodes away from the data: a Steiner node is in the triangulation only while no
/// inserted point lies within `clearance` (map units, below half the step) of it. A node that
/// close to a point cuts the cells around the point into slivers whose carving, and so the
/// surface, depends on where the lattice happens to lie (docs/accuracy.md, issue 14); without it
/// the cells near the data are those of the points alone. The rule is a function of the current
/// points, so moves and removals restore nodes that no point is near any more.
///
/// Nodes are only removed or restored when that destroys no cell of O (the enclosing set shrinks
/// around every changed position first); a node that cannot be is left as it is until a later
/// update changes a point near it.
class SteinerClearance {
 public:
  SteinerClearance(MapState& state, TriangulationEditor& editor) : state_(state), editor_(editor) {}

  /// Whether the rule is on (a positive clearance).
  bool enabled() const;

  /// Before inserting a point at `p`: removes the lattice node within the clearance of `p`, if
  /// any and if its star is outside O. Rays crossing its star are appended to `retrace`.
  /// @return true if a node was removed.
  bool clearAround(const Eigen::Vector3d& p, std::vector<RayId>& retrace);

  /// After the points at `old_positions` were removed or moved (and every insertion of the
  /// update is done): restores the lattice nodes near those positions that no point is within
  /// the clearance of any more. Rays crossing the destroyed cells are appended to `retrace`.
  /// @return the number of nodes restored.
  std::size_t restoreAround(const std::vector<Eigen::Vector3d>& old_positions, std::vector<RayId>& retrace);

 private:
  double clearance() const;
  /// The lattice node nearest to `p` if it lies inside the grid's box and within the clearance.
  bool nearNode(const Eigen::Vector3d& p, GridKey& node) const;

  MapState& state_;
  TriangulationEditor& editor_;
};

}  // namespace terramesh::mesher::internal
