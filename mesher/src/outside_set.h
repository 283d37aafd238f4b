#pragma once

#include <vector>

#include "boundary_hash.h"
#include "cgal_types.h"
#include "manifold_test.h"
#include "mark_epochs.h"
#include "point_registry.h"
#include "steiner_grid.h"
#include "surface_log.h"

namespace terramesh::mesher::internal {

/// The outside set O: free-space cells whose boundary is the output surface. Keeps the per-vertex
/// count of incident O-cells and the boundary hash in step with every change, and answers whether
/// a change keeps the boundary a 2-manifold.
class OutsideSet {
 public:
  OutsideSet(const Delaunay& tri, const SteinerGrid& grid, BoundaryHash& hash, MarkEpochs& epochs)
      : tri_(tri), grid_(grid), hash_(hash), epochs_(epochs), test_(epochs) {}

  std::size_t size() const { return size_; }

  /// True if adding `cell` (not in O, finite) keeps every boundary vertex regular.
  bool canAdd(CellHandle cell);
  /// True if removing `cell` (in O) keeps every boundary vertex regular.
  bool canRemove(CellHandle cell);
  /// True if adding all `cells` (none in O, all finite) at once keeps the boundary manifold; if
  /// not, and `failed` is given, a vertex that would not stay regular goes to it.
  bool canAddAll(const std::vector<CellHandle>& cells, VertexHandle* failed = nullptr);
  /// True if removing all `cells` (all in O) at once keeps the boundary manifold.
  bool canRemoveAll(const std::vector<CellHandle>& cells);

  /// From now on, records in `log` every surface face that add and remove create or destroy
  /// (vertex keys taken from `registry`).
  void attachLog(SurfaceLog& log, const PointRegistry& registry) {
    log_ = &log;
    registry_ = &registry;
  }

  void add(CellHandle cell);
  void remove(CellHandle cell);

  /// Tells the log that the surface faces bounded by `cell` (on either side: in O, or the cell
  /// behind a face) may be observed differently.
  void touchFacesOf(const CellHandle& cell);

  /// Stable key of a finite vertex: its point's id, or its Steiner lattice node. Requires a log
  /// attached (for the registry).
  /// Computed once per vertex, then read from VertexInfo::key.
  VertexKey vertexKey(const VertexHandle& v) const {
    VertexInfo& info = v->info();
    if (!info.key_cached) {
      info.key = computeVertexKey(v).value;
      info.key_cached = true;
    }
    return {info.key, info.point == kNone};
  }

  /// Regularity of `v` for the current O (invariant checks).
  bool isRegular(VertexHandle v);

  /// Hash key of a vertex: the Steiner cell containing it.
  GridKey keyOf(VertexHandle v) const { return grid_.cellOf(toEigen(v->point())); }

 private:
  friend class CheckpointAccess;

  /// Whether a cell other than `cell` around its edge (vertex i, vertex j) is (or is not) in O.
  bool anyAroundEdge(const CellHandle& cell, int i, int j, bool in_outside) const;
  /// Regularity of every vertex of `cells` when cells flagged kCellPending flip membership.
  bool pendingChangeKeepsManifold(const std::vector<CellHandle>& cells, bool adding, VertexHandle* failed = nullptr);
  void vertexGainedCell(VertexHandle v);
  void vertexLostCell(VertexHandle v);
  VertexKey computeVertexKey(const VertexHandle& v) const {
    if (v->info().point != kNone) return VertexKey::point(registry_->point(v->info().point).id);
    const GridKey node = grid_.nodeOf(toEigen(v->point()));
    return VertexKey::steinerNode(node.i, node.j, node.k);
  }
  /// Logs the faces `cell` gains or loses by entering (or leaving) O; its flag already changed.
  void logFacets(const CellHandle& cell, bool entering);

  const Delaunay& tri_;
  const SteinerGrid& grid_;
  BoundaryHash& hash_;
  MarkEpochs& epochs_;
  VertexRegularityTest test_;
  std::size_t size_ = 0;
  SurfaceLog* log_ = nullptr;
  const PointRegistry* registry_ = nullptr;
};

}  // namespace terramesh::mesher::internal
