// Mesher::Impl's surface queries: revisions, deltas and the faces with their observation counts.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

#include "mesher_impl.h"

namespace terramesh::mesher {

using internal::CellHandle;
using internal::Delaunay;
using internal::VertexHandle;

namespace {

void sortByKey(std::vector<SurfaceFace>& faces) {
  std::sort(faces.begin(), faces.end(),
            [](const SurfaceFace& a, const SurfaceFace& b) { return a.key < b.key; });
}

}  // namespace

SurfaceFace Mesher::Impl::makeFace(const CellHandle& front, int facet) const {
  assert(front->info().outside() && !front->neighbor(facet)->info().outside());
  std::array<VertexHandle, 3> vertices;
  std::array<VertexKey, 3> keys;
  for (int k = 0; k < 3; ++k) {
    const auto slot = static_cast<std::size_t>(k);
    vertices[slot] = front->vertex(Delaunay::vertex_triple_index(facet, k));
    keys[slot] = state_.outside.vertexKey(vertices[slot]);
  }
  // Start at the smallest key, keeping the winding: equal faces give equal records.
  const auto first = static_cast<std::size_t>(std::min_element(keys.begin(), keys.end()) - keys.begin());
  SurfaceFace face;
  face.front_crossings = front->info().crossings;
  face.rays = face.front_crossings;
  for (std::size_t k = 0; k < 3; ++k) {
    const VertexHandle& v = vertices[(first + k) % 3];
    face.vertices[k] = keys[(first + k) % 3];
    face.positions_W[k] = internal::toEigen(v->point());
    face.touches_steiner = face.touches_steiner || v->info().steiner;
    if (v->info().point != internal::kNone) {
      const internal::PointRecord& point = state_.registry.point(v->info().point);
      face.rays += static_cast<std::uint32_t>(point.rays.size());
      face.driven_vertices += point.kind == PointKind::kDrivenGround ? 1 : 0;
      face.underside_vertices += point.kind == PointKind::kDrivenUnderside ? 1 : 0;
    }
  }
  face.key = FaceKey::of(keys[0], keys[1], keys[2]);
  const Eigen::Vector3d& a = face.positions_W[0];
  const Eigen::Vector3d normal = (face.positions_W[1] - a).cross(face.positions_W[2] - a);
  if (normal.norm() > 0) face.view_sides = viewSides(vertices, normal);
  const CellHandle back = front->neighbor(facet);
  if (!state_.tri.is_infinite(back) && back->info().crossings > 0 && normal.norm() > 0) {
    face.back_crossings = back->info().crossings;
    const Eigen::Vector3d apex = internal::toEigen(back->vertex(back->index(front))->point());
    face.back_depth = std::abs(normal.normalized().dot(apex - a));
  }
  return face;
}

std::uint8_t Mesher::Impl::viewSides(const std::array<VertexHandle, 3>& vertices, const Eigen::Vector3d& normal) const {
  // A view within this angle of the plane (sine) is grazing: the points' noise may tilt the face by
  // that much, so it shows neither side.
  const double grazing = std::sin(view_side::kGrazingDeg * M_PI / 180.0);
  const Eigen::Vector3d n = normal.normalized();
  std::uint8_t sides = 0;
  for (const VertexHandle& v : vertices) {
    if (v->info().point == internal::kNone) continue;
    const Eigen::Vector3d at = internal::toEigen(v->point());
    // Stored rays, not every keyframe: a face is reported again when its points' rays change.
    for (internal::RayId ray : state_.registry.point(v->info().point).rays) {
      const Eigen::Vector3d to_camera = state_.registry.keyframe(state_.rays[ray].keyframe).centre_W - at;
      const double side = n.dot(to_camera);
      const double length = to_camera.norm();
      if (side > grazing * length) sides |= view_side::kFront;
      if (side < -grazing * length) sides |= view_side::kBehind;
    }
  }
  return sides;
}

VertexHandle Mesher::Impl::vertexOf(const VertexKey& key) const {
  if (key.steiner) {
    const auto it = state_.steiner_nodes.find(key.value);
    return it == state_.steiner_nodes.end() ? VertexHandle() : it->second;
  }
  const std::uint32_t index = state_.registry.findPoint(PointId{key.value});
  return index == internal::kNone ? VertexHandle() : state_.registry.point(index).vertex;
}

SurfaceDelta Mesher::Impl::changesSince(std::uint64_t revision) const {
  const internal::SurfaceLog& log = state_.surface_log;
  if (revision > log.revision()) {
    throw std::invalid_argument("changesSince: revision " + std::to_string(revision) +
                                " is newer than the current revision " +
                                std::to_string(log.revision()));
  }
  SurfaceDelta delta;
  delta.from_revision = revision;
  delta.to_revision = log.revision();
  if (revision < log.oldestRevision()) {
    delta.complete = false;
    return delta;
  }
  internal::SurfaceLog::Changes changes = log.since(revision);
  delta.removed = std::move(changes.removed);
  delta.touched_vertices = std::move(changes.touched);
  delta.added.reserve(changes.added.size());
  for (const internal::WoundFace& wound : changes.added) {
    const VertexHandle a = vertexOf(wound[0]);
    const VertexHandle b = vertexOf(wound[1]);
    const VertexHandle c = vertexOf(wound[2]);
    CellHandle cell;
    int i = 0;
    int j = 0;
    int k = 0;
    const bool found = a != VertexHandle() && b != VertexHandle() && c != VertexHandle() &&
                       state_.tri.is_facet(a, b, c, cell, i, j, k);
    assert(found);  // an added face exists now
    if (!found) continue;
    int facet = 6 - i - j - k;
    if (!cell->info().outside()) {
      const CellHandle other = cell->neighbor(facet);
      facet = other->index(cell);
      cell = other;
    }
    delta.added.push_back(makeFace(cell, facet));
    assert(delta.added.back().vertices == internal::canonicalRotation(wound));
  }
  sortByKey(delta.added);
  return delta;
}

std::vector<SurfaceFace> Mesher::Impl::surfaceFaces() const {
  std::vector<SurfaceFace> faces;
  for (auto cell = state_.tri.finite_cells_begin(); cell != state_.tri.finite_cells_end(); ++cell) {
    if (!cell->info().outside()) continue;
    for (int i = 0; i < 4; ++i) {
      if (!cell->neighbor(i)->info().outside()) faces.push_back(makeFace(cell, i));
    }
  }
  sortByKey(faces);
  return faces;
}

std::vector<SurfaceFace> Mesher::Impl::facesAround(const std::vector<VertexKey>& vertices) const {
  // The surface facets around the vertices, each once (a face around several of them is found
  // from each): keyed first, so that every face is built once, in key order.
  struct Facet {
    FaceKey key;
    CellHandle front;
    int index = 0;
  };
  std::vector<Facet> facets;
  std::vector<CellHandle> star;
  for (const VertexKey& key : vertices) {
    const VertexHandle v = vertexOf(key);
    if (v == VertexHandle() || v->info().outside_cells == 0) continue;
    star.clear();
    state_.tri.incident_cells(v, std::back_inserter(star));
    for (const CellHandle& cell : star) {
      if (!cell->info().outside()) continue;
      const int own = cell->index(v);
      for (int i = 0; i < 4; ++i) {
        if (i == own || cell->neighbor(i)->info().outside()) continue;
        std::array<VertexKey, 3> keys;
        for (int k = 0; k < 3; ++k) {
          keys[static_cast<std::size_t>(k)] =
              state_.outside.vertexKey(cell->vertex(Delaunay::vertex_triple_index(i, k)));
        }
        facets.push_back({FaceKey::of(keys[0], keys[1], keys[2]), cell, i});
      }
    }
  }
  // A face's front cell is the one outside cell on its facet: equal keys are the same facet.
  std::sort(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) { return a.key < b.key; });
  facets.erase(std::unique(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) { return a.key == b.key; }),
               facets.end());
  std::vector<SurfaceFace> faces;
  faces.reserve(facets.size());
  for (const Facet& facet : facets) faces.push_back(makeFace(facet.front, facet.index));
  return faces;
}

std::vector<UnconfirmedPoint> Mesher::Impl::unconfirmedPoints() const {
  std::vector<UnconfirmedPoint> points;
  points.reserve(state_.registry.waitingPoints().size());
  for (std::uint32_t index : state_.registry.waitingPoints()) {
    const internal::PointRecord& record = state_.registry.point(index);
    points.push_back({record.id, record.latest_W, static_cast<std::uint32_t>(record.keyframes.size())});
  }
  std::sort(points.begin(), points.end(),
            [](const UnconfirmedPoint& a, const UnconfirmedPoint& b) { return a.id < b.id; });
  return points;
}

UnconfirmedChanges Mesher::Impl::unconfirmedChangesSince(const UnconfirmedCursor& cursor) const {
  UnconfirmedChanges changes;
  changes.cursor = unconfirmedCursor();
  if (cursor.instance != instance_) return changes;
  const std::optional<std::vector<PointId>> logged = state_.registry.waitingChangesSince(cursor.revision);
  if (!logged) return changes;
  changes.complete = true;
  for (const PointId id : *logged) {
    const std::uint32_t index = state_.registry.findPoint(id);
    if (index != internal::kNone && state_.registry.waitingPoints().count(index) != 0) {
      const internal::PointRecord& record = state_.registry.point(index);
      changes.waiting.push_back({record.id, record.latest_W, static_cast<std::uint32_t>(record.keyframes.size())});
    } else {
      changes.gone.push_back(id);
    }
  }
  return changes;
}

}  // namespace terramesh::mesher
