#pragma once

#include <optional>
#include <unordered_set>
#include <vector>

#include "manifold_growing.h"
#include "map_state.h"
#include "mesher/mesher.h"
#include "shrinking.h"
#include "step_clock.h"
#include "triangulation_editor.h"
#include "visibility_tracer.h"

namespace terramesh::mesher {

/// The mesher's state and pipeline. Steps live in their own classes (internal::TriangulationEditor,
/// VisibilityTracer, Shrinker, Grower); this class does the bookkeeping of points, keyframes and
/// rays and runs the steps in the paper's order.
class Mesher::Impl {
 public:
  explicit Impl(const MesherConfig& config);

  UpdateStats integrateKeyframe(const Keyframe& keyframe);
  UpdateStats removePoints(const std::vector<PointId>& points);
  UpdateStats removeKeyframe(KeyframeId keyframe);
  UpdateStats removeKeyframes(const std::vector<KeyframeId>& keyframes);
  UpdateStats releaseFarSteiner(const std::vector<Eigen::Vector3d>& keep_W, double reach_m);

  TriangleMesh extractMesh() const;
  std::uint64_t revision() const { return state_.surface_log.revision(); }
  SurfaceDelta changesSince(std::uint64_t revision) const;
  std::vector<SurfaceFace> surfaceFaces() const;
  std::vector<SurfaceFace> facesAround(const std::vector<VertexKey>& vertices) const;
  std::vector<UnconfirmedPoint> unconfirmedPoints() const;
  UnconfirmedCursor unconfirmedCursor() const { return {instance_, state_.registry.waitingRevision()}; }
  UnconfirmedChanges unconfirmedChangesSince(const UnconfirmedCursor& cursor) const;
  MapSize size() const;
  InvariantReport checkInvariants() const;
  std::vector<CellVisibility> cellVisibility() const;
  const MesherConfig& config() const { return state_.config; }

 private:
  friend class internal::CheckpointAccess;

  /// What one update has to do, filled by the bookkeeping and consumed by `run`.
  struct UpdatePlan {
    std::vector<std::uint32_t> insert;  ///< points to insert for the first time (or again)
    std::vector<std::uint32_t> move;    ///< inserted points with a new estimate
    std::vector<std::uint32_t> remove;  ///< inserted points to delete
    std::vector<std::uint32_t> forget;  ///< records to erase once the update is done
    std::vector<std::uint32_t> classified;  ///< every point classified (its waiting state re-read at the end)
    std::vector<internal::RayId> untrace_now;  ///< rays whose segment changes or that go away
    std::vector<internal::RayId> destroy;      ///< rays to free after untracing
    std::vector<internal::RayId> trace;        ///< rays to walk at the end (new segments)
    std::vector<Eigen::Vector3d> cameras;      ///< camera centres involved
    /// Where free boxes went or changed (FreeBoxIndex::coverage): their region is shrunk.
    std::vector<Eigen::Vector3d> box_changes;
    std::vector<FreeBox> new_boxes;                ///< free boxes of a keyframe that had none
    std::uint32_t pose_changed = internal::kNone;  ///< keyframe whose pose changed, if any
  };

  // Bookkeeping.
  /// @throw std::invalid_argument if an observed point is known with another PointKind.
  void validateKinds(const Keyframe& keyframe) const;
  /// Replaces keyframe `k`'s free boxes. Boxes that go or change shrink the region around them (in
  /// `plan.box_changes`); a keyframe's first boxes only add the cells they meet to the grow
  /// candidates (`plan.new_boxes`), as a new ray's cells are.
  void setFreeBoxes(std::uint32_t k, const std::vector<FreeBox>& boxes, UpdatePlan& plan);
  void classifyPoint(std::uint32_t point, UpdatePlan& plan, UpdateStats& stats);
  void reconcileRays(std::uint32_t point, UpdatePlan& plan, UpdateStats& stats);
  void createRays(std::uint32_t point, UpdatePlan& plan, UpdateStats& stats);
  void detachRay(std::uint32_t point, std::size_t slot, UpdatePlan& plan);
  std::size_t viewsInRange(const internal::PointRecord& point, const Eigen::Vector3d& at) const;
  bool rayWanted(std::uint32_t keyframe, const Eigen::Vector3d& at, bool& degenerate) const;

  VertexKey pointKey(std::uint32_t index) const { return VertexKey::point(state_.registry.point(index).id); }
  /// The point gained or lost rays: the observation of its faces changed.
  void touchPoint(std::uint32_t index) { state_.surface_log.touch(pointKey(index)); }

  // Surface queries (surface_queries.cpp).
  /// The surface face on facet `facet` of `front` (a cell of O whose neighbour there is not).
  SurfaceFace makeFace(const internal::CellHandle& front, int facet) const;
  /// SurfaceFace::view_sides of a face on `vertices` with normal `normal` (towards free space,
  /// any non-zero length).
  std::uint8_t viewSides(const std::array<internal::VertexHandle, 3>& vertices, const Eigen::Vector3d& normal) const;
  /// The vertex with this key, or null.
  internal::VertexHandle vertexOf(const VertexKey& key) const;

  // Pipeline.
  UpdateStats run(UpdatePlan& plan, UpdateStats stats);
  void growSteinerGrid(const UpdatePlan& plan, UpdateStats& stats);
  void insertSteinerNode(const Eigen::Vector3d& node, UpdateStats& stats);
  std::optional<std::unordered_set<internal::GridKey, internal::GridKeyHash>> shrink(
      const UpdatePlan& plan, UpdateStats& stats);
  void changeTopology(UpdatePlan& plan, UpdateStats& stats, internal::StepClock& clock);
  /// Traces the rays of `rays` that need it (each once), counting new segments as traced and the
  /// others as retraced; clears `rays`.
  void traceNow(std::vector<internal::RayId>& rays, UpdateStats& stats);
  void traceScheduled(UpdatePlan& plan, UpdateStats& stats);
  void untraceAndDestroyRaysOf(std::uint32_t point, UpdateStats& stats);

  internal::MapState state_;
  /// This mesher's identity in UnconfirmedCursor (drawn once: another mesher's cursor is foreign).
  std::uint64_t instance_ = 0;
  internal::VisibilityTracer tracer_;
  internal::TriangulationEditor editor_;
  internal::Shrinker shrinker_;
  internal::Grower grower_;
  /// Explicit removals refused because the star still touched O; retried every update.
  std::vector<std::uint32_t> pending_removals_;
  /// Rays flagged kRayNeedsTrace by topology changes of the current update.
  std::vector<internal::RayId> retrace_;
};

}  // namespace terramesh::mesher
