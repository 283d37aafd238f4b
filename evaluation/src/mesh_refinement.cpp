#include "evaluation/mesh_refinement.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace terramesh::evaluation {
namespace {

using Triangle = std::array<Eigen::Vector3d, 3>;

/// Appends the pieces of `triangle` to `out` (depth-first, so the order is deterministic).
void split(const Triangle& triangle, double max_edge_sq, std::uint32_t parent, RefinedMesh& out) {
  std::vector<Triangle> stack{triangle};
  while (!stack.empty()) {
    const Triangle t = stack.back();
    stack.pop_back();
    int longest = 0;
    double longest_sq = -1;
    for (int e = 0; e < 3; ++e) {
      const double length_sq = (t[(e + 1) % 3] - t[e]).squaredNorm();
      if (length_sq > longest_sq) {
        longest_sq = length_sq;
        longest = e;
      }
    }
    const double twice_area = (t[1] - t[0]).cross(t[2] - t[0]).norm();
    if (longest_sq <= max_edge_sq || twice_area <= 0) {
      const auto base = static_cast<std::uint32_t>(out.mesh.vertices.size());
      out.mesh.vertices.insert(out.mesh.vertices.end(), t.begin(), t.end());
      out.mesh.faces.push_back({base, base + 1, base + 2});
      out.parent_face.push_back(parent);
      continue;
    }
    // Edge (a, b) is split at m; c is the opposite vertex. Both halves keep the winding a-b-c.
    const Eigen::Vector3d& a = t[longest];
    const Eigen::Vector3d& b = t[(longest + 1) % 3];
    const Eigen::Vector3d& c = t[(longest + 2) % 3];
    const Eigen::Vector3d m = 0.5 * (a + b);
    stack.push_back({m, b, c});
    stack.push_back({a, m, c});
  }
}

}  // namespace

RefinedMesh refineMesh(const mesher::TriangleMesh& mesh, double max_edge) {
  if (std::isnan(max_edge)) throw std::invalid_argument("refineMesh: max_edge is NaN");
  const double max_edge_sq = max_edge > 0 && std::isfinite(max_edge) ? max_edge * max_edge
                                                                       : std::numeric_limits<double>::infinity();
  RefinedMesh out;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.faces[f][k];
      if (v >= mesh.vertices.size()) {
        throw std::invalid_argument("refineMesh: face " + std::to_string(f) + " indexes missing vertex " +
                                    std::to_string(v));
      }
      t[k] = mesh.vertices[v];
    }
    split(t, max_edge_sq, static_cast<std::uint32_t>(f), out);
  }
  return out;
}

datasets::LabeledMesh refineLabeledMesh(const datasets::LabeledMesh& mesh, double max_edge) {
  mesh.validate();
  RefinedMesh refined = refineMesh(mesh.mesh, max_edge);
  datasets::LabeledMesh out;
  out.labels.reserve(refined.parent_face.size());
  out.slope_deg.reserve(refined.parent_face.size());
  for (const std::uint32_t parent : refined.parent_face) {
    out.labels.push_back(mesh.labels[parent]);
    out.slope_deg.push_back(mesh.slope_deg[parent]);
  }
  out.mesh = std::move(refined.mesh);
  return out;
}

double faceArea(const mesher::TriangleMesh& mesh, std::size_t f) {
  const auto& face = mesh.faces[f];
  const Eigen::Vector3d& a = mesh.vertices[face[0]];
  return 0.5 * (mesh.vertices[face[1]] - a).cross(mesh.vertices[face[2]] - a).norm();
}

Eigen::Vector3d faceCentroid(const mesher::TriangleMesh& mesh, std::size_t f) {
  const auto& face = mesh.faces[f];
  return (mesh.vertices[face[0]] + mesh.vertices[face[1]] + mesh.vertices[face[2]]) / 3.0;
}

}  // namespace terramesh::evaluation
