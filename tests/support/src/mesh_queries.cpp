#include "test_support/mesh_queries.h"

#include <Eigen/Geometry>
#include <random>

namespace terramesh::test {

bool insideClosedMesh(const mesher::TriangleMesh& mesh, const Eigen::Vector3d& p) {
  // A direction unlikely to graze edges of meshes built on round coordinates.
  const Eigen::Vector3d d = Eigen::Vector3d(0.5773, 0.4123, 0.7049).normalized();
  int crossings = 0;
  for (const auto& face : mesh.faces) {
    const Eigen::Vector3d& a = mesh.vertices[face[0]];
    const Eigen::Vector3d& b = mesh.vertices[face[1]];
    const Eigen::Vector3d& c = mesh.vertices[face[2]];
    // Moller-Trumbore.
    const Eigen::Vector3d e1 = b - a;
    const Eigen::Vector3d e2 = c - a;
    const Eigen::Vector3d h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-14) continue;
    const Eigen::Vector3d s = p - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(q) / det > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

double fractionInside(const mesher::TriangleMesh& mesh, const Eigen::Vector3d& lo,
                      const Eigen::Vector3d& hi, int samples) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int inside = 0;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector3d p = lo + (hi - lo).cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    inside += insideClosedMesh(mesh, p);
  }
  return static_cast<double>(inside) / samples;
}

}  // namespace terramesh::test
