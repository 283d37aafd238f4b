#pragma once

#include "mesher/triangle_mesh.h"

namespace terramesh::baselines {

/// Merges vertices whose coordinates round to the same multiple of `tolerance` (0: identical
/// coordinates only), so a triangle soup becomes an indexed mesh; faces keep their order, faces
/// that collapse (two corners merged) are dropped; is_steiner is kept (a merged vertex is Steiner
/// if any copy was). O(V + F) expected.
/// @throw std::invalid_argument if tolerance is negative or not finite.
mesher::TriangleMesh weldVertices(const mesher::TriangleMesh& mesh, double tolerance = 0);

}  // namespace terramesh::baselines
