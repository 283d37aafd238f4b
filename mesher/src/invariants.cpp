#include <sstream>
#include <unordered_map>

#include "mesher_impl.h"
#include "ray_walk.h"

namespace terramesh::mesher {

using internal::CellHandle;
using internal::kRayMarked;
using internal::kRayNeedsTrace;
using internal::kRayTraced;
using internal::VertexHandle;

std::string InvariantReport::summary(std::size_t max_lines) const {
  if (violations.empty()) return "ok";
  std::ostringstream out;
  out << violations.size() << " violation(s)";
  for (std::size_t i = 0; i < violations.size() && i < max_lines; ++i) out << "; " << violations[i];
  return out.str();
}

InvariantReport Mesher::Impl::checkInvariants() const {
  InvariantReport report;
  auto fail = [&report](const std::string& message) {
    if (report.violations.size() < 1000) report.violations.push_back(message);
  };
  const internal::Delaunay& tri = state_.tri;
  if (tri.number_of_vertices() == 0) return report;
  if (!tri.is_valid()) fail("the triangulation is not a valid Delaunay triangulation");
  if (tri.dimension() != 3) fail("the triangulation is not three-dimensional");

  // Crossing counts and paths recomputed from scratch over every stored ray.
  std::unordered_map<const internal::Delaunay::Cell*, std::uint32_t> crossings;
  std::unordered_map<const internal::Delaunay::Cell*, std::uint32_t> driven_crossings;
  std::unordered_map<const internal::Delaunay::Cell*, std::uint32_t> spreading;
  std::unordered_map<const internal::Delaunay::Cell*, std::vector<internal::RayId>> lists;
  internal::RayWalker walker(tri, false);
  internal::WalkCounters counters;
  std::vector<CellHandle> path;
  std::size_t alive_rays = 0;
  for (internal::RayId id = 0; id < state_.rays.slotCount(); ++id) {
    const internal::Ray& ray = state_.rays[id];
    if (!ray.alive()) continue;
    ++alive_rays;
    const std::string name = "ray " + std::to_string(id);
    if (!(ray.flags & kRayTraced) || (ray.flags & (kRayNeedsTrace | kRayMarked))) {
      fail(name + ": not traced at rest (flags " + std::to_string(ray.flags) + ")");
      continue;
    }
    const internal::PointRecord& point = state_.registry.point(ray.point);
    const internal::KeyframeRecord& keyframe = state_.registry.keyframe(ray.keyframe);
    if (!point.alive || !point.inserted() || !keyframe.alive) {
      fail(name + ": its point or keyframe is gone");
      continue;
    }
    internal::CameraLocation camera;
    camera.position = internal::toPoint(keyframe.centre_W);
    camera.cell = tri.locate(camera.position, camera.type, camera.li, camera.lj);
    walker.walk(camera, point.vertex, path, counters);
    if (path != ray.path) fail(name + ": stored path differs from a fresh walk");
    for (std::size_t i = 0; i < ray.path.size(); ++i) {
      const CellHandle& cell = ray.path[i];
      ++crossings[&*cell];
      if (point.kind == PointKind::kDrivenGround) ++driven_crossings[&*cell];
      if (i + 1 < ray.path.size()) ++spreading[&*cell];
      lists[&*cell].push_back(id);
    }
  }
  if (alive_rays != state_.rays.size()) fail("ray count does not match the live rays");
  std::size_t path_entries = 0;
  for (internal::RayId id = 0; id < state_.rays.slotCount(); ++id) path_entries += state_.rays[id].path.size();
  if (path_entries != state_.rays.totalCrossings()) fail("the crossing total does not match the paths");

  std::size_t outside = 0;
  for (auto cell = tri.all_cells_begin(); cell != tri.all_cells_end(); ++cell) {
    const internal::CellInfo& info = cell->info();
    const auto it = crossings.find(&*cell);
    const std::uint32_t expected = it == crossings.end() ? 0 : it->second;
    if (info.crossings != expected) {
      fail("cell " + std::to_string(info.uid) + ": crossings " + std::to_string(info.crossings) +
           " but " + std::to_string(expected) + " stored rays cross it");
    }
    const auto driven = driven_crossings.find(&*cell);
    if (info.driven_crossings != (driven == driven_crossings.end() ? 0 : driven->second)) {
      fail("cell " + std::to_string(info.uid) + ": driven crossings " + std::to_string(info.driven_crossings) +
           " do not match the stored rays to driven-ground samples");
    }
    const auto spread = spreading.find(&*cell);
    const std::uint32_t expected_spread = spread == spreading.end() ? 0 : spread->second;
    if (info.spreading != expected_spread) {
      fail("cell " + std::to_string(info.uid) + ": spreading crossings " +
           std::to_string(info.spreading) + " but recomputation gives " +
           std::to_string(expected_spread));
    }
    std::vector<internal::RayId> stored;
    const auto& entries = state_.rays.crossing(cell);
    for (std::size_t position = 0; position < entries.size(); ++position) {
      const internal::Crossing& entry = entries[position];
      stored.push_back(entry.ray);
      const internal::Ray& ray = state_.rays[entry.ray];
      if (entry.step >= ray.path.size() || ray.path[entry.step] != CellHandle(cell) ||
          ray.slots[entry.step] != position) {
        fail("cell " + std::to_string(info.uid) + ": ray list entry does not match its path step");
      }
    }
    std::vector<internal::RayId> fresh;
    if (const auto list = lists.find(&*cell); list != lists.end()) fresh = list->second;
    std::sort(stored.begin(), stored.end());
    std::sort(fresh.begin(), fresh.end());
    if (stored != fresh) fail("cell " + std::to_string(info.uid) + ": ray list is inconsistent");
    const std::int32_t weight = state_.weights.computeWeight(cell);
    if (info.weight != weight) {
      fail("cell " + std::to_string(info.uid) + ": weight " + std::to_string(info.weight) +
           " but recomputation gives " + std::to_string(weight));
    }
    if (info.flags & (internal::kCellQueued | internal::kCellPending | internal::kCellEnclosed |
                      internal::kCellCandidate)) {
      fail("cell " + std::to_string(info.uid) + ": scratch flags left set");
    }
    if (info.outside()) {
      ++outside;
      if (tri.is_infinite(cell)) fail("an infinite cell is in O");
    }
  }
  if (outside != state_.outside.size()) fail("the size of O does not match the cell flags");

  // Vertices: O counters, hash membership, regularity, point records.
  auto& outside_set = const_cast<internal::OutsideSet&>(state_.outside);
  std::size_t hashed = 0;
  std::vector<CellHandle> incident;
  for (auto it = tri.finite_vertices_begin(); it != tri.finite_vertices_end(); ++it) {
    const VertexHandle v = it;
    incident.clear();
    tri.incident_cells(v, std::back_inserter(incident));
    std::size_t count = 0;
    for (const CellHandle& cell : incident) count += cell->info().outside();
    const internal::VertexInfo& info = v->info();
    const std::string name = "vertex at (" + std::to_string(v->point().x()) + ", " +
                             std::to_string(v->point().y()) + ", " + std::to_string(v->point().z()) + ")";
    if (info.outside_cells != count) fail(name + ": outside-cell counter is wrong");
    if (info.degree != incident.size()) fail(name + ": degree counter is wrong");
    if ((info.hash_slot != internal::kNone) != (count > 0)) fail(name + ": boundary hash membership is wrong");
    if (info.hash_slot != internal::kNone) {
      ++hashed;
      const auto* bucket = state_.hash.bucket(outside_set.keyOf(v));
      if (bucket == nullptr || info.hash_slot >= bucket->size() || (*bucket)[info.hash_slot] != v) {
        fail(name + ": not found in its boundary-hash bucket");
      }
    }
    if (count > 0 && !outside_set.isRegular(v)) fail(name + ": not regular on the boundary of O");
    if (!info.steiner) {
      if (info.point == internal::kNone) {
        fail(name + ": neither Steiner nor a point");
        continue;
      }
      const internal::PointRecord& point = state_.registry.point(info.point);
      if (!point.alive || point.vertex != v || internal::toPoint(point.inserted_W) != v->point()) {
        fail(name + ": point record does not match");
      }
    }
  }
  if (hashed != state_.hash.size()) fail("boundary hash holds vertices that are not on dO");

  std::size_t links = 0;
  for (std::uint32_t index = 0; index < state_.registry.keyframeSlots(); ++index) {
    links += state_.registry.keyframe(index).points.size();
  }
  if (links != state_.registry.observationLinks()) fail("the observation link count is wrong");
  for (std::uint32_t k : state_.boxes.keyframes()) {
    if (k >= state_.registry.keyframeSlots() || !state_.registry.keyframe(k).alive) {
      fail("free boxes of keyframe slot " + std::to_string(k) + ", which holds no live keyframe");
    }
  }

  // Every inserted point has exactly the rays its keyframes in range call for.
  for (std::uint32_t index = 0; index < state_.registry.pointSlots(); ++index) {
    const internal::PointRecord& point = state_.registry.point(index);
    if (!point.alive) continue;
    if (!point.inserted()) {
      if (!point.rays.empty()) fail("point " + std::to_string(point.id.value) + ": rays without a vertex");
      continue;
    }
    std::size_t wanted = 0;
    bool degenerate = false;
    if (tracesRays(point.kind)) {
      for (std::uint32_t keyframe : point.keyframes) wanted += rayWanted(keyframe, point.inserted_W, degenerate);
    }
    if (wanted != point.rays.size()) {
      fail("point " + std::to_string(point.id.value) + ": has " + std::to_string(point.rays.size()) +
           " rays, expected " + std::to_string(wanted));
    }
  }
  return report;
}

}  // namespace terramesh::mesher
