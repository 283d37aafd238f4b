#include "mesher_impl.h"

#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "keyframe_validation.h"
#include "steiner_clearance.h"

namespace terramesh::mesher {

using internal::CellHandle;
using internal::kNone;
using internal::kRayMarked;
using internal::kRayNeedsTrace;
using internal::kRayNewSegment;
using internal::kRayTraced;
using internal::RayId;
using internal::Step;
using internal::StepClock;
using internal::VertexHandle;

namespace {

/// Reorders `items` along a space-filling curve of their positions (locality for CGAL's locate).
template <class Position>
void spatialSort(std::vector<std::uint32_t>& items, Position position) {
  if (items.size() < 2) return;
  std::vector<internal::Point> points;
  points.reserve(items.size());
  for (std::uint32_t item : items) points.push_back(internal::toPoint(position(item)));
  std::vector<std::size_t> order(items.size());
  std::iota(order.begin(), order.end(), 0);
  using Map = CGAL::Pointer_property_map<internal::Point>::type;
  using Traits = CGAL::Spatial_sort_traits_adapter_3<internal::Kernel, Map>;
  CGAL::spatial_sort(order.begin(), order.end(), Traits(CGAL::make_property_map(points)));
  std::vector<std::uint32_t> sorted;
  sorted.reserve(items.size());
  for (std::size_t index : order) sorted.push_back(items[index]);
  items.swap(sorted);
}

void sortUnique(std::vector<std::uint32_t>& items) {
  std::sort(items.begin(), items.end());
  items.erase(std::unique(items.begin(), items.end()), items.end());
}

template <class T>
void eraseValue(std::vector<T>& items, const T& value) {
  const auto it = std::find(items.begin(), items.end(), value);
  if (it != items.end()) {
    *it = items.back();
    items.pop_back();
  }
}

}  // namespace

Mesher::Impl::Impl(const MesherConfig& config)
    : state_(config), tracer_(state_), editor_(state_, tracer_), shrinker_(state_), grower_(state_) {
  std::random_device entropy;
  // Never 0: a default UnconfirmedCursor belongs to no mesher.
  instance_ = ((static_cast<std::uint64_t>(entropy()) << 32) | entropy()) | 1u;
}

// ---- Bookkeeping ---------------------------------------------------------------------------

bool Mesher::Impl::rayWanted(std::uint32_t keyframe, const Eigen::Vector3d& at,
                             bool& degenerate) const {
  const double distance = (state_.registry.keyframe(keyframe).centre_W - at).norm();
  degenerate = distance == 0.0;
  return distance > 0.0 && distance <= state_.config.maxCameraDistanceUnits();
}

std::size_t Mesher::Impl::viewsInRange(const internal::PointRecord& point,
                                       const Eigen::Vector3d& at) const {
  std::size_t count = 0;
  bool degenerate = false;
  for (std::uint32_t keyframe : point.keyframes) count += rayWanted(keyframe, at, degenerate);
  return count;
}

void Mesher::Impl::classifyPoint(std::uint32_t index, UpdatePlan& plan, UpdateStats& stats) {
  internal::PointRecord& point = state_.registry.point(index);
  plan.classified.push_back(index);
  if (!point.inserted()) {
    // A driven-ground sample (or its underside) is measured by the drive itself: one view suffices.
    const std::size_t min_views = isDrivenKind(point.kind)
                                      ? 1
                                      : static_cast<std::size_t>(state_.config.min_views);
    if (point.keyframes.empty()) {
      plan.forget.push_back(index);
    } else if (viewsInRange(point, point.latest_W) >= min_views) {
      plan.insert.push_back(index);
    } else {
      ++stats.points_waiting;
      stats.points_waiting_too_far += point.keyframes.size() >= min_views;
    }
    return;
  }
  if (point.keyframes.empty()) {
    plan.remove.push_back(index);
  } else if (state_.config.point_policy == PointPolicy::kExactMoves &&
             (point.latest_W - point.inserted_W).norm() > state_.config.moveThresholdUnits()) {
    plan.move.push_back(index);  // with kFixedPosition the point keeps its vertex where it is
  } else {
    reconcileRays(index, plan, stats);
  }
}

void Mesher::Impl::detachRay(std::uint32_t index, std::size_t slot, UpdatePlan& plan) {
  internal::PointRecord& point = state_.registry.point(index);
  const RayId id = point.rays[slot];
  if (state_.rays[id].flags & kRayTraced) plan.untrace_now.push_back(id);
  plan.destroy.push_back(id);
  point.rays[slot] = point.rays.back();
  point.rays.pop_back();
}

void Mesher::Impl::reconcileRays(std::uint32_t index, UpdatePlan& plan, UpdateStats& stats) {
  internal::PointRecord& point = state_.registry.point(index);
  bool degenerate = false;
  for (std::size_t slot = 0; slot < point.rays.size();) {
    const RayId id = point.rays[slot];
    internal::Ray& ray = state_.rays[id];
    const bool observed =
        std::find(point.keyframes.begin(), point.keyframes.end(), ray.keyframe) != point.keyframes.end();
    if (!observed || !rayWanted(ray.keyframe, point.inserted_W, degenerate)) {
      detachRay(index, slot, plan);
      touchPoint(index);
      continue;
    }
    if (ray.keyframe == plan.pose_changed) {
      // The camera moved: the segment is new, the old votes go.
      if (ray.flags & kRayTraced) plan.untrace_now.push_back(id);
      if (!(ray.flags & kRayNeedsTrace)) plan.trace.push_back(id);
      ray.flags |= kRayNeedsTrace | kRayNewSegment;
    }
    ++slot;
  }
  if (!tracesRays(point.kind)) return;
  for (std::uint32_t keyframe : point.keyframes) {
    const bool has_ray = std::any_of(point.rays.begin(), point.rays.end(), [&](RayId id) {
      return state_.rays[id].keyframe == keyframe;
    });
    if (has_ray) continue;
    if (!rayWanted(keyframe, point.inserted_W, degenerate)) {
      stats.rays_skipped += degenerate;
      continue;
    }
    const RayId id = state_.rays.create(index, keyframe);
    state_.rays[id].flags = kRayNeedsTrace | kRayNewSegment;
    point.rays.push_back(id);
    plan.trace.push_back(id);
    touchPoint(index);
  }
}

void Mesher::Impl::createRays(std::uint32_t index, UpdatePlan& plan, UpdateStats& stats) {
  reconcileRays(index, plan, stats);  // no rays yet: creates one per keyframe in range
}

void Mesher::Impl::validateKinds(const Keyframe& keyframe) const {
  for (const PointObservation& observation : keyframe.observations) {
    const std::uint32_t index = state_.registry.findPoint(observation.point);
    if (index == kNone || state_.registry.point(index).kind == observation.kind) continue;
    throw std::invalid_argument("keyframe " + std::to_string(keyframe.id.value) + ": point " +
                                std::to_string(observation.point.value) +
                                " is observed with another kind than it was first observed with "
                                "(SLAM point vs driven-ground sample)");
  }
}

UpdateStats Mesher::Impl::integrateKeyframe(const Keyframe& keyframe) {
  internal::validateKeyframe(keyframe);
  internal::validateGridGrowth(keyframe, state_.grid, state_.config);
  validateKinds(keyframe);
  UpdatePlan plan;
  UpdateStats stats;
  internal::PointRegistry& registry = state_.registry;
  bool created = false;
  const std::uint32_t k = registry.findOrCreateKeyframe(keyframe.id, created);
  if (!created && registry.keyframe(k).centre_W != keyframe.position_W_C) plan.pose_changed = k;
  registry.keyframe(k).centre_W = keyframe.position_W_C;
  registry.keyframe(k).rotation_W_C = keyframe.rotation_W_C.normalized();
  plan.cameras.push_back(keyframe.position_W_C);

  const std::vector<std::uint32_t> previous = registry.takeKeyframePoints(k);
  std::vector<std::uint32_t> touched;
  touched.reserve(keyframe.observations.size() + previous.size());
  for (const PointObservation& observation : keyframe.observations) {
    const std::uint32_t index = registry.findOrCreatePoint(observation.point);
    internal::PointRecord& point = registry.point(index);
    point.kind = observation.kind;  // validateKinds: new, or the kind it already has
    point.latest_W = observation.position_W;
    ++stats.observations;
    stats.observations_too_far += (keyframe.position_W_C - observation.position_W).norm() >
                                  state_.config.maxCameraDistanceUnits();
    if (std::find(point.keyframes.begin(), point.keyframes.end(), k) == point.keyframes.end()) {
      point.keyframes.push_back(k);
    }
    registry.addKeyframePoint(k, index);
    touched.push_back(index);
  }
  if (!previous.empty()) {
    const std::unordered_set<std::uint32_t> current(registry.keyframe(k).points.begin(),
                                                    registry.keyframe(k).points.end());
    for (std::uint32_t index : previous) {
      if (current.count(index)) continue;
      eraseValue(registry.point(index).keyframes, k);
      touched.push_back(index);
    }
  }
  for (std::uint32_t index : touched) classifyPoint(index, plan, stats);
  setFreeBoxes(k, keyframe.free_boxes, plan);
  return run(plan, stats);
}

void Mesher::Impl::setFreeBoxes(std::uint32_t k, const std::vector<FreeBox>& boxes,
                                UpdatePlan& plan) {
  const std::vector<FreeBox> before = state_.boxes.of(k);
  if (before.empty() && boxes.empty()) return;
  state_.boxes.set(k, boxes);
  if (before.empty()) {
    plan.new_boxes.insert(plan.new_boxes.end(), boxes.begin(), boxes.end());
    return;
  }
  for (const std::vector<FreeBox>* list : {&before, &boxes}) {
    for (const FreeBox& box : *list) {
      const std::vector<Eigen::Vector3d> points = state_.boxes.coverage(box);
      plan.box_changes.insert(plan.box_changes.end(), points.begin(), points.end());
    }
  }
}

UpdateStats Mesher::Impl::removePoints(const std::vector<PointId>& ids) {
  UpdatePlan plan;
  UpdateStats stats;
  internal::PointRegistry& registry = state_.registry;
  for (const PointId& id : ids) {
    const std::uint32_t index = registry.findPoint(id);
    if (index == kNone) continue;
    internal::PointRecord& point = registry.point(index);
    if (point.keyframes.empty() && !point.inserted()) continue;  // already scheduled
    for (std::uint32_t keyframe : point.keyframes) registry.removeKeyframePoint(keyframe, index);
    point.keyframes.clear();
    classifyPoint(index, plan, stats);
  }
  return run(plan, stats);
}

UpdateStats Mesher::Impl::removeKeyframe(KeyframeId id) { return removeKeyframes({id}); }

UpdateStats Mesher::Impl::removeKeyframes(const std::vector<KeyframeId>& ids) {
  internal::PointRegistry& registry = state_.registry;
  std::vector<std::uint32_t> gone;
  std::vector<std::uint32_t> touched;
  for (const KeyframeId& id : ids) {
    const std::uint32_t k = registry.findKeyframe(id);
    if (k == kNone || std::find(gone.begin(), gone.end(), k) != gone.end()) continue;
    gone.push_back(k);
    for (std::uint32_t index : registry.takeKeyframePoints(k)) {
      eraseValue(registry.point(index).keyframes, k);
      touched.push_back(index);
    }
  }
  if (gone.empty()) return {};
  // A point seen by two of them is classified once, in the order a single removal would.
  if (gone.size() > 1) sortUnique(touched);
  UpdatePlan plan;
  UpdateStats stats;
  for (std::uint32_t index : touched) classifyPoint(index, plan, stats);
  for (std::uint32_t k : gone) setFreeBoxes(k, {}, plan);
  stats = run(plan, stats);
  for (std::uint32_t k : gone) registry.eraseKeyframe(k);
  return stats;
}

// ---- Pipeline ------------------------------------------------------------------------------

UpdateStats Mesher::Impl::run(UpdatePlan& plan, UpdateStats stats) {
  const auto start = std::chrono::steady_clock::now();
  StepClock clock(stats.time);
  retrace_.clear();
  for (std::uint32_t index : pending_removals_) {
    const internal::PointRecord& point = state_.registry.point(index);
    if (point.alive && point.inserted() && point.keyframes.empty()) plan.remove.push_back(index);
  }
  pending_removals_.clear();
  sortUnique(plan.remove);

  {
    StepClock::Scope scope(clock, Step::kRayTracing);
    for (RayId id : plan.untrace_now) stats.rays_untraced += (state_.rays[id].flags & kRayTraced) != 0;
    tracer_.untrace(plan.untrace_now);
    for (RayId id : plan.destroy) state_.rays.destroy(id);
  }
  {
    StepClock::Scope scope(clock, Step::kSteiner);
    growSteinerGrid(plan, stats);
  }
  std::optional<std::unordered_set<internal::GridKey, internal::GridKeyHash>> region;
  {
    StepClock::Scope scope(clock, Step::kShrink);
    region = shrink(plan, stats);
  }
  {
    StepClock::Scope scope(clock, Step::kInsertion);
    changeTopology(plan, stats, clock);
  }
  {
    StepClock::Scope scope(clock, Step::kRayTracing);
    traceScheduled(plan, stats);
  }
  {
    StepClock::Scope scope(clock, Step::kGrow);
    internal::addFreeBoxCandidates(state_, plan.new_boxes);
    grower_.grow(region ? &*region : nullptr, stats);
  }
  for (std::uint32_t index : plan.forget) {
    const internal::PointRecord& point = state_.registry.point(index);
    if (point.alive && !point.inserted() && point.keyframes.empty() && point.rays.empty()) {
      state_.registry.erasePoint(index);
    }
  }
  for (const auto* list : {&plan.classified, &plan.remove, &plan.forget}) {
    for (std::uint32_t index : *list) state_.registry.refreshWaiting(index);
  }
  state_.registry.commitWaiting();
  state_.surface_log.commit();
  clock.enter(Step::kIdle);
  stats.time.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

void Mesher::Impl::growSteinerGrid(const UpdatePlan& plan, UpdateStats& stats) {
  std::vector<Eigen::Vector3d> positions = plan.cameras;
  for (const auto* list : {&plan.insert, &plan.move}) {
    for (std::uint32_t index : *list) positions.push_back(state_.registry.point(index).latest_W);
  }
  if (positions.empty()) return;
  Eigen::Vector3d lo = positions.front();
  Eigen::Vector3d hi = positions.front();
  for (const Eigen::Vector3d& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const int margin = state_.config.steiner_margin_cells;
  if (state_.tri.number_of_vertices() == 0) {
    std::vector<Eigen::Vector3d> nodes;
    if (state_.config.incremental_steiner_grid) {
      nodes = state_.grid.coverBox(lo, hi, margin);
    } else {
      const AxisAlignedBox& box = *state_.config.fixed_grid_bounds_W;
      nodes = state_.grid.coverBox(box.min_W.cwiseMin(lo), box.max_W.cwiseMax(hi), margin);
    }
    editor_.bootstrap(nodes);
    stats.steiner_points += nodes.size();
    for (auto v = state_.tri.finite_vertices_begin(); v != state_.tri.finite_vertices_end(); ++v) {
      state_.steiner_nodes.emplace(state_.outside.vertexKey(v).value, v);
    }
    return;
  }
  // The fixed grid of the baselines already covers the scene; growing it only happens for data
  // outside the box it was given, which would otherwise lie outside the triangulation.
  std::vector<Eigen::Vector3d> nodes = state_.grid.coverBox(lo, hi, margin);
  if (nodes.empty()) return;
  std::vector<std::uint32_t> order(nodes.size());
  std::iota(order.begin(), order.end(), 0u);
  spatialSort(order, [&nodes](std::uint32_t i) { return nodes[i]; });
  for (std::uint32_t i : order) insertSteinerNode(nodes[i], stats);
}

void Mesher::Impl::insertSteinerNode(const Eigen::Vector3d& node, UpdateStats& stats) {
  using Result = internal::TriangulationEditor::InsertResult;
  VertexHandle vertex;
  Result result = editor_.insert(node, kNone, retrace_, vertex);
  // The margin keeps O far from new grid layers; should O reach one, shrink around it.
  for (int radius = state_.config.enclosing_radius_cells;
       result == Result::kConflictsWithOutside && radius <= 32; radius *= 2) {
    if (state_.config.local_enclosing_set) {
      shrinker_.shrinkInKeys(shrinker_.enclosingKeys({node}, radius), stats);
    } else {
      shrinker_.shrinkInSpheres({node}, radius * state_.grid.step(), stats);
    }
    result = editor_.insert(node, kNone, retrace_, vertex);
  }
  if (result == Result::kInserted) {
    ++stats.steiner_points;
    ++state_.steiner_vertices;
    state_.steiner_nodes.emplace(state_.outside.vertexKey(vertex).value, vertex);
  }
}

std::optional<std::unordered_set<internal::GridKey, internal::GridKeyHash>> Mesher::Impl::shrink(
    const UpdatePlan& plan, UpdateStats& stats) {
  std::vector<Eigen::Vector3d> positions;
  for (std::uint32_t index : plan.insert) positions.push_back(state_.registry.point(index).latest_W);
  for (std::uint32_t index : plan.move) {
    positions.push_back(state_.registry.point(index).inserted_W);
    positions.push_back(state_.registry.point(index).latest_W);
  }
  for (std::uint32_t index : plan.remove) positions.push_back(state_.registry.point(index).inserted_W);
  positions.insert(positions.end(), plan.box_changes.begin(), plan.box_changes.end());
  const bool changes = !positions.empty();

  if (!state_.config.local_enclosing_set) {
    if (changes) {
      const std::vector<Eigen::Vector3d>& centres = plan.cameras.empty() ? positions : plan.cameras;
      const double radius =
          state_.config.maxCameraDistanceUnits() + std::sqrt(3.0) * state_.grid.step();
      shrinker_.shrinkInSpheres(centres, radius, stats);
    }
    return std::nullopt;
  }
  auto keys = shrinker_.enclosingKeys(positions, state_.config.enclosing_radius_cells);
  if (changes && state_.config.camera_enclosing_radius_cells > 0) {
    keys.merge(shrinker_.enclosingKeys(plan.cameras, state_.config.camera_enclosing_radius_cells));
  }
  if (!keys.empty()) shrinker_.shrinkInKeys(keys, stats);
  return keys;
}

void Mesher::Impl::untraceAndDestroyRaysOf(std::uint32_t index, UpdateStats& stats) {
  internal::PointRecord& point = state_.registry.point(index);
  if (!point.rays.empty()) touchPoint(index);
  for (RayId id : point.rays) stats.rays_untraced += (state_.rays[id].flags & kRayTraced) != 0;
  tracer_.untrace(point.rays);
  for (RayId id : point.rays) state_.rays.destroy(id);
  point.rays.clear();
}

void Mesher::Impl::changeTopology(UpdatePlan& plan, UpdateStats& stats, StepClock& clock) {
  using Result = internal::TriangulationEditor::InsertResult;
  const bool scheduled = state_.config.ray_scheduler;
  std::vector<std::uint32_t> reinsert;

  auto removeVertexOf = [&](std::uint32_t index, bool moving) {
    internal::PointRecord& point = state_.registry.point(index);
    if (editor_.starTouchesOutside(point.vertex)) {
      ++stats.deferred_points;
      if (!moving) {
        pending_removals_.push_back(index);
        return;
      }
      // The point stays where it was for now; still honour this update's observation changes.
      UpdatePlan local;
      local.pose_changed = plan.pose_changed;
      reconcileRays(index, local, stats);
      StepClock::Scope scope(clock, Step::kRayTracing);
      for (RayId id : local.untrace_now) stats.rays_untraced += (state_.rays[id].flags & kRayTraced) != 0;
      tracer_.untrace(local.untrace_now);
      for (RayId id : local.destroy) state_.rays.destroy(id);
      plan.trace.insert(plan.trace.end(), local.trace.begin(), local.trace.end());
      return;
    }
    {
      StepClock::Scope scope(clock, Step::kRayTracing);
      untraceAndDestroyRaysOf(index, stats);
    }
    editor_.remove(point.vertex, retrace_);
    point.vertex = VertexHandle();
    state_.surface_log.moved(pointKey(index));
    if (moving) {
      reinsert.push_back(index);
    } else {
      ++stats.removed_points;
      plan.forget.push_back(index);
    }
    if (!scheduled) {
      StepClock::Scope scope(clock, Step::kRayTracing);
      traceNow(retrace_, stats);
    }
  };
  for (std::uint32_t index : plan.remove) removeVertexOf(index, false);
  for (std::uint32_t index : plan.move) removeVertexOf(index, true);

  // Lattice nodes are kept clear of the points (steiner_clearance.h): those near a vacated
  // position may return once every insertion is done.
  internal::SteinerClearance clearance(state_, editor_);
  std::vector<Eigen::Vector3d> vacated;
  if (clearance.enabled()) {
    for (std::uint32_t index : plan.remove) {
      if (!state_.registry.point(index).inserted()) vacated.push_back(state_.registry.point(index).inserted_W);
    }
    for (std::uint32_t index : reinsert) vacated.push_back(state_.registry.point(index).inserted_W);
  }
  const std::unordered_set<std::uint32_t> moving(reinsert.begin(), reinsert.end());
  std::vector<std::uint32_t> inserts = plan.insert;
  inserts.insert(inserts.end(), reinsert.begin(), reinsert.end());
  spatialSort(inserts, [this](std::uint32_t i) { return state_.registry.point(i).latest_W; });
  for (std::uint32_t index : inserts) {
    internal::PointRecord& point = state_.registry.point(index);
    VertexHandle vertex;
    const bool cleared = clearance.clearAround(point.latest_W, retrace_);
    const Result result = editor_.insert(point.latest_W, index, retrace_, vertex);
    if (result != Result::kInserted) {
      ++(result == Result::kDuplicate ? stats.duplicate_points : stats.dropped_points);
      if (cleared) vacated.push_back(point.latest_W);
      continue;
    }
    point.vertex = vertex;
    point.inserted_W = point.latest_W;
    ++(moving.count(index) ? stats.moved_points : stats.new_points);
    const std::size_t first_new = plan.trace.size();
    createRays(index, plan, stats);
    if (!scheduled) {
      StepClock::Scope scope(clock, Step::kRayTracing);
      traceNow(retrace_, stats);
      std::vector<RayId> own(plan.trace.begin() + static_cast<std::ptrdiff_t>(first_new), plan.trace.end());
      plan.trace.resize(first_new);
      traceNow(own, stats);
    }
  }
  if (clearance.restoreAround(vacated, retrace_) > 0 && !scheduled) {
    StepClock::Scope scope(clock, Step::kRayTracing);
    traceNow(retrace_, stats);
  }
}

void Mesher::Impl::traceNow(std::vector<RayId>& ids, UpdateStats& stats) {
  std::vector<RayId> batch;
  batch.reserve(ids.size());
  for (RayId id : ids) {
    internal::Ray& ray = state_.rays[id];
    if (!ray.alive() || !(ray.flags & kRayNeedsTrace) || (ray.flags & kRayMarked)) continue;
    ray.flags |= kRayMarked;
    batch.push_back(id);
  }
  for (RayId id : batch) {
    internal::Ray& ray = state_.rays[id];
    ray.flags &= static_cast<std::uint8_t>(~kRayMarked);
    if (ray.flags & kRayNewSegment) {
      ++stats.rays_traced;
    } else {
      ++stats.rays_retraced;
    }
  }
  ids.clear();
  if (batch.empty()) return;
  internal::WalkCounters counters;
  tracer_.trace(batch, counters);
  stats.walk_steps += counters.steps;
  stats.cache_lookups += counters.cache_lookups;
  stats.cache_hits += counters.cache_hits;
  stats.walk_fallbacks += counters.fallbacks;
  stats.walk_failures += counters.failures;
  stats.walk_step_limit_hits += counters.step_limit_hits;
}

void Mesher::Impl::traceScheduled(UpdatePlan& plan, UpdateStats& stats) {
  // The scheduler's rules: a ray both traced and retraced is traced once; a ray untraced and
  // retraced but gone is only untraced (destroyed rays are skipped); untracing came first.
  std::vector<RayId> all;
  all.reserve(plan.trace.size() + retrace_.size());
  all.insert(all.end(), plan.trace.begin(), plan.trace.end());
  all.insert(all.end(), retrace_.begin(), retrace_.end());
  plan.trace.clear();
  retrace_.clear();
  traceNow(all, stats);
}

}  // namespace terramesh::mesher
