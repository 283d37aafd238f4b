#pragma once

#include <cstddef>

#include "mesher/triangle_mesh.h"

namespace terramesh::evaluation {

/// Manifoldness of a triangle mesh.
struct Manifoldness {
  std::size_t vertices = 0;  ///< referenced by a face
  std::size_t faces = 0;
  std::size_t non_manifold_edges = 0;     ///< edges with more than two faces
  std::size_t non_manifold_vertices = 0;  ///< vertices whose faces form more than one fan
  std::size_t boundary_edges = 0;         ///< edges with exactly one face
  /// Connected pieces of the graph of boundary edges (one per hole or border on a manifold mesh).
  std::size_t boundary_loops = 0;
  std::size_t components = 0;  ///< connected through shared vertices
  /// Sum over components of (2 - chi - b) / 2, chi = V - E + F and b the boundary loops of the
  /// component: the genus of each surface when it is a manifold (a formal value otherwise).
  long genus = 0;
  std::size_t orientation_errors = 0;  ///< directed edges used by more than one face
};

/// Counts the above (mesher::analyzeTopology plus boundary loops and the genus of open
/// components). O(F log F).
Manifoldness measureManifoldness(const mesher::TriangleMesh& mesh);

}  // namespace terramesh::evaluation
