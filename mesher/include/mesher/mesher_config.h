#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace terramesh::mesher {

/// Which algorithm the pipeline runs. All three share the same code; the baselines switch off the
/// techniques the paper (Piazza, Romanoni, Matteucci, RA-L 2018) adds.
enum class MesherMode {
  kProposed,    ///< the paper's method (default)
  kLitvinov13,  ///< Litvinov & Lhuillier 2013: ray-count weights, fixed grid, camera-sphere enclosing
  kRomanoni15,  ///< Romanoni & Matteucci 2015: as kLitvinov13 with inverse-cone weights
};

/// What happens to an inserted point whose SLAM estimate changes.
enum class PointPolicy {
  kExactMoves,     ///< its vertex is removed and re-inserted at the new estimate (the paper's method)
  kFixedPosition,  ///< it stays where it was first inserted, as the originals ran Litvinov13 and
                   ///< Romanoni15 in the paper's comparison; later estimates are ignored
};

/// "proposed", "litvinov13" or "romanoni15".
const char* toString(MesherMode mode);
/// Parses the names printed by toString; std::nullopt for anything else.
std::optional<MesherMode> parseMesherMode(const std::string& name);
/// "exact-moves" or "fixed".
const char* toString(PointPolicy policy);
/// Parses the names printed by toString; std::nullopt for anything else.
std::optional<PointPolicy> parsePointPolicy(const std::string& name);

/// Axis-aligned box in the world frame, in map units.
struct AxisAlignedBox {
  Eigen::Vector3d min_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_W = Eigen::Vector3d::Zero();
};

/// Configuration of the mesher. Distances are in metres; `metres_per_unit` converts them into the
/// units of the incoming map (1 for a metric map; about 16.6 for the ORB-SLAM KITTI 00 export).
///
/// The mode is the single source of the mode-dependent settings (weights, threshold, spread cap,
/// point policy, technique switches): it can only be set through `forMode` or `setMode`, which
/// set all of them to the mode's values. Assign a setting after that to override it (ablations);
/// the mesher runs exactly the settings held, and `mode()` names where their defaults came from.
/// A default-constructed config is `forMode(MesherMode::kProposed)`.
struct MesherConfig {

  /// Size of one map unit in metres.
  double metres_per_unit = 1.0;
  /// A point enters the triangulation once this many keyframes within range have observed it.
  int min_views = 2;
  /// Observations farther than this from their camera are ignored (no ray, no vote).
  double max_camera_distance_m = 40.0;
  /// Spacing of the Steiner grid.
  double steiner_step_m = 10.0;
  /// Enclosing set: cells with a vertex within this many Steiner cells of a changed point.
  int enclosing_radius_cells = 2;
  /// When an update inserts, moves or removes points, also enclose the Steiner cells within this
  /// many cells of its cameras (0: off, the paper's enclosing set). Rays from the camera change
  /// weights along their whole length; re-growing near the camera too lets those cells be carved
  /// in weight order. Costs time; see docs/accuracy.md for what it buys.
  int camera_enclosing_radius_cells = 0;
  /// The grid is kept at least this many cells beyond every point and camera.
  int steiner_margin_cells = 3;
  /// Experiment option (leave at zero): shifts the Steiner lattice by this much, per world axis,
  /// from where the mesher places it (from the first update's data, or the fixed grid's box). For
  /// measuring how the lattice's placement changes the surface (docs/accuracy.md).
  Eigen::Vector3d steiner_origin_offset_m = Eigen::Vector3d::Zero();
  /// Places the Steiner lattice on a phase fixed in the map frame (nodes at multiples of the step
  /// plus the lattice's own fractional offsets and steiner_origin_offset_m) rather than on one set
  /// by the first update's data. Runs given different parts of one stream (the tiles of a plan,
  /// `terramesh mesh --tile`) then share their lattice where they overlap, and mesh it alike.
  /// Off by default: a single run places its lattice as it always has.
  bool steiner_global_phase = false;
  /// Lattice nodes closer than this many grid steps to an inserted point are left out of the
  /// triangulation (restored when no point is that close any more), so that the cells around the
  /// data are the points' own and do not depend on where the lattice lies. In [0, 0.5); 0 keeps
  /// every node (the baselines, as their authors ran them). See docs/algorithms.md.
  double steiner_clearance_steps = 0.0;

  /// Inverse-cone weights: added to each crossed cell, to its face neighbours and to their
  /// neighbours, per crossing. Stored internally in fixed point with 1/16 resolution.
  double weight_crossed = 10.0;
  double weight_neighbour = 2.0;
  double weight_second_neighbour = 1.0;
  /// How many crossings of a neighbour count towards a cell's weight (0: all of them, as in the
  /// authors' code and in romanoni15 mode). Spreading every crossing lets big cells at a surface,
  /// crossed by hundreds of rays, carve the cells behind it; a cap (this project's, 1 in proposed
  /// mode) bounds what a neighbour can contribute.
  int spread_cap = 1;
  /// A cell is free space when its weight is strictly above this.
  double free_threshold = 20.0;
  /// A point whose new estimate moved by no more than this keeps its vertex.
  double move_threshold_m = 0.0;
  /// Up, for driven-ground samples (PointKind::kDrivenGround), as a unit vector in W; zero: not
  /// given. When given, a cell incident to a driven-ground vertex whose centroid lies below that
  /// vertex along up is free space only by rays from cameras below the vertex: the robot stood on
  /// the ground there, so no ray from above passed through it (a camera on the level beneath a
  /// parking deck did not look through it).
  Eigen::Vector3d driven_ground_up_W = Eigen::Vector3d::Zero();
  /// How far under its driven-ground sample an underside vertex (PointKind::kDrivenUnderside)
  /// lies, metres: for the rule above, an underside vertex stands for driven ground this far above
  /// it. In [0, 10].
  double driven_underside_depth_m = 0.0;
  /// Whether inserted points follow their SLAM estimates (proposed) or stay put (baselines).
  PointPolicy point_policy = PointPolicy::kExactMoves;

  /// Technique switches. The mode sets them; they can be changed for ablation studies.
  bool incremental_steiner_grid = true;  ///< grow the grid with the map (else fixed_grid_bounds_W)
  bool local_enclosing_set = true;       ///< enclosing set from grid cells around new points
  bool boundary_hash = true;             ///< boundary vertices hashed by Steiner cell
  bool next_cell_cache = true;           ///< next-tetrahedron caching in the ray walk
  bool ray_scheduler = true;             ///< batch and de-duplicate trace/untrace/retrace
  /// Ours, not the paper's: before the per-vertex pass, for each cell growing refused, try adding
  /// all free cells around one of its edges at once (docs/algorithms.md, docs/accuracy.md).
  bool edge_growing_pass = true;
  /// Ours: growing adds the free cells that a ray to a driven-ground sample crosses (the robot's
  /// body passed there) before all others, by weight among themselves, so that where the manifold
  /// test must keep one of two free regions out it keeps out the one only sensor rays support; such
  /// a cell still refused is tried with the free cells joined to it (docs/algorithms.md,
  /// "Growing"). Changes nothing without driven-ground samples.
  bool driven_cells_first = true;
  /// The edge pass only tries refused cells at least this heavy (weight units): cells that many
  /// rays cross, which matter most and are few (200: about 20 crossings at the default weights).
  double edge_pass_min_weight = 200.0;
  /// Handle control (proposed mode; 0: off). A set of cells added at once by the edge, per-vertex or
  /// ball pass that would raise the genus of the surface (a tunnel through matter) is added only if
  /// some cell of it is crossed by at least this many rays; single cells never add a handle. Keeps
  /// tunnels carved by few rays through thin matter closed (docs/algorithms.md). In [0, 1000000].
  /// 30 (proposed default) removes a third to three quarters of the handles on the synthetic scenes
  /// for <= 1.3% of depth error and coverage (docs/accuracy.md); 0 in the baseline modes.
  int handle_min_rays = 30;
  /// Bytes of surface history kept for Mesher::changesSince, besides the revision bound
  /// (Mesher::kSurfaceHistoryRevisions): the oldest revisions are forgotten first, but the newest
  /// one is always kept. A caller asking for a forgotten revision gets `complete == false` and
  /// resyncs from Mesher::surfaceFaces(). At least 64 KiB.
  std::size_t surface_history_max_bytes = std::size_t{32} << 20;
  /// Region covered by the fixed Steiner grid when incremental_steiner_grid is false.
  std::optional<AxisAlignedBox> fixed_grid_bounds_W;

  /// A config with the defaults of `mode`: weights, threshold, spread cap, point policy and
  /// technique switches (the other fields keep their defaults).
  static MesherConfig forMode(MesherMode mode);

  /// The mode whose settings this config started from.
  MesherMode mode() const { return mode_; }
  /// Sets the mode and every mode-dependent setting to that mode's values (overriding earlier
  /// assignments to them); fields that do not depend on the mode are kept.
  void setMode(MesherMode mode);

  /// Every problem with the configuration, one sentence each; empty when valid.
  std::vector<std::string> problems() const;
  /// @throw std::invalid_argument listing every problem, if any.
  void validate() const;

  /// Distances converted to map units.
  double maxCameraDistanceUnits() const { return max_camera_distance_m / metres_per_unit; }
  double steinerStepUnits() const { return steiner_step_m / metres_per_unit; }
  double moveThresholdUnits() const { return move_threshold_m / metres_per_unit; }
  double drivenUndersideDepthUnits() const { return driven_underside_depth_m / metres_per_unit; }

 private:
  MesherMode mode_ = MesherMode::kProposed;
};

}  // namespace terramesh::mesher
