#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>

#include "boundary_hash.h"
#include "cgal_types.h"
#include "free_boxes.h"
#include "mark_epochs.h"
#include "mesher/mesher.h"
#include "mesher/mesher_config.h"
#include "outside_set.h"
#include "point_registry.h"
#include "ray_store.h"
#include "steiner_grid.h"
#include "surface_log.h"
#include "visibility_weights.h"

namespace terramesh::mesher::internal {

/// Everything the mesher holds: the triangulation and the side structures kept in step with it.
/// The pipeline steps (editor, tracer, shrinker, grower) operate on one MapState.
struct MapState {
  explicit MapState(const MesherConfig& cfg)
      : config(cfg),
        epochs(tri),
        grid(cfg.steinerStepUnits(), cfg.steiner_origin_offset_m / cfg.metres_per_unit,
             cfg.steiner_global_phase),
        hash(cfg.boundary_hash),
        outside(tri, grid, hash, epochs),
        weights(cfg.weight_crossed, cfg.weight_neighbour, cfg.weight_second_neighbour,
                cfg.free_threshold, cfg.spread_cap),
        boxes(1.0 / cfg.metres_per_unit),
        surface_log(Mesher::kSurfaceHistoryRevisions, cfg.surface_history_max_bytes) {
    outside.attachLog(surface_log, registry);
  }

  MapState(const MapState&) = delete;
  MapState& operator=(const MapState&) = delete;

  /// True if the stamped cell still exists (not destroyed by a topology change since stamped).
  bool alive(const StampedCell& stamped) const {
    return stamped.cell != CellHandle() && tri.tds().cells().is_used(stamped.cell) &&
           stamped.cell->info().uid == stamped.uid;
  }
  StampedCell stamp(const CellHandle& cell) const { return {cell, cell->info().uid}; }

  /// A fresh value for CellInfo::mark, distinct from every mark currently stored.
  std::uint32_t nextMark() { return epochs.nextCellMark(); }
  /// A fresh value for VertexInfo::mark, distinct from every mark currently stored.
  std::uint32_t nextVertexMark() { return epochs.nextVertexMark(); }

  /// Whether `cell` is free space: its weight is above the threshold, or, over driven ground, a
  /// ray to a driven-ground sample crosses it or it meets a keyframe's free box (the robot's body
  /// passed there). Under driven ground (MesherConfig::driven_ground_up_W) only rays from beneath
  /// that ground count (freedFromBelow): a ray from above would have passed through ground the
  /// robot drove on, while one from a camera on the level beneath a parking deck did not. A
  /// function of the cell's rays, their keyframes and points, the boxes and the cell's vertices
  /// only.
  bool isFree(const CellHandle& cell) const {
    std::array<Eigen::Vector3d, 4> over;
    int count_over = 0;
    const int side = drivenGroundSide(cell, over, count_over);
    if (side < 0) return weights.isFree(cell) && freedFromBelow(cell, over, count_over);
    return weights.isFree(cell) ||
           (side > 0 && (cell->info().driven_crossings > 0 || inFreeBox(cell)));
  }

  /// Whether `cell` (finite) meets a keyframe's free box (Keyframe::free_boxes): the robot's body
  /// was there.
  bool inFreeBox(const CellHandle& cell) const {
    if (boxes.empty() || tri.is_infinite(cell)) return false;
    return boxes.meets(corners(cell));
  }

  /// The four corners of a finite cell.
  static std::array<Eigen::Vector3d, 4> corners(const CellHandle& cell) {
    std::array<Eigen::Vector3d, 4> out;
    for (int i = 0; i < 4; ++i) out[static_cast<std::size_t>(i)] = toEigen(cell->vertex(i)->point());
    return out;
  }

  /// Where `cell` lies relative to the driven ground its corners stand for, judged by its centroid
  /// along MesherConfig::driven_ground_up_W: -1 below one of them, +1 above all of them, 0 with
  /// none (or when up is not given, or the cell is infinite). A driven-ground corner stands for
  /// the ground at itself, an underside corner for the ground driven_underside_depth_m above it.
  /// The driven ground the centroid lies below (the points its corners stand for) goes to
  /// over[0, count_over).
  int drivenGroundSide(const CellHandle& cell, std::array<Eigen::Vector3d, 4>& over, int& count_over) const {
    count_over = 0;
    if (config.driven_ground_up_W.isZero(0) || tri.is_infinite(cell)) return 0;
    // Most cells have no driven corner: find them before computing anything (a hot path).
    int driven[4];
    bool underside[4];
    int count = 0;
    for (int i = 0; i < 4; ++i) {
      const std::uint32_t point = cell->vertex(i)->info().point;
      if (point == kNone || !isDrivenKind(registry.point(point).kind)) continue;
      underside[count] = registry.point(point).kind == PointKind::kDrivenUnderside;
      driven[count++] = i;
    }
    if (count == 0) return 0;
    const Eigen::Vector3d& up = config.driven_ground_up_W;
    const auto position = [&](int i) {
      const Point& p = cell->vertex(i)->point();
      return Eigen::Vector3d(p.x(), p.y(), p.z());
    };
    const Eigen::Vector3d centroid = 0.25 * (position(0) + position(1) + position(2) + position(3));
    int side = 1;
    for (int k = 0; k < count; ++k) {
      Eigen::Vector3d corner = position(driven[k]);
      if (underside[k]) corner += config.drivenUndersideDepthUnits() * up;
      if ((centroid - corner).dot(up) >= 0) continue;
      side = -1;
      over[static_cast<std::size_t>(count_over++)] = corner;
    }
    return side;
  }

  /// Whether rays from beneath all the driven ground the centroid of `cell` lies under (`over`,
  /// from drivenGroundSide) weigh enough, on their own, to make a crossed cell free (crossings x
  /// weight_crossed over the threshold). A ray is from beneath when its camera lies below that ground and its point lies
  /// more than the underside depth below it: a camera lower on a ramp looking at the deck ahead
  /// sees points on the deck, through the thin cells under its samples.
  bool freedFromBelow(const CellHandle& cell, const std::array<Eigen::Vector3d, 4>& over, int count_over) const {
    const Eigen::Vector3d& up = config.driven_ground_up_W;
    const double depth = config.drivenUndersideDepthUnits();
    double weight = 0;
    for (const Crossing& crossing : rays.crossing(cell)) {
      const Ray& ray = rays[crossing.ray];
      const Eigen::Vector3d& camera = registry.keyframe(ray.keyframe).centre_W;
      const Eigen::Vector3d& point = registry.point(ray.point).inserted_W;
      bool below = true;
      for (int k = 0; k < count_over && below; ++k) {
        const Eigen::Vector3d& ground = over[static_cast<std::size_t>(k)];
        below = (camera - ground).dot(up) < 0 && (point - ground).dot(up) < -depth;
      }
      if (!below) continue;
      weight += config.weight_crossed;
      if (weight > config.free_threshold) return true;
    }
    return false;
  }

  /// Gives a new unique stamp to a freshly created cell.
  void stampNewCell(const CellHandle& cell) { cell->info().uid = next_uid++; }

  MesherConfig config;
  Delaunay tri;
  MarkEpochs epochs;
  SteinerGrid grid;
  BoundaryHash hash;
  OutsideSet outside;
  RayStore rays;
  PointRegistry registry;
  WeightField weights;
  GrowCandidates candidates;
  /// The keyframes' free boxes (Keyframe::free_boxes), by registry index of their keyframe.
  FreeBoxIndex boxes;
  std::size_t steiner_vertices = 0;
  /// Steiner vertices by lattice node (VertexKey::value of their key).
  std::unordered_map<std::uint64_t, VertexHandle> steiner_nodes;
  /// What changed on the surface, per revision.
  SurfaceLog surface_log;
  std::uint32_t next_uid = 1;
};

/// Adds to the grow candidates every cell not in O that meets one of `boxes` (found by walking
/// from the cell holding each box's centre through the cells that meet it): new free space the
/// growing step takes up where O reaches it, as it takes up cells a new ray frees.
void addFreeBoxCandidates(MapState& state, const std::vector<FreeBox>& boxes);

}  // namespace terramesh::mesher::internal
