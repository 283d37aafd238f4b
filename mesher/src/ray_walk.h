#pragma once

#include <cstddef>
#include <vector>

#include "cgal_types.h"
#include "ray_store.h"

namespace terramesh::mesher::internal {

/// Counters of the walks done in one update.
struct WalkCounters {
  std::size_t steps = 0;
  std::size_t cache_lookups = 0;
  std::size_t cache_hits = 0;
  std::size_t fallbacks = 0;  ///< rays walked from a displaced camera (degenerate geometry)
  std::size_t failures = 0;   ///< rays for which no displacement helped (left without a path)
  /// Walks stopped by the step bound: a straight walk enters each cell at most once, so it is
  /// cut after (cells + 1) steps. Never expected; counted, not hidden, should it ever happen.
  std::size_t step_limit_hits = 0;
};

/// Where a camera lies in the triangulation (from Delaunay::locate).
struct CameraLocation {
  Point position;
  CellHandle cell;
  Delaunay::Locate_type type = Delaunay::OUTSIDE_AFFINE_HULL;
  int li = -1;
  int lj = -1;
};

/// Walks the cells crossed by the segment from a camera to a point vertex, with exact orientation
/// predicates. In each cell the segment enters through one facet and leaves through the unique
/// facet whose interior it crosses: with the next-tetrahedron cache, the facet the previous ray
/// left the cell by is tested first (2 predicates when right). The set of cells is a function of
/// the segment and the triangulation only; the cache changes the order of tests, never the result.
///
/// Degenerate geometry (the camera on a facet, edge or vertex, or the segment leaving a cell
/// through an edge or vertex, so that no facet is crossed strictly) is resolved by walking again
/// from the camera displaced by a tiny fixed offset in a generic direction: still exact
/// predicates, and still a function of the segment and the triangulation only. (CGAL 5.5's segment
/// traverser is not used: in such cases it can stop in a cell that does not contain the target.)
class RayWalker {
 public:
  RayWalker(const Delaunay& tri, bool use_cache) : tri_(tri), use_cache_(use_cache) {}

  /// Fills `path` (cleared first) with the cells crossed from the camera to `target`, camera end
  /// first; the last cell is incident to `target`. Returns kWalkedStraight, or 1 + the index of
  /// the camera displacement that resolved a degenerate ray (path left empty if none did).
  std::uint8_t walk(const CameraLocation& camera, VertexHandle target, std::vector<CellHandle>& path,
                    WalkCounters& counters) const;

  /// Continues a straight walk from camera `camera_W` whose first cells are already in `path`
  /// (a prefix of the ray's path: alive cells, none incident to `target`). Returns false, with
  /// `path` back to the prefix, if the rest is degenerate (the caller then walks the whole ray).
  bool resume(const Point& camera_W, VertexHandle target, std::vector<CellHandle>& path,
              WalkCounters& counters) const;

  /// Walks the stretch of a straight ray between a prefix and a tail of its path, both still
  /// valid: from path[gap - 1] (gap >= 1) until the walk enters path[gap]. Fills `between` with the
  /// cells crossed in between (cleared first). Since the cells a segment crosses are a function of
  /// the segment and the triangulation, prefix + between + tail is then the ray's whole path.
  /// Returns false if the walk is degenerate or reaches the target without entering path[gap].
  bool bridge(const Point& camera_W, VertexHandle target, const std::vector<CellHandle>& path,
              std::size_t gap, std::vector<CellHandle>& between, WalkCounters& counters) const;

 private:
  bool walkStraight(const CameraLocation& camera, VertexHandle target,
                    std::vector<CellHandle>& path, WalkCounters& counters) const;
  /// Walks on from `cell` (the last cell of `path`, or the cell before it), entered through facet
  /// `entry`, or containing the camera when `entry` is negative, appending the cells crossed. Ends
  /// at the first cell incident to `target`, or at `stop` (appended too) if it comes first. False
  /// on degenerate geometry.
  bool walkFrom(CellHandle cell, int entry, const Point& q, VertexHandle target,
                std::vector<CellHandle>& path, WalkCounters& counters,
                const CellHandle& stop = CellHandle()) const;
  /// The facet through which segment q->p leaves a cell it contains, or -1 if not strict.
  int exitFromInside(const CellHandle& cell, const Point& q, const Point& p) const;
  /// The facet through which segment q->p leaves `cell` after entering through `entry`, or -1.
  int exitAfterEntry(const CellHandle& cell, int entry, const Point& q, const Point& p,
                     WalkCounters& counters) const;

  const Delaunay& tri_;
  bool use_cache_;
};

}  // namespace terramesh::mesher::internal
