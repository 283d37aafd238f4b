#pragma once
// The faces of a surface with the indexes the layers need: by key, by vertex (adjacency) and a
// hash grid in the horizontal plane. Internal to terramesh::traversability.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <tsl/robin_map.h>
#include <vector>

#include "mesher/surface_delta.h"
#include "traversability/layered_mesh.h"

namespace terramesh::traversability::internal {

/// A face as the layers see it. Coordinates "L" are metres in a frame whose z axis is up, so
/// "height" is z and the horizontal plane is xy.
struct StoredFace {
  mesher::FaceKey key;
  std::array<mesher::VertexKey, 3> vertices;
  std::array<Eigen::Vector3d, 3> positions_W;  ///< as given, map units
  std::array<Eigen::Vector3d, 3> p_L;          ///< metres, up = +z
  Eigen::Vector3d centroid_L = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_L = Eigen::Vector3d::UnitZ();  ///< unit (zero for a degenerate face)
  Eigen::Vector2d box_min = Eigen::Vector2d::Zero();    ///< horizontal bounding box
  Eigen::Vector2d box_max = Eigen::Vector2d::Zero();
  double min_z = 0;
  double max_z = 0;
  /// Twice the signed area of the horizontal projection (cached for heightAt).
  double projected_det = 0;
  std::uint32_t rays = 0;
  /// Rays through the free cell in front of the face (mesher::SurfaceFace::front_crossings).
  std::uint32_t front_crossings = 0;
  /// Rays through the cell behind the face (mesher::SurfaceFace::back_crossings), and how far
  /// behind its plane that cell reaches (back_depth: as given, map units; and in metres).
  std::uint32_t back_crossings = 0;
  double back_depth_W = 0;
  double back_depth_m = 0;
  /// Which sides of its plane its points were seen from (mesher::SurfaceFace::view_sides).
  std::uint8_t view_sides = 0;
  /// How many vertices are driven-ground samples (mesher::SurfaceFace::driven_vertices).
  std::uint8_t driven_vertices = 0;
  /// How many are undersides of driven ground (mesher::SurfaceFace::underside_vertices).
  std::uint8_t underside_vertices = 0;
  bool steiner = false;
  bool alive = false;
  /// With two or three driven vertices (a pose lookup set): the horizontal unit axis the robot
  /// drove along there (either sense), zero otherwise; and a point of the drive's centre line (the
  /// mean of the driven vertices' base origins, L).
  Eigen::Vector2d drive_axis = Eigen::Vector2d::Zero();
  Eigen::Vector2d drive_centre = Eigen::Vector2d::Zero();
  /// The horizontal normal of the drive's centre line (drive_axis turned a quarter left).
  Eigen::Vector2d driveNormal() const { return {-drive_axis.y(), drive_axis.x()}; }
  /// Where the drive's centre line lies from the centroid along driveNormal(), metres.
  double driveOffsetM() const { return driveNormal().dot(drive_centre - centroid_L.head<2>()); }
  FaceLayers layers;
  /// Fraction of the footprint samples that found ground on faces no steeper than max_slope
  /// (set with the local layers; tells a step riser from a steep ramp).
  float level_fraction = 0;
  /// Set with the local layers: whether the footprint fits at some heading (step, roughness and
  /// contact within the robot's limits there; a disc has one heading), and the contact of the
  /// heading the layers report (the best one), which the cost uses.
  bool footprint_fits = true;
  float heading_contact = 1;
  /// Set with the local layers: whether the footprint also fits at some heading in the worst case
  /// within the height uncertainty of the ground it stands on (unknown samples unsupported), away
  /// from possible obstacles (interpolated walls, the possible extension of measured ones).
  bool footprint_fits_worst = true;
  /// When it does not: the reason:: bits of what fails the worst case at the headings that fit
  /// as reconstructed (relief, possible obstacles, extensions, unconfirmed points).
  std::uint16_t worst_case_reasons = 0;
  /// Set with the local layers: the first face above the centroid is closing geometry lower than
  /// the robot (the clearance cannot be known to suffice).
  bool clearance_unknown_low = false;
  /// Set with the local layers: the face rises no more than max_step_m, or a measured point of an
  /// edge neighbour beyond it along its slope lies on its plane (a ramp, not a step hidden in
  /// the span).
  bool rise_confirmed = true;
  /// Set with the local layers: the extent along the slope, metres, over which the face's own
  /// vertices and the measured points of edge neighbours on its plane confirm it (infinite for
  /// walls and level faces).
  float slope_extent_m = std::numeric_limits<float>::infinity();
  /// Set by the footprint stage: the face is known (not closing geometry, enough rays) and lethal
  /// by its local layers; the inflation's sources.
  bool lethal = false;

  /// Height of the face's plane at horizontal position (x, y), if (x, y) lies in the face's
  /// horizontal projection and the face is not vertical.
  std::optional<double> heightAt(double x, double y) const;
};

/// Slot index of a stored face (stable while the face lives).
using Slot = std::uint32_t;

/// The few fields of a StoredFace that neighbourhood queries filter on, packed densely (a copy).
struct FaceBounds {
  Eigen::Vector2d box_min = Eigen::Vector2d::Zero();
  Eigen::Vector2d box_max = Eigen::Vector2d::Zero();
  double normal_z = 1;
  bool alive = false;
  float min_z = 0, max_z = 0;  ///< the face's height range, rounded outwards
};

/// What footprint sampling reads of a face, packed densely (a copy): its horizontal projection
/// relative to its first vertex, and the barycentric coordinates u (of vertex 0) and v (of
/// vertex 1) as affine functions of (x - x0, y - y0). Filled for faces that heightAt can sample.
struct SampleGeometry {
  Eigen::Vector2d box_min = Eigen::Vector2d::Zero();
  Eigen::Vector2d box_max = Eigen::Vector2d::Zero();
  double x0 = 0, y0 = 0;  ///< vertex 0's horizontal position
  double bx = 0, by = 0;  ///< vertex 1 - vertex 0
  double cx = 0, cy = 0;  ///< vertex 2 - vertex 0
  double ux = 0, uy = 0, vx = 0, vy = 0;  ///< u = 1 + ux dx + uy dy, v = vx dx + vy dy
  double z0 = 0, z1 = 0, z2 = 0;          ///< vertex heights
  double min_z = 0, max_z = 0;
  double normal_z = 1;
  Eigen::Vector2d normal_xy = Eigen::Vector2d::Zero();  ///< the normal's horizontal part (towards the front)
  bool sampleable = false;  ///< the projection is not degenerate (heightAt can find it)
  bool steiner = false;
  /// The face's evidence is interpolated (closing geometry or an unobserved span): as an obstacle
  /// it is only a possible one.
  bool interpolated = true;
  /// Whether a vertex is a driven-ground sample (StoredFace::driven_vertices > 0), and whether the
  /// face is driven ground (all three are, or it is the strip's edge: its evidence is driven).
  bool touches_driven = false;
  bool driven = false;
  /// The relief the face's span may hide (its height uncertainty bound less the noise floor that
  /// the measured step already shows: 0 for driven ground, +inf for closing geometry) and its
  /// longest horizontal edge, metres.
  double relief_m = std::numeric_limits<double>::infinity();
  double span_m = 0;

  /// Height of the face's plane at (x, y) if (x, y) lies in its projection (heightAt's test).
  std::optional<double> heightAt(double x, double y) const {
    const double dx = x - x0, dy = y - y0;
    const double u = 1.0 + (ux * dx + uy * dy);
    const double v = vx * dx + vy * dy;
    const double w = 1.0 - u - v;
    constexpr double kEps = -1e-12;
    if (u < kEps || v < kEps || w < kEps) return std::nullopt;
    return u * z0 + v * z1 + w * z2;
  }
};

/// std::hash remixed by murmur3's 64-bit finaliser. tsl::robin_map keeps power-of-two tables and
/// starts probing at the hash's low bits, which std::hash<std::uint64_t> (the identity on
/// libstdc++) leaves patterned for packed grid coordinates.
template <class Key>
struct MixedHash {
  std::size_t operator()(const Key& key) const noexcept {
    std::uint64_t h = static_cast<std::uint64_t>(std::hash<Key>{}(key));
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return static_cast<std::size_t>(h);
  }
};

/// The store's indexes: open addressing (Debian's robin-map-dev), no node per entry.
template <class Key, class Value>
using HashMap = tsl::robin_map<Key, Value, MixedHash<Key>>;

/// Faces by key, vertex and horizontal grid cell. Each face is registered in every grid cell its
/// horizontal bounding box overlaps, so point queries see large faces too, and in the one cell of
/// a second grid that holds its centroid (for "faces whose centroid is near" queries). The
/// queries are const and keep no scratch state; add and remove are not thread-safe.
class SurfaceStore {
 public:
  /// @param R_L_W rotation taking map-frame directions to L (up_W -> +z).
  /// @param cell_m cell of the grid of face boxes; @param centroid_cell_m cell of the grid of
  /// face centroids (both metres, > 0).
  SurfaceStore(const Eigen::Matrix3d& R_L_W, double metres_per_unit, double cell_m, double centroid_cell_m);

  /// Adds a face, replacing one with the same key. Returns its slot.
  /// @throw std::length_error if 2^30 slots are in use.
  Slot add(const mesher::SurfaceFace& face);
  /// Sets face s's drive_axis and drive_centre from the bases of its driven vertices (at least
  /// two; else zero): the mean of their horizontal axes, taken modulo a half turn (zero when they
  /// spread), and of their origins.
  void setDrive(Slot s, const std::function<std::optional<Eigen::Isometry3d>(mesher::PointId)>& lookup);
  /// Removes the face with this key; false if unknown.
  bool remove(const mesher::FaceKey& key);
  /// Removes the alive face in slot s (its slot may be reused by the next add).
  void removeSlot(Slot s);
  void clear();

  std::optional<Slot> find(const mesher::FaceKey& key) const;
  const StoredFace& face(Slot s) const { return faces_[s]; }
  StoredFace& face(Slot s) { return faces_[s]; }
  /// The face's box, normal z and liveness (equal to those of face(s)).
  const FaceBounds& bounds(Slot s) const { return bounds_[s]; }
  /// The face's sampling geometry (equal to that of face(s)).
  const SampleGeometry& geometry(Slot s) const { return geometry_[s]; }
  /// Sets the evidence fields of the face's sampling geometry (kept equal to its layers').
  void setSampleEvidence(Slot s, bool interpolated, bool driven, double relief_m) {
    geometry_[s].interpolated = interpolated;
    geometry_[s].driven = driven && !geometry_[s].steiner;
    geometry_[s].relief_m = relief_m;
  }
  /// The face's centroid (equal to face(s).centroid_L), packed densely.
  const Eigen::Vector3d& centroid(Slot s) const { return centroids_[s]; }
  /// Number of slots (alive or not).
  std::size_t slotCount() const { return faces_.size(); }
  std::size_t size() const { return by_key_.size(); }

  /// Calls f(slot) once for every alive face registered in a grid cell overlapping the box.
  template <class F>
  void forEachInBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, F&& f) const;
  /// Calls f(slot) for every alive face registered in the grid cell of (x, y) (a superset of the
  /// faces whose projection contains the point).
  template <class F>
  void forEachAt(double x, double y, F&& f) const;
  /// Calls f(slot) once for every alive face whose centroid lies in a centroid-grid cell
  /// overlapping the box (a superset of the faces whose centroid lies in the box; each face is in
  /// one cell, so no marks are needed and queries may nest).
  template <class F>
  void forEachCentroidInBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, F&& f) const;
  /// Reorders slots[first, last) to walk the plane locally (the Z-order of their centroids'
  /// cells, kLocalityCellM wide; ties by slot): faces judged one after another then read mostly
  /// the same nearby faces, which stay in the cache. Deterministic.
  void sortByLocality(std::vector<Slot>& slots, std::size_t first, std::size_t last) const;
  /// Every alive slot, in sortByLocality's order.
  std::vector<Slot> aliveSlotsByLocality() const;
  /// Faces sharing an edge with `s`.
  void neighbours(Slot s, std::vector<Slot>& out) const;
  /// Calls f(slot) for every face other than `s` that shares a vertex with it (a face sharing an
  /// edge is reported twice).
  template <class F>
  void forEachVertexNeighbour(Slot s, F&& f) const;

 private:
  /// Cell of sortByLocality's order: a fraction of any footprint (the Z-order is local at every
  /// coarser scale too).
  static constexpr double kLocalityCellM = 0.25;
  using CellKey = std::uint64_t;
  /// An entry of a cell list of grid_: the slot, and whether the cell is not in the first column
  /// or not in the first row of the cells the face's box overlaps (forEachInBox's deduplication).
  using GridEntry = std::uint32_t;
  static constexpr GridEntry kNotFirstColumn = 1u << 31;
  static constexpr GridEntry kNotFirstRow = 1u << 30;
  static constexpr GridEntry kSlotMask = kNotFirstRow - 1;
  CellKey cellKey(std::int64_t i, std::int64_t j) const;
  std::int64_t cellIndex(double v) const;
  std::int64_t centroidCellIndex(double v) const;
  CellKey centroidCellKey(const Eigen::Vector3d& c) const;
  void link(Slot s);
  void unlink(Slot s);
  /// Unlinks slot s and frees it (its key already erased).
  void release(Slot s);

  Eigen::Matrix3d R_L_W_;
  double metres_per_unit_;
  double cell_m_;
  std::vector<StoredFace> faces_;
  std::vector<FaceBounds> bounds_;
  std::vector<SampleGeometry> geometry_;
  std::vector<Eigen::Vector3d> centroids_;
  std::vector<Slot> free_slots_;
  HashMap<mesher::FaceKey, Slot> by_key_;
  HashMap<mesher::VertexKey, std::vector<Slot>> by_vertex_;
  double centroid_cell_m_;
  /// Faces by the cell of their centroid (cells are kept when they empty, as in grid_).
  HashMap<CellKey, std::vector<Slot>> centroid_grid_;
  /// Cells are kept when they empty (their lists are reused: no allocation churn); the number of
  /// cells is bounded by the area ever mapped.
  HashMap<CellKey, std::vector<GridEntry>> grid_;
};

inline std::optional<double> StoredFace::heightAt(double x, double y) const {
  const double det = projected_det;
  if (std::abs(det) < 1e-12) return std::nullopt;
  const double ax = p_L[0].x(), ay = p_L[0].y(), bx = p_L[1].x(), by = p_L[1].y(), cx = p_L[2].x(), cy = p_L[2].y();
  const double u = ((bx - x) * (cy - y) - (cx - x) * (by - y)) / det;
  const double v = ((cx - x) * (ay - y) - (ax - x) * (cy - y)) / det;
  const double w = 1.0 - u - v;
  constexpr double kEps = -1e-12;
  if (u < kEps || v < kEps || w < kEps) return std::nullopt;
  return u * p_L[0].z() + v * p_L[1].z() + w * p_L[2].z();
}

template <class F>
void SurfaceStore::forEachInBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, F&& f) const {
  const std::int64_t i0 = cellIndex(lo.x()), i1 = cellIndex(hi.x());
  const std::int64_t j0 = cellIndex(lo.y()), j1 = cellIndex(hi.y());
  for (std::int64_t i = i0; i <= i1; ++i) {
    for (std::int64_t j = j0; j <= j1; ++j) {
      const auto it = grid_.find(cellKey(i, j));
      if (it == grid_.end()) continue;
      const std::vector<GridEntry>* list = &it->second;
      // A face is reported in the first cell (i, then j) of the query that it overlaps: the cell
      // of the query's first column or of the face's first column, and likewise for rows. This
      // is where a scan with "seen" marks would report it, in the same order, without the marks.
      const GridEntry skip = (i == i0 ? 0u : kNotFirstColumn) | (j == j0 ? 0u : kNotFirstRow);
      for (const GridEntry e : *list) {
        if (e & skip) continue;
        f(static_cast<Slot>(e & kSlotMask));
      }
    }
  }
}

template <class F>
void SurfaceStore::forEachVertexNeighbour(Slot s, F&& f) const {
  for (const mesher::VertexKey& v : faces_[s].vertices) {
    const auto it = by_vertex_.find(v);
    if (it == by_vertex_.end()) continue;
    for (const Slot t : it->second) {
      if (t != s) f(t);
    }
  }
}

template <class F>
void SurfaceStore::forEachCentroidInBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, F&& f) const {
  const std::int64_t i0 = centroidCellIndex(lo.x()), i1 = centroidCellIndex(hi.x());
  const std::int64_t j0 = centroidCellIndex(lo.y()), j1 = centroidCellIndex(hi.y());
  for (std::int64_t i = i0; i <= i1; ++i) {
    for (std::int64_t j = j0; j <= j1; ++j) {
      const auto it = centroid_grid_.find(cellKey(i, j));
      if (it == centroid_grid_.end()) continue;
      for (Slot s : it->second) f(s);
    }
  }
}

template <class F>
void SurfaceStore::forEachAt(double x, double y, F&& f) const {
  const auto it = grid_.find(cellKey(cellIndex(x), cellIndex(y)));
  if (it == grid_.end()) return;
  for (const GridEntry e : it->second) f(static_cast<Slot>(e & kSlotMask));
}

}  // namespace terramesh::traversability::internal
