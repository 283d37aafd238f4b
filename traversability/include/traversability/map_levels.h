#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "traversability/layered_mesh.h"

namespace terramesh::traversability {

/// The horizontal map frame of the 2D exports, in metres.
///
/// Axes: `z_W` = up; `x_W` = the world x axis projected onto the plane perpendicular to up
/// (world y if x is within 30 degrees of up); `y_W` = z_W x x_W (right-handed). A map-frame point
/// is (x_W . p, y_W . p, z_W . p) * metres_per_unit: the plan position (x, y) and the height.
/// With up = +z this is the world frame itself, scaled to metres.
struct MapPlane {
  Eigen::Vector3d x_W = Eigen::Vector3d::UnitX();
  Eigen::Vector3d y_W = Eigen::Vector3d::UnitY();
  Eigen::Vector3d z_W = Eigen::Vector3d::UnitZ();
  double metres_per_unit = 1.0;

  /// @throw std::invalid_argument if `up_W` is not finite and non-zero or the scale not > 0.
  static MapPlane fromUp(const Eigen::Vector3d& up_W, double metres_per_unit);
  /// Plan position of a map point, metres.
  Eigen::Vector2d planM(const Eigen::Vector3d& p_W) const {
    return {x_W.dot(p_W) * metres_per_unit, y_W.dot(p_W) * metres_per_unit};
  }
  /// Height of a map point along up, metres.
  double heightM(const Eigen::Vector3d& p_W) const { return z_W.dot(p_W) * metres_per_unit; }
};

/// Options of the level segmentation (see segmentLevels).
struct LevelConfig {
  /// Two walkable faces whose plan footprints share a cell but whose heights there differ by more
  /// than this never go into one level; must be below a storey height.
  double level_separation_m = 1.5;
  /// Cell size of the plan grid on which overlaps are tested.
  double overlap_cell_m = 0.5;
  /// Levels with less walkable plan area that fit into no other level are dropped (their faces
  /// are then attached like lethal faces).
  double min_level_area_m2 = 4.0;
  /// ... and so are levels smaller than this fraction of the largest level: fragments of a
  /// noisy reconstruction that overlap every real floor are not floors of their own.
  double min_level_fraction = 0.1;
  /// A non-walkable face is attached to the nearest level that has walkable surface within
  /// this plan distance and height distance `level_separation_m`; else to no level.
  double attach_radius_m = 1.0;
  /// Faces whose normal points more than this far below the horizon (ceilings, the closing
  /// faces over the map) are never attached: they would hide the floor beneath them.
  double max_downward_deg = 30.0;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Faces split into walkable levels, each single-valued over the plan (a 2.5D map). Walkable: free
/// or uncertain (measured surface a robot may stand on) and facing up.
struct Levels {
  static constexpr std::int32_t kNone = -1;
  /// Per face: its level, or kNone.
  std::vector<std::int32_t> face_level;
  /// Per face: true if it is one of the level's walkable faces (not merely attached to it).
  std::vector<std::uint8_t> walkable;
  /// Per level: mean height of its walkable faces (area-weighted), metres. Levels are numbered
  /// by increasing mean height.
  std::vector<double> mean_height_m;
  /// Per level: plan area of its walkable faces, m^2.
  std::vector<double> walkable_area_m2;

  std::size_t count() const { return mean_height_m.size(); }
};

/// Segments the walkable faces (known, not lethal, normal pointing up) into levels and attaches
/// the other faces.
///
/// Algorithm: repeatedly seed a new level at the lowest unassigned walkable face and grow it
/// over edge-adjacent walkable faces, best-first by height difference to the seed (the seed's
/// floor fills before a ramp leads elsewhere). A face joins only if, on every overlap cell its
/// plan bounding box touches, the level's height interval stays within `level_separation_m`:
/// so no level holds two surfaces stacked above each other; and it climbs no further than
/// `level_separation_m` from its seed (higher faces seed levels of their own). Then, largest first, each level is
/// merged into the first kept level (most shared edges first, then largest) that takes all its
/// faces without an overlap conflict: regions cut apart only by lethal faces (a sidewalk behind
/// a curb, a car roof) share one map, and only stacked surfaces stay apart. A level that cannot
/// merge is kept if its area reaches `min_level_area_m2` and `min_level_fraction` of the largest
/// level's, else dropped. Finally each non-walkable face (lethal, unknown, or walkable in a dropped level)
/// that is not a ceiling goes to the level nearest in height among those with walkable
/// surface within `attach_radius_m` in plan, if within `level_separation_m`.
/// O(F log F). Deterministic.
/// @throw std::invalid_argument if the config does not validate or layers/mesh sizes differ.
Levels segmentLevels(const LayeredMesh& map, const MapPlane& plane, const LevelConfig& config);

/// A level rasterised on a regular plan grid. Cell (col, row) covers
/// x in [origin_x_m + col * r, origin_x_m + (col + 1) * r), y likewise with row; row 0 is the
/// LOWEST y (image writers flip it).
struct LevelGrid {
  double origin_x_m = 0;
  double origin_y_m = 0;
  double resolution_m = 0.1;
  std::size_t width = 0;
  std::size_t height = 0;
  /// Per cell (row-major, row 0 = lowest y): the face chosen for the cell or -1 for none.
  /// Choice: a lethal face touching the cell wins (walls have no plan area, so lethal faces are
  /// rasterised conservatively: cell centre inside, or an edge crossing the cell); else the
  /// walkable face covering the cell centre (the highest if several); else any other face
  /// covering the centre (unknown).
  std::vector<std::int64_t> face;
  /// Per cell: the class of the chosen face (kUnknown where face is -1).
  std::vector<FaceClass> cell_class;

  std::size_t index(std::size_t col, std::size_t row) const { return row * width + col; }
};

/// Rasterises level `level` of `levels` at `resolution_m`, over the plan bounding box of the
/// level's faces padded by one cell. Origin aligned to multiples of the resolution.
/// @throw std::invalid_argument if `level` is out of range or the resolution is not > 0.
LevelGrid rasterizeLevel(const LayeredMesh& map, const MapPlane& plane, const Levels& levels,
                         std::size_t level, double resolution_m);

}  // namespace terramesh::traversability
