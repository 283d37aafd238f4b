#include "mesh_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terramesh::datasets::synthetic {
namespace {

constexpr double kMinTriangleArea = 1e-8;
constexpr double kRadToDeg = 180.0 / M_PI;

}  // namespace

std::uint32_t LabeledMeshBuilder::vertex(const Eigen::Vector3d& position_W) {
  mesh_.mesh.vertices.push_back(position_W);
  return static_cast<std::uint32_t>(mesh_.mesh.vertices.size() - 1);
}

bool LabeledMeshBuilder::triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, SurfaceLabel label) {
  const auto& v = mesh_.mesh.vertices;
  const Eigen::Vector3d normal = (v[b] - v[a]).cross(v[c] - v[a]);
  const double twice_area = normal.norm();
  if (!(twice_area >= 2.0 * kMinTriangleArea)) return false;
  const double cosine = std::clamp(normal.dot(up_) / twice_area, -1.0, 1.0);
  mesh_.mesh.faces.push_back({a, b, c});
  mesh_.labels.push_back(label);
  mesh_.slope_deg.push_back(static_cast<float>(std::acos(cosine) * kRadToDeg));
  return true;
}

void LabeledMeshBuilder::quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d,
                              SurfaceLabel label) {
  triangle(a, b, c, label);
  triangle(a, c, d, label);
}

void LabeledMeshBuilder::quad(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                              const Eigen::Vector3d& c, const Eigen::Vector3d& d, SurfaceLabel label) {
  const std::uint32_t ia = vertex(a), ib = vertex(b), ic = vertex(c), id = vertex(d);
  quad(ia, ib, ic, id, label);
}

LabeledMesh LabeledMeshBuilder::finish() {
  constexpr auto kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> remap(mesh_.mesh.vertices.size(), kUnused);
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(mesh_.mesh.vertices.size());
  for (auto& face : mesh_.mesh.faces) {
    for (std::uint32_t& index : face) {
      if (remap[index] == kUnused) {
        remap[index] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(mesh_.mesh.vertices[index]);
      }
      index = remap[index];
    }
  }
  mesh_.mesh.vertices = std::move(kept);
  LabeledMesh result = std::move(mesh_);
  mesh_ = LabeledMesh();
  return result;
}

}  // namespace terramesh::datasets::synthetic
