#pragma once

#include <Eigen/Core>

#include "mesher/triangle_mesh.h"

namespace terramesh::test {

/// Whether `p` is inside the closed mesh, by the parity of crossings of a ray in a fixed generic
/// direction (brute force over all faces).
bool insideClosedMesh(const mesher::TriangleMesh& mesh, const Eigen::Vector3d& p);

/// Fraction of `samples` points drawn uniformly (fixed seed) in the box [lo, hi] that are inside.
double fractionInside(const mesher::TriangleMesh& mesh, const Eigen::Vector3d& lo,
                      const Eigen::Vector3d& hi, int samples);

}  // namespace terramesh::test
