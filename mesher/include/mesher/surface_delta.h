#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "mesher/ids.h"

namespace terramesh::mesher {

/// Stable identity of a surface vertex: the SLAM point's id, or the Steiner lattice node it sits
/// on. A point keeps its key when it moves; a Steiner node's key is its lattice index.
struct VertexKey {
  /// PointId::value for points; for Steiner nodes the lattice index (i, j, k), each biased by
  /// 2^20 and packed in 21 bits (i in the low bits).
  std::uint64_t value = 0;
  bool steiner = false;

  static VertexKey point(PointId id) { return {id.value, false}; }
  /// @pre each index within [-2^20, 2^20).
  static VertexKey steinerNode(std::int32_t i, std::int32_t j, std::int32_t k) {
    constexpr std::int64_t kBias = std::int64_t{1} << 20;
    constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
    const auto pack = [&](std::int32_t x) { return static_cast<std::uint64_t>(x + kBias) & kMask; };
    return {pack(i) | (pack(j) << 21) | (pack(k) << 42), true};
  }

  friend bool operator==(const VertexKey& a, const VertexKey& b) {
    return a.value == b.value && a.steiner == b.steiner;
  }
  friend bool operator!=(const VertexKey& a, const VertexKey& b) { return !(a == b); }
  /// Points before Steiner nodes, then by value.
  friend bool operator<(const VertexKey& a, const VertexKey& b) {
    return a.steiner != b.steiner ? b.steiner : a.value < b.value;
  }
};

/// Stable identity of a surface face: its three vertex keys, sorted ascending. A face keeps its
/// key for as long as it exists (and gets the same key back if the same triple reappears).
struct FaceKey {
  std::array<VertexKey, 3> sorted;

  /// The key of the face with these vertices, in any order.
  static FaceKey of(VertexKey a, VertexKey b, VertexKey c);

  friend bool operator==(const FaceKey& a, const FaceKey& b) { return a.sorted == b.sorted; }
  friend bool operator!=(const FaceKey& a, const FaceKey& b) { return !(a == b); }
  friend bool operator<(const FaceKey& a, const FaceKey& b) { return a.sorted < b.sorted; }
};

/// One face of the surface (the boundary of the outside set O) with what a consumer needs to
/// place and judge it.
struct SurfaceFace {
  FaceKey key;
  /// The vertices wound counter-clockwise seen from free space (normal out of the matter).
  std::array<VertexKey, 3> vertices;
  /// Their positions, same order, in map units.
  std::array<Eigen::Vector3d, 3> positions_W;
  /// How well it was observed: visibility rays ending on its vertices plus rays crossing the
  /// free cell in front of it (the O-cell the face bounds), counted when the face was reported.
  std::uint32_t rays = 0;
  /// Rays crossing the free cell in front of the face (the O-cell it bounds), part of `rays`:
  /// whether any observation passed through the free space over the face's interior, counted
  /// when the face was reported.
  std::uint32_t front_crossings = 0;
  /// Rays crossing the cell behind the face (the matter-side cell it bounds), counted when the
  /// face was reported: observations that passed through space the surface closes off. The
  /// surface keeps such a cell out of O only where adding it would break the 2-manifold (a lid
  /// over a pit whose rim and floor are both on the surface), so rays behind a face contradict it.
  std::uint32_t back_crossings = 0;
  /// How far behind the face's plane that cell reaches: the distance of its fourth vertex from the
  /// plane, in map units, when rays cross it (`back_crossings > 0`); 0 otherwise.
  double back_depth = 0;
  /// True if a vertex is a Steiner vertex (the face closes the map, it was not measured).
  bool touches_steiner = false;
  /// How many of its vertices (0-3) are driven-ground samples (PointKind::kDrivenGround): ground
  /// the robot's own trajectory put there.
  std::uint8_t driven_vertices = 0;
  /// How many of its vertices are undersides of driven ground (PointKind::kDrivenUnderside).
  std::uint8_t underside_vertices = 0;
  /// On which sides of the face's plane lie the keyframes whose rays end on its vertices
  /// (view_side bits, counted when the face was reported); a view within view_side::kGrazingDeg
  /// of the plane counts for neither. view_side::kBehind alone: its points were seen only from
  /// behind, so the side it faces, the one a robot would stand on, was never observed (the top
  /// of a ceiling slab seen from below).
  std::uint8_t view_sides = 0;
};

/// Bits of SurfaceFace::view_sides.
namespace view_side {
inline constexpr std::uint8_t kFront = 1;   ///< a keyframe in front of the plane (the free side)
inline constexpr std::uint8_t kBehind = 2;  ///< a keyframe behind it (the matter side)
/// Views closer to the plane than this show neither side: the points' noise tilts a face by a
/// few degrees (3 cm over 1 m is 1.7 degrees).
inline constexpr double kGrazingDeg = 10.0;
}  // namespace view_side

/// What changed on the surface between two revisions of a Mesher.
///
/// Replaying a delta onto the face set of revision `from_revision` (erase `removed`, then insert
/// `added`) gives exactly the face set of `to_revision`. A face that was removed and re-added in
/// between (e.g. a vertex moved) is in both lists; `added` carries its current geometry.
struct SurfaceDelta {
  std::uint64_t from_revision = 0;
  std::uint64_t to_revision = 0;
  /// False when the history back to `from_revision` has been forgotten (it is older than
  /// Mesher::kSurfaceHistoryRevisions, or than the history that fits in
  /// MesherConfig::surface_history_max_bytes); the caller must then rebuild from
  /// Mesher::surfaceFaces().
  /// `removed`, `added` and `touched_vertices` are empty in that case.
  bool complete = true;
  /// Faces that existed at `from_revision` and were removed since (some may exist again).
  std::vector<FaceKey> removed;
  /// Faces that exist at `to_revision` and were added since `from_revision`.
  std::vector<SurfaceFace> added;
  /// Vertices that moved, gained or lost faces, or whose point gained or lost rays; sorted,
  /// without repeats. Faces around them may have new observation counts.
  std::vector<VertexKey> touched_vertices;

  bool empty() const { return complete && removed.empty() && added.empty() && touched_vertices.empty(); }
};

}  // namespace terramesh::mesher

template <>
struct std::hash<terramesh::mesher::VertexKey> {
  std::size_t operator()(const terramesh::mesher::VertexKey& key) const noexcept {
    return std::hash<std::uint64_t>{}(key.value * 0x9E3779B97F4A7C15ull ^ (key.steiner ? 0x5bd1e995ull : 0));
  }
};

template <>
struct std::hash<terramesh::mesher::FaceKey> {
  std::size_t operator()(const terramesh::mesher::FaceKey& key) const noexcept {
    std::size_t h = 0;
    for (const auto& v : key.sorted) h = h * 0x100000001B3ull ^ std::hash<terramesh::mesher::VertexKey>{}(v);
    return h;
  }
};
