#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mesher/ids.h"
#include "mesher/keyframe.h"
#include "mesher/mesher_config.h"
#include "mesher/surface_delta.h"
#include "mesher/triangle_mesh.h"
#include "mesher/update_stats.h"

namespace terramesh::mesher {

/// Sizes of the map and an estimate of the memory it holds.
struct MapSize {
  std::size_t keyframes = 0;
  std::size_t points = 0;           ///< points known (inserted or waiting)
  std::size_t inserted_points = 0;  ///< points with a vertex in the triangulation
  std::size_t steiner_vertices = 0;
  std::size_t cells = 0;            ///< cells, including the infinite ones on the hull
  std::size_t outside_cells = 0;    ///< cells in O
  std::size_t rays = 0;             ///< stored visibility rays
  std::size_t ray_crossings = 0;    ///< cells on stored ray paths, summed over rays

  std::size_t triangulation_bytes = 0;  ///< vertices and cells
  std::size_t ray_bytes = 0;            ///< ray records, paths and per-cell ray lists
  std::size_t point_bytes = 0;          ///< point and keyframe records
  std::size_t index_bytes = 0;          ///< id maps, the boundary hash and the surface history
  std::size_t totalBytes() const { return triangulation_bytes + ray_bytes + point_bytes + index_bytes; }
};

/// Visibility state of one finite cell of the triangulation (for inspection and comparison).
struct CellVisibility {
  /// The cell's vertices, sorted lexicographically, in map units.
  std::array<Eigen::Vector3d, 4> vertices_W;
  /// Inverse-cone weight (same units as the config's weights).
  double weight = 0;
  /// Number of stored rays crossing the cell.
  std::uint32_t crossings = 0;
  /// Whether the cell is in the outside set O.
  bool outside = false;
  /// Stored rays to driven-ground samples crossing the cell.
  std::uint32_t driven_crossings = 0;
  /// Whether the cell is free space (its weight, with the ground rule of driven-ground samples),
  /// in O or not.
  bool free = false;
};

/// A SLAM point observed but not in the triangulation: fewer than `min_views` keyframes within
/// `max_camera_distance_m` see it (a rock seen from one keyframe, a point still waiting for its
/// second view). It shapes no surface; traversability treats it as a possible obstacle.
struct UnconfirmedPoint {
  PointId id;
  /// Latest estimate, in the world frame W, in map units.
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  /// Keyframes observing it (in range or not).
  std::uint32_t views = 0;
};

/// A position in the history of the unconfirmed points (Mesher::unconfirmedChangesSince): which
/// mesher, and after which of its updates.
struct UnconfirmedCursor {
  std::uint64_t instance = 0;
  std::uint64_t revision = 0;
};

/// The unconfirmed points that may have changed since a cursor, as they are now.
struct UnconfirmedChanges {
  /// Now: the cursor to pass next time.
  UnconfirmedCursor cursor;
  /// False when the cursor is another mesher's or older than the history kept: then nothing
  /// else is filled, and unconfirmedPoints() gives the whole set.
  bool complete = false;
  /// Points that may have changed and are unconfirmed now, sorted by id.
  std::vector<UnconfirmedPoint> waiting;
  /// Points that may have changed and are not unconfirmed now (inserted, removed), sorted.
  std::vector<PointId> gone;
};

/// Result of Mesher::checkInvariants: every violation found, described in one line each.
struct InvariantReport {
  std::vector<std::string> violations;
  bool ok() const { return violations.empty(); }
  /// The first few violations joined, or "ok".
  std::string summary(std::size_t max_lines = 5) const;
};

namespace internal {
class CheckpointAccess;
}  // namespace internal

/// Incremental manifold mesh reconstruction from SLAM keyframes (Piazza et al., RA-L 2018).
///
/// Keeps a 3D Delaunay triangulation of the SLAM points plus a Steiner grid, a visibility weight
/// per cell from camera-to-point rays, and a set O of free-space cells whose boundary is always a
/// closed, oriented 2-manifold. Each update inserts, moves and removes points and rays exactly:
/// after any sequence of updates the weights equal a from-scratch recomputation over the stored
/// rays.
///
/// Not thread-safe: one thread at a time. Every update returns what it did and how long each
/// step took; the library never prints.
class Mesher {
 public:
  /// @throw std::invalid_argument if the configuration is invalid (see MesherConfig::validate).
  explicit Mesher(const MesherConfig& config);
  ~Mesher();
  Mesher(Mesher&&) noexcept;
  Mesher& operator=(Mesher&&) noexcept;
  Mesher(const Mesher&) = delete;
  Mesher& operator=(const Mesher&) = delete;

  /// Integrates a keyframe, or replaces an earlier one with the same id (corrected pose, new
  /// observation list). Observed points take the given positions: new points enter once seen by
  /// `min_views` keyframes in range, inserted points that moved are removed and re-inserted.
  /// @throw std::invalid_argument if a coordinate or the rotation is not finite, the keyframe
  ///        lists a point twice, or its camera and points in range would grow the Steiner grid
  ///        beyond 16 Mi nodes (the map's extent does not fit its units or the grid step); the
  ///        map is then unchanged.
  UpdateStats integrateKeyframe(const Keyframe& keyframe);

  /// Deletes points (e.g. culled by SLAM) with all their rays. Unknown ids are ignored.
  UpdateStats removePoints(const std::vector<PointId>& points);

  /// Deletes a keyframe and its rays; points left without any ray are removed too.
  /// Unknown ids are ignored.
  UpdateStats removeKeyframe(KeyframeId keyframe);

  /// Deletes several keyframes in one update (their rays, and the points left without any);
  /// unknown ids are ignored. The online freeze retires keyframes so.
  UpdateStats removeKeyframes(const std::vector<KeyframeId>& keyframes);

  /// Lets go of the Steiner lattice far from the data still in use (the online freeze: call it after
  /// removing the keyframes of a region left behind). Every Steiner vertex farther than `reach_m`
  /// plus the grid's margin and two cells from each of `keep_W` (map units: the cameras of the
  /// keyframes kept) whose cells are outside O, crossed by no ray and spanned by Steiner vertices
  /// only leaves the triangulation (but for a node on the hull whose neighbours lie in one plane);
  /// the surface and every ray are unchanged. From the first call
  /// on, the lattice grows only around new data (not as a whole box), and comes back where data
  /// comes back. Not in the baselines' fixed grid (then a no-op). A checkpoint keeps the lattice
  /// nodes held (saveCheckpoint). O(Steiner vertices).
  /// @throw std::invalid_argument if `reach_m` is not finite and >= 0.
  UpdateStats releaseFarSteiner(const std::vector<Eigen::Vector3d>& keep_W, double reach_m);

  /// The boundary of O as a closed, consistently oriented 2-manifold (vertices include Steiner
  /// vertices, flagged in `is_steiner`), in a canonical order: vertices sorted by position, faces
  /// sorted, so equal surfaces give equal meshes. O(cells + F log F).
  TriangleMesh extractMesh() const;

  /// Revision of the surface: starts at 0 and grows by one with every update call that changed
  /// the surface or the observation of its vertices. O(1).
  std::uint64_t revision() const;

  /// Faces added and removed, and vertices touched, since `revision` (see SurfaceDelta). Exact:
  /// every surface change goes through adding or removing a cell of O. Cost proportional to the
  /// changes since `revision`, not to the map. History older than the last
  /// `kSurfaceHistoryRevisions` revisions, or beyond MesherConfig::surface_history_max_bytes, is
  /// forgotten: asking for it gives `complete == false`.
  /// @throw std::invalid_argument if `revision` is greater than revision().
  SurfaceDelta changesSince(std::uint64_t revision) const;

  /// Revisions of surface history kept for changesSince.
  static constexpr std::uint64_t kSurfaceHistoryRevisions = 4096;

  /// Every face of the current surface with its observation counts, sorted by key. O(F log F).
  std::vector<SurfaceFace> surfaceFaces() const;

  /// The current surface faces having a vertex in `vertices`, with their observation counts,
  /// sorted by key, without repeats; unknown keys are ignored. Use it with
  /// SurfaceDelta::touched_vertices to refresh the counts of faces that changed only in how they
  /// were observed. O(sum of the vertices' degrees + result log result).
  std::vector<SurfaceFace> facesAround(const std::vector<VertexKey>& vertices) const;

  /// Every unconfirmed SLAM point (driven-ground samples never are), sorted by id. O(n log n) in
  /// their number, kept current by every update.
  std::vector<UnconfirmedPoint> unconfirmedPoints() const;
  /// The cursor of the current state (with unconfirmedPoints(): where its history starts).
  UnconfirmedCursor unconfirmedCursor() const;
  /// What changed in the unconfirmed set since `cursor`: the points any update since logged (a
  /// superset of those that entered, left or moved), as they are now. Kept for the last
  /// 256 updates. O(points logged log points logged).
  UnconfirmedChanges unconfirmedChangesSince(const UnconfirmedCursor& cursor) const;

  MapSize size() const;
  const MesherConfig& config() const;

  /// Every finite cell with its weight, crossing count and membership of O, sorted by vertices.
  /// O(cells log cells); meant for tests, debugging and visualisation.
  std::vector<CellVisibility> cellVisibility() const;

  /// Full consistency check, for tests: triangulation validity, every boundary vertex regular,
  /// per-vertex counters, the boundary hash, ray paths equal to fresh walks, and cell weights
  /// equal to a from-scratch recomputation over all stored rays. O(map size x ray length).
  InvariantReport checkInvariants() const;

 private:
  friend class internal::CheckpointAccess;  // saveCheckpoint / loadCheckpoint (mesher/checkpoint.h)
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terramesh::mesher
