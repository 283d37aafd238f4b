// White-box test helper: the surface dO of the cells a triangulation flags outside, and whether it
// is a closed 2-manifold (the oracle the manifold tests compare against).
#pragma once

#include <cstdint>
#include <map>

#include "cgal_types.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::mesher::internal::test {

/// Boundary of the cells flagged outside, as a triangle mesh.
inline TriangleMesh boundaryOf(const Delaunay& tri) {
  TriangleMesh mesh;
  std::map<const Delaunay::Vertex*, std::uint32_t> index;
  auto id = [&](const VertexHandle& v) {
    const auto [it, inserted] = index.try_emplace(&*v, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) mesh.vertices.push_back(toEigen(v->point()));
    return it->second;
  };
  for (auto cell = tri.finite_cells_begin(); cell != tri.finite_cells_end(); ++cell) {
    if (!cell->info().outside()) continue;
    for (int i = 0; i < 4; ++i) {
      if (cell->neighbor(i)->info().outside()) continue;
      mesh.faces.push_back({id(cell->vertex(Delaunay::vertex_triple_index(i, 0))),
                            id(cell->vertex(Delaunay::vertex_triple_index(i, 1))),
                            id(cell->vertex(Delaunay::vertex_triple_index(i, 2)))});
    }
  }
  return mesh;
}

inline bool surfaceIsManifold(const Delaunay& tri) { return analyzeTopology(boundaryOf(tri)).isClosedManifold(); }

}  // namespace terramesh::mesher::internal::test
