#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "mesher_impl.h"

namespace terramesh::mesher {

using internal::CellHandle;
using internal::kRayMarked;
using internal::kRayNeedsTrace;
using internal::kRayTraced;
using internal::VertexHandle;

namespace {

/// Puts a mesh in a canonical order, independent of where the triangulation's cells sit in memory:
/// vertices sorted by position, each face rotated to start at its smallest index (winding kept),
/// faces sorted.
void canonicalize(TriangleMesh& mesh) {
  std::vector<std::uint32_t> order(mesh.vertices.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&mesh](std::uint32_t a, std::uint32_t b) {
    const Eigen::Vector3d& p = mesh.vertices[a];
    const Eigen::Vector3d& q = mesh.vertices[b];
    return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
  });
  std::vector<std::uint32_t> rank(order.size());
  TriangleMesh sorted;
  sorted.vertices.reserve(order.size());
  sorted.is_steiner.reserve(order.size());
  sorted.driven_kind.reserve(order.size());
  sorted.vertex_keys.reserve(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    rank[order[i]] = i;
    sorted.vertices.push_back(mesh.vertices[order[i]]);
    sorted.is_steiner.push_back(mesh.is_steiner[order[i]]);
    sorted.driven_kind.push_back(mesh.driven_kind[order[i]]);
    sorted.vertex_keys.push_back(mesh.vertex_keys[order[i]]);
  }
  // Faces sorted (each starting at its smallest index), with their observations.
  std::vector<std::array<std::uint32_t, 3>> faces(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    auto& face = faces[f];
    face = mesh.faces[f];
    for (auto& index : face) index = rank[index];
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
  }
  std::vector<std::size_t> face_order(faces.size());
  std::iota(face_order.begin(), face_order.end(), std::size_t{0});
  std::sort(face_order.begin(), face_order.end(), [&](std::size_t a, std::size_t b) { return faces[a] < faces[b]; });
  for (std::size_t f : face_order) {
    sorted.faces.push_back(faces[f]);
    sorted.face_rays.push_back(mesh.face_rays[f]);
    sorted.face_front_crossings.push_back(mesh.face_front_crossings[f]);
    sorted.face_view_sides.push_back(mesh.face_view_sides[f]);
    sorted.face_back_crossings.push_back(mesh.face_back_crossings[f]);
    sorted.face_back_depth.push_back(mesh.face_back_depth[f]);
  }
  mesh = std::move(sorted);
}

}  // namespace

TriangleMesh Mesher::Impl::extractMesh() const {
  TriangleMesh mesh;
  std::unordered_map<const internal::Delaunay::Vertex*, std::uint32_t> index;
  auto vertexIndex = [&](const VertexHandle& v) {
    const auto [it, inserted] = index.try_emplace(&*v, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) {
      mesh.vertices.push_back(internal::toEigen(v->point()));
      mesh.is_steiner.push_back(v->info().steiner ? 1 : 0);
      const std::uint32_t point = v->info().point;
      mesh.driven_kind.push_back(
          point != internal::kNone ? static_cast<std::uint8_t>(state_.registry.point(point).kind) : 0);
      mesh.vertex_keys.push_back(state_.outside.vertexKey(v));
    }
    return it->second;
  };
  for (auto cell = state_.tri.finite_cells_begin(); cell != state_.tri.finite_cells_end(); ++cell) {
    if (!cell->info().outside()) continue;
    for (int i = 0; i < 4; ++i) {
      if (cell->neighbor(i)->info().outside()) continue;
      // CGAL's vertex_triple_index winds the facet with its normal into the cell, i.e. into free
      // space: the orientation the output mesh uses.
      std::array<std::uint32_t, 3> face{};
      for (int k = 0; k < 3; ++k) {
        face[static_cast<std::size_t>(k)] =
            vertexIndex(cell->vertex(internal::Delaunay::vertex_triple_index(i, k)));
      }
      mesh.faces.push_back(face);
      // The observation counts the surface queries report for this face (makeFace).
      const SurfaceFace observed = makeFace(cell, i);
      mesh.face_rays.push_back(observed.rays);
      mesh.face_front_crossings.push_back(observed.front_crossings);
      mesh.face_view_sides.push_back(observed.view_sides);
      mesh.face_back_crossings.push_back(observed.back_crossings);
      mesh.face_back_depth.push_back(observed.back_depth);
    }
  }
  canonicalize(mesh);
  return mesh;
}

std::vector<CellVisibility> Mesher::Impl::cellVisibility() const {
  std::vector<CellVisibility> cells;
  cells.reserve(state_.tri.number_of_finite_cells());
  auto less = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  for (auto cell = state_.tri.finite_cells_begin(); cell != state_.tri.finite_cells_end(); ++cell) {
    CellVisibility visibility;
    for (int i = 0; i < 4; ++i) {
      visibility.vertices_W[static_cast<std::size_t>(i)] = internal::toEigen(cell->vertex(i)->point());
    }
    std::sort(visibility.vertices_W.begin(), visibility.vertices_W.end(), less);
    visibility.weight = static_cast<double>(cell->info().weight) / internal::WeightField::kFixedPointScale;
    visibility.crossings = cell->info().crossings;
    visibility.outside = cell->info().outside();
    visibility.driven_crossings = cell->info().driven_crossings;
    visibility.free = state_.isFree(cell);
    cells.push_back(visibility);
  }
  std::sort(cells.begin(), cells.end(), [&less](const CellVisibility& a, const CellVisibility& b) {
    return std::lexicographical_compare(a.vertices_W.begin(), a.vertices_W.end(), b.vertices_W.begin(),
                                        b.vertices_W.end(), less);
  });
  return cells;
}

MapSize Mesher::Impl::size() const {
  MapSize size;
  size.keyframes = state_.registry.keyframeCount();
  size.points = state_.registry.pointCount();
  size.steiner_vertices = state_.steiner_vertices;
  const std::size_t vertices = state_.tri.number_of_vertices();
  size.inserted_points = vertices - state_.steiner_vertices;
  size.cells = state_.tri.tds().number_of_cells();  // O(1); counting finite cells is O(cells)
  size.outside_cells = state_.outside.size();
  size.rays = state_.rays.size();
  size.ray_crossings = state_.rays.totalCrossings();
  const std::size_t all_cells = state_.tri.tds().number_of_cells();
  size.triangulation_bytes = (vertices + 1) * sizeof(internal::Delaunay::Vertex) +
                             all_cells * sizeof(internal::Delaunay::Cell);
  size.ray_bytes = state_.rays.memoryBytes();
  size.point_bytes = state_.registry.pointBytes(state_.rays.size());
  size.index_bytes = state_.registry.indexBytes() + state_.hash.memoryBytes() +
                     state_.surface_log.memoryBytes() +
                     state_.steiner_nodes.size() * (sizeof(std::uint64_t) + sizeof(VertexHandle) + 2 * sizeof(void*)) +
                     state_.steiner_nodes.bucket_count() * sizeof(void*);
  return size;
}

}  // namespace terramesh::mesher
