#include "visibility_tracer.h"

#include <algorithm>
#include <cassert>

namespace terramesh::mesher::internal {

void VisibilityTracer::noteChange(const CellHandle& cell, std::uint32_t mark) {
  if (cell->info().mark == mark) return;
  cell->info().mark = mark;
  changed_.push_back({cell, cell->info().crossings, cell->info().spreading});
}

void VisibilityTracer::applyChanges() {
  for (const Change& change : changed_) {
    state_.weights.propagateCrossingChange(change.cell, change.crossings_before,
                                           change.spreading_before, state_.candidates);
    // The crossings of the cells on both sides of a surface face count in its observation.
    if (change.cell->info().crossings != change.crossings_before) {
      state_.outside.touchFacesOf(change.cell);
    }
  }
  changed_.clear();
}

bool VisibilityTracer::drivenRay(const Ray& ray) const {
  return state_.registry.point(ray.point).kind == PointKind::kDrivenGround;
}

void VisibilityTracer::withdrawRange(Ray& ray, std::size_t from, std::size_t to, std::uint32_t mark) {
  // In a path that ends at the point the last cell (the cone's apex) does not spread; in a prefix
  // every cell does (the ray goes on beyond it).
  const bool complete = !(ray.flags & kRayPartial);
  const bool driven = drivenRay(ray);
  const std::size_t size = ray.path.size();
  for (std::size_t i = from; i < to; ++i) {
    const CellHandle& cell = ray.path[i];
    noteChange(cell, mark);
    assert(cell->info().crossings > 0);
    --cell->info().crossings;
    if (driven) --cell->info().driven_crossings;
    if (!complete || i + 1 < size) --cell->info().spreading;
  }
}

void VisibilityTracer::untrace(const std::vector<RayId>& batch) {
  const std::uint32_t mark = state_.nextMark();
  RayStore& rays = state_.rays;
  for (RayId id : batch) {
    Ray& ray = rays[id];
    if (!(ray.flags & kRayTraced)) continue;
    withdrawRange(ray, 0, ray.path.size(), mark);
    rays.clearPath(id);
    ray.flags &= static_cast<std::uint8_t>(~(kRayTraced | kRayPartial | kRayGap));
  }
  applyChanges();
}

void VisibilityTracer::truncateAtDoomed(std::vector<Crossing>& doomed, std::vector<RayId>& batch) {
  RayStore& rays = state_.rays;
  std::sort(doomed.begin(), doomed.end(), [](const Crossing& a, const Crossing& b) {
    return a.ray < b.ray || (a.ray == b.ray && a.step < b.step);
  });
  batch.clear();
  const std::uint32_t mark = state_.nextMark();
  for (std::size_t i = 0; i < doomed.size();) {
    // The crossings of one ray: its first and last doomed steps.
    std::size_t j = i;
    while (j + 1 < doomed.size() && doomed[j + 1].ray == doomed[i].ray) ++j;
    const RayId id = doomed[i].ray;
    const auto [from, to] = stretchToWithdraw(rays[id], doomed[i].step, doomed[j].step);
    i = j + 1;
    batch.push_back(id);
    Ray& ray = rays[id];
    if (!(ray.flags & kRayTraced) || from == to) continue;
    const bool tail = to < ray.path.size();
    withdrawRange(ray, from, to, mark);
    // The ray leaves the lists of its withdrawn cells only; its other cells keep it.
    rays.erasePath(id, from, to);
    if (from == 0) {
      ray.flags &= static_cast<std::uint8_t>(~(kRayTraced | kRayPartial | kRayGap));
    } else if (tail) {
      ray.flags |= kRayGap;
      ray.gap = static_cast<std::uint32_t>(from);
    } else {
      ray.flags = static_cast<std::uint8_t>((ray.flags | kRayPartial) & ~kRayGap);
    }
  }
  applyChanges();
}

std::pair<std::size_t, std::size_t> VisibilityTracer::stretchToWithdraw(const Ray& ray, std::size_t first,
                                                                        std::size_t last) const {
  const std::size_t size = ray.path.size();
  // Rays walked from a displaced camera are walked again whole.
  if (ray.walk != kWalkedStraight) return {0, size};
  std::size_t from = first, to = last + 1;
  // A stretch withdrawn earlier in this update joins this one; a prefix has nothing after it.
  if (ray.flags & kRayGap) {
    from = std::min<std::size_t>(from, ray.gap);
    to = std::max<std::size_t>(to, ray.gap);
  }
  if ((ray.flags & kRayPartial) || from == 0) to = size;
  return {from, to};
}

void VisibilityTracer::addVotes(RayId id, std::size_t from, std::uint32_t mark) {
  // `mark` is the batch's: each cell's counts before the batch are recorded once.
  Ray& ray = state_.rays[id];
  const bool driven = drivenRay(ray);
  const std::size_t size = ray.path.size();
  for (std::size_t i = from; i < size; ++i) {
    const CellHandle& cell = ray.path[i];
    noteChange(cell, mark);
    ++cell->info().crossings;
    if (driven) ++cell->info().driven_crossings;
    if (i + 1 < size) ++cell->info().spreading;  // the last cell is the cone's apex
  }
  // The old last cell of a resumed prefix already counted as spreading.
  state_.rays.registerPath(id, from);
}

bool VisibilityTracer::bridgeGap(RayId id, VertexHandle target, std::uint32_t mark, WalkCounters& counters) {
  Ray& ray = state_.rays[id];
  const Point camera_W = toPoint(state_.registry.keyframe(ray.keyframe).centre_W);
  if (!walker_.bridge(camera_W, target, ray.path, ray.gap, between_, counters)) return false;
  // Every cell in between spreads: the ray goes on to its tail.
  const bool driven = drivenRay(ray);
  for (const CellHandle& cell : between_) {
    noteChange(cell, mark);
    ++cell->info().crossings;
    if (driven) ++cell->info().driven_crossings;
    ++cell->info().spreading;
  }
  state_.rays.insertPath(id, ray.gap, between_);
  ray.flags &= static_cast<std::uint8_t>(~kRayGap);
  return true;
}

CameraLocation VisibilityTracer::locateCamera(std::uint32_t keyframe) {
  KeyframeRecord& record = state_.registry.keyframe(keyframe);
  CameraLocation location;
  location.position = toPoint(record.centre_W);
  const CellHandle hint = state_.alive(record.camera_hint) ? record.camera_hint.cell : CellHandle();
  location.cell = state_.tri.locate(location.position, location.type, location.li, location.lj, hint);
  record.camera_hint = state_.stamp(location.cell);
  return location;
}

void VisibilityTracer::trace(const std::vector<RayId>& batch, WalkCounters& counters) {
  RayStore& rays = state_.rays;
  // Walk the rays of one camera together: it is located once.
  order_.assign(batch.begin(), batch.end());
  std::sort(order_.begin(), order_.end(),
            [&rays](RayId a, RayId b) { return rays[a].keyframe < rays[b].keyframe; });
  const std::uint32_t mark = state_.nextMark();
  std::vector<RayId> restart;
  std::uint32_t located = kNone;
  CameraLocation camera;
  for (RayId id : order_) {
    Ray& ray = rays[id];
    ray.flags &= static_cast<std::uint8_t>(~(kRayNeedsTrace | kRayNewSegment));
    const VertexHandle target = state_.registry.point(ray.point).vertex;
    if (ray.flags & kRayGap) {
      if (bridgeGap(id, target, mark, counters)) continue;
      restart.push_back(id);  // degenerate in between: walked again from scratch below
      continue;
    }
    if (ray.flags & kRayPartial) {
      const std::size_t prefix = ray.path.size();
      const Point camera_W = toPoint(state_.registry.keyframe(ray.keyframe).centre_W);
      if (walker_.resume(camera_W, target, ray.path, counters)) {
        ray.flags &= static_cast<std::uint8_t>(~kRayPartial);
        addVotes(id, prefix, mark);
      } else {
        restart.push_back(id);  // degenerate further on: walked again from scratch below
      }
      continue;
    }
    if (ray.flags & kRayTraced) continue;
    if (ray.keyframe != located) {
      camera = locateCamera(ray.keyframe);
      located = ray.keyframe;
    }
    // Walked into a scratch path, then stored at its exact size (one allocation, no slack).
    ray.walk = walker_.walk(camera, target, walked_, counters);
    ray.path.assign(walked_.begin(), walked_.end());
    addVotes(id, 0, mark);
    ray.flags |= kRayTraced;
  }
  applyChanges();
  if (restart.empty()) return;
  untrace(restart);
  trace(restart, counters);
}

void VisibilityTracer::walkOnly(const Ray& ray, std::vector<CellHandle>& path,
                                WalkCounters& counters) {
  const CameraLocation camera = locateCamera(ray.keyframe);
  // A walk without cache writes: use a cache-less walker so checking changes nothing.
  RayWalker plain(state_.tri, false);
  plain.walk(camera, state_.registry.point(ray.point).vertex, path, counters);
}

}  // namespace terramesh::mesher::internal
