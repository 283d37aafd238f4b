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
  }
  changed_.clear();
}

void VisibilityTracer::untrace(const std::vector<RayId>& batch) {
  const std::uint32_t mark = state_.nextMark();
  RayStore& rays = state_.rays;
  for (RayId id : batch) {
    Ray& ray = rays[id];
    if (!(ray.flags & kRayTraced) || (ray.flags & kRayMarked)) continue;
    ray.flags |= kRayMarked;
    for (std::size_t i = 0; i < ray.path.size(); ++i) {
      const CellHandle& cell = ray.path[i];
      noteChange(cell, mark);
      assert(cell->info().crossings > 0);
      --cell->info().crossings;
      if (i + 1 < ray.path.size()) --cell->info().spreading;
    }
  }
  for (const Change& change : changed_) rays.removeMarkedCrossings(change.cell);
  for (RayId id : batch) {
    Ray& ray = rays[id];
    if (!(ray.flags & kRayMarked)) continue;
    ray.flags &= static_cast<std::uint8_t>(~(kRayMarked | kRayTraced));
    rays.clearPath(id);
  }
  applyChanges();
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
  std::uint32_t located = kNone;
  CameraLocation camera;
  for (RayId id : order_) {
    Ray& ray = rays[id];
    ray.flags &= static_cast<std::uint8_t>(~(kRayNeedsTrace | kRayNewSegment));
    if (ray.flags & kRayTraced) continue;
    if (ray.keyframe != located) {
      camera = locateCamera(ray.keyframe);
      located = ray.keyframe;
    }
    const VertexHandle target = state_.registry.point(ray.point).vertex;
    walker_.walk(camera, target, ray.path, counters);
    rays.notePathFilled(id);
    for (std::size_t i = 0; i < ray.path.size(); ++i) {
      const CellHandle& cell = ray.path[i];
      noteChange(cell, mark);
      ++cell->info().crossings;
      if (i + 1 < ray.path.size()) ++cell->info().spreading;  // the last cell is the cone's apex
      rays.addCrossing(cell, id);
    }
    ray.flags |= kRayTraced;
  }
  applyChanges();
}

void VisibilityTracer::walkOnly(const Ray& ray, std::vector<CellHandle>& path,
                                WalkCounters& counters) {
  const CameraLocation camera = locateCamera(ray.keyframe);
  // A walk without cache writes: use a cache-less walker so checking changes nothing.
  RayWalker plain(state_.tri, false);
  plain.walk(camera, state_.registry.point(ray.point).vertex, path, counters);
}

}  // namespace terramesh::mesher::internal
