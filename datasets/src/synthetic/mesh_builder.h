#pragma once
// Accumulates labelled triangles; every face's slope is computed from its own normal.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "datasets/labeled_mesh.h"

namespace terramesh::datasets::synthetic {

class LabeledMeshBuilder {
 public:
  /// `up_W`: unit up vector of the scene, against which slopes are measured.
  explicit LabeledMeshBuilder(const Eigen::Vector3d& up_W) : up_(up_W.normalized()) {}

  const Eigen::Vector3d& up() const { return up_; }

  /// Adds a vertex and returns its index.
  std::uint32_t vertex(const Eigen::Vector3d& position_W);

  /// Adds the triangle (a, b, c), counter-clockwise seen from free space. Triangles with an area
  /// below 1e-8 m^2 are dropped (collapsed curbs, clamped profiles); returns whether it was kept.
  bool triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, SurfaceLabel label);

  /// Adds the quad (a, b, c, d), counter-clockwise seen from free space, as two triangles.
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d, SurfaceLabel label);

  /// Same, from positions (the quad gets its own four vertices).
  void quad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
            const Eigen::Vector3d& d, SurfaceLabel label);

  /// A sheet over a grid of points `rows x cols` (row-major): the quad of cell (i, j) is
  /// (p[i][j], p[i+1][j], p[i+1][j+1], p[i][j+1]); `label_of(i, j)` labels it, or returns
  /// std::nullopt for a hole. Vertices are shared inside the sheet. The caller orders rows and
  /// columns so that this winding faces free space.
  template <class LabelOf>
  void sheet(const std::vector<Eigen::Vector3d>& points, std::size_t rows, std::size_t cols,
             LabelOf&& label_of) {
    const auto base = static_cast<std::uint32_t>(mesh_.mesh.vertices.size());
    for (const Eigen::Vector3d& p : points) vertex(p);
    auto at = [&](std::size_t i, std::size_t j) { return base + static_cast<std::uint32_t>(i * cols + j); };
    for (std::size_t i = 0; i + 1 < rows; ++i) {
      for (std::size_t j = 0; j + 1 < cols; ++j) {
        const std::optional<SurfaceLabel> label = label_of(i, j);
        if (label) quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), *label);
      }
    }
  }

  std::size_t faceCount() const { return mesh_.mesh.faces.size(); }

  /// Drops vertices no face uses and returns the mesh; the builder is left empty.
  LabeledMesh finish();

 private:
  Eigen::Vector3d up_;
  LabeledMesh mesh_;
};

}  // namespace terramesh::datasets::synthetic
