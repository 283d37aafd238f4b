#pragma once
// The only header that names CGAL's kernel, vertex/cell bases and triangulation. Internal to the
// mesher: public headers speak Eigen.

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace terramesh::mesher::internal {

inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// Per-vertex data. Trivially copyable.
struct VertexInfo {
  /// VertexKey::value of this vertex's stable key, cached by OutsideSet::vertexKey once
  /// `key_cached` is set (the key of a vertex never changes while it exists).
  std::uint64_t key = 0;
  /// Index of the SLAM point in PointRegistry, or kNone for Steiner and the infinite vertex.
  std::uint32_t point = kNone;
  /// Position of this vertex in its boundary-hash bucket, kNone if not hashed.
  std::uint32_t hash_slot = kNone;
  /// Scratch visit mark compared against a per-pass epoch.
  std::uint32_t mark = 0;
  /// Number of incident cells in the outside set O.
  std::uint16_t outside_cells = 0;
  /// Number of incident cells (finite or not); kept by TriangulationEditor.
  std::uint16_t degree = 0;
  bool steiner = false;
  bool key_cached = false;
};
static_assert(std::is_trivially_copyable_v<VertexInfo>);

/// Flags of CellInfo::flags.
enum CellFlag : std::uint8_t {
  kCellOutside = 1u << 0,    ///< in the outside set O
  kCellQueued = 1u << 1,     ///< in a grow/shrink queue
  kCellPending = 1u << 2,    ///< member of a tentative set in a manifold test
  kCellEnclosed = 1u << 3,   ///< scratch: known to be in the enclosing set
  kCellCandidate = 1u << 4,  ///< in the list of grow candidates of this update
};

/// Per-cell data, kept small and trivially copyable; ray lists live in a side table.
struct CellInfo {
  /// Inverse-cone weight in fixed point (1/16 units): a function of `crossings` in the 2-ring.
  std::int32_t weight = 0;
  /// Number of stored rays whose path crosses this cell.
  std::uint32_t crossings = 0;
  /// ... of which spread votes to the neighbours: all but those ending in this cell (the apex of
  /// the inverse cone, incident to the ray's point).
  std::uint32_t spreading = 0;
  /// ... of which end at a driven-ground sample (the robot's body volume): see MapState::isFree.
  std::uint32_t driven_crossings = 0;
  /// Unique stamp given at creation; validates handles kept across topology changes.
  std::uint32_t uid = 0;
  /// Slot of this cell's ray list in RayStore, kNone if no ray crosses it.
  std::uint32_t ray_list = kNone;
  /// Scratch visit mark compared against a per-pass epoch.
  std::uint32_t mark = 0;
  std::uint8_t flags = 0;
  /// Next-tetrahedron cache: facet through which the last ray left this cell (4 = none).
  std::uint8_t next_facet = 4;

  bool outside() const { return (flags & kCellOutside) != 0; }
};

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<VertexInfo, Kernel>;
using CellBase = CGAL::Triangulation_cell_base_with_info_3<CellInfo, Kernel>;
using Tds = CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;

using VertexHandle = Delaunay::Vertex_handle;
using CellHandle = Delaunay::Cell_handle;
using Facet = Delaunay::Facet;

/// A cell handle with the uid it had when stored: detects cells destroyed meanwhile.
struct StampedCell {
  CellHandle cell;
  std::uint32_t uid = 0;
};

inline Point toPoint(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }
inline Eigen::Vector3d toEigen(const Point& p) { return {p.x(), p.y(), p.z()}; }

/// Vertex indices of facet `i` of a cell wound so that its normal points out of the cell.
inline int outwardFacetVertex(int i, int k) {
  // CGAL's vertex_triple_index winds facets with the normal towards the cell; reverse it.
  static constexpr int kOrder[3] = {0, 2, 1};
  return Delaunay::vertex_triple_index(i, kOrder[k]);
}

}  // namespace terramesh::mesher::internal
