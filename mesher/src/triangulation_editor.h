#pragma once

#include <vector>

#include "map_state.h"
#include "visibility_tracer.h"

namespace terramesh::mesher::internal {

/// Changes the triangulation's topology while keeping the side structures exact:
/// - before cells are destroyed, the rays crossing them are untraced and flagged kRayNeedsTrace
///   (appended to the caller's retrace list), so no stored path ever names a dead cell;
/// - new cells get a uid, and their weights and those of their neighbours are recomputed.
/// It never destroys a cell of O: insertions whose conflict zone meets O are refused, and vertex
/// removal requires a star outside O.
class TriangulationEditor {
 public:
  TriangulationEditor(MapState& state, VisibilityTracer& tracer) : state_(state), tracer_(tracer) {}

  enum class InsertResult { kInserted, kConflictsWithOutside, kDuplicate, kOutsideHull };

  /// Inserts `position` as the vertex of point `point_index` (kNone for a Steiner vertex).
  InsertResult insert(const Eigen::Vector3d& position, std::uint32_t point_index,
                      std::vector<RayId>& retrace, VertexHandle& vertex);

  /// Whether inserting `position` now would destroy a cell of O (or hit a vertex).
  bool conflictsWithOutside(const Eigen::Vector3d& position);

  /// True if a cell incident to `v` is in O.
  bool starTouchesOutside(VertexHandle v);

  /// Removes vertex `v`. Requires !starTouchesOutside(v) and no stored ray ending at v.
  void remove(VertexHandle v, std::vector<RayId>& retrace);

  /// Inserts the first Steiner points when the triangulation is empty (dimension < 3 phase).
  void bootstrap(const std::vector<Eigen::Vector3d>& steiner_points);

 private:
  friend class CheckpointAccess;

  /// Orders cells by their sorted vertex keys (the infinite vertex last): independent of memory.
  void sortByVertexKeys(std::vector<CellHandle>& cells) const;
  void untraceCrossing(const std::vector<CellHandle>& doomed, std::vector<RayId>& retrace);
  /// Vertex degrees lose the cells about to be destroyed.
  void forgetCells(const std::vector<CellHandle>& doomed);
  void registerNewCells(const std::vector<CellHandle>& cells);

  MapState& state_;
  VisibilityTracer& tracer_;
  CellHandle hint_;
  std::vector<CellHandle> conflict_cells_;
  std::vector<Facet> boundary_facets_;
  std::vector<CellHandle> new_cells_;
  std::vector<RayId> batch_;
  std::vector<Crossing> crossings_;
};

}  // namespace terramesh::mesher::internal
