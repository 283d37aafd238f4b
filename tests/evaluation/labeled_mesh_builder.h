#pragma once
// Hand-made labelled meshes for the traversability evaluation tests (z up, metres).

#include <Eigen/Core>
#include <cmath>

#include "datasets/labeled_mesh.h"

namespace terramesh::test {

/// Adds the quad a-b-c-d (counter-clockwise seen from free space) as two triangles with `label`
/// and the slope of its normal against +z.
inline void addQuad(datasets::LabeledMesh& mesh, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    const Eigen::Vector3d& c, const Eigen::Vector3d& d, datasets::SurfaceLabel label) {
  const auto base = static_cast<std::uint32_t>(mesh.mesh.vertices.size());
  for (const Eigen::Vector3d& p : {a, b, c, d}) mesh.mesh.vertices.push_back(p);
  mesh.mesh.faces.push_back({base, base + 1, base + 2});
  mesh.mesh.faces.push_back({base, base + 2, base + 3});
  const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
  const auto slope = static_cast<float>(std::acos(std::clamp(normal.z(), -1.0, 1.0)) * 180.0 / M_PI);
  for (int k = 0; k < 2; ++k) {
    mesh.labels.push_back(label);
    mesh.slope_deg.push_back(slope);
  }
}

/// The level rectangle [x0, x1] x [y0, y1] at height z, facing up.
inline void addFloor(datasets::LabeledMesh& mesh, double x0, double x1, double y0, double y1, double z,
                     datasets::SurfaceLabel label) {
  addQuad(mesh, {x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}, label);
}

}  // namespace terramesh::test
