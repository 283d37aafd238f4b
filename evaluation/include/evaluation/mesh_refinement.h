#pragma once

#include <cstdint>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::evaluation {

/// A mesh whose faces were split, with the face of the original mesh each piece came from.
struct RefinedMesh {
  /// A triangle soup (three vertices of its own per face), same frame and units as the input.
  mesher::TriangleMesh mesh;
  /// One per face of `mesh`: the index of the input face it is part of.
  std::vector<std::uint32_t> parent_face;
};

/// Splits every face at the midpoint of its longest edge, recursively, until no edge is longer
/// than `max_edge` (mesh units). The pieces cover each face exactly (same plane, same total area,
/// same winding). `max_edge` <= 0 or +inf copies the faces unsplit. Zero-area faces are kept
/// whole. O(total area / max_edge^2 + F).
/// @throw std::invalid_argument if a face indexes a missing vertex or `max_edge` is NaN.
RefinedMesh refineMesh(const mesher::TriangleMesh& mesh, double max_edge);

/// refineMesh on a labelled mesh; every piece keeps its face's label and slope.
/// @throw std::invalid_argument as refineMesh, or if `mesh` does not validate.
datasets::LabeledMesh refineLabeledMesh(const datasets::LabeledMesh& mesh, double max_edge);

/// Area of face `f` (mesh units squared).
double faceArea(const mesher::TriangleMesh& mesh, std::size_t f);

/// Centroid of face `f`.
Eigen::Vector3d faceCentroid(const mesher::TriangleMesh& mesh, std::size_t f);

}  // namespace terramesh::evaluation
