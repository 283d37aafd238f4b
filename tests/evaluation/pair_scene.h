#pragma once
// The scene of the start-goal pair tests: two roads, one of them hidden from the cameras by a wall
// (z up, metres).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "evaluation/ground_truth_traversability.h"
#include "evaluation/robot_limits.h"

namespace terramesh::test {

/// A horizontal rectangle [x0, x1] x [y0, y1] at height z, split into a grid of `n` x `n` cells
/// (two triangles each, facing up), appended to `mesh` with `label` per face.
inline void addGrid(datasets::LabeledMesh& mesh, double x0, double x1, double y0, double y1, double z, int n,
                    datasets::SurfaceLabel label) {
  const auto base = static_cast<std::uint32_t>(mesh.mesh.vertices.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.mesh.vertices.emplace_back(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n, z);
  }
  auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.mesh.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.mesh.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      for (int k = 0; k < 2; ++k) {
        mesh.labels.push_back(label);
        mesh.slope_deg.push_back(label == datasets::SurfaceLabel::kWall ? 90.0f : 0.0f);
      }
    }
  }
}

/// A vertical wall x = x, y in [y0, y1], z in [0, height].
inline void addWall(datasets::LabeledMesh& mesh, double x, double y0, double y1, double height) {
  const auto base = static_cast<std::uint32_t>(mesh.mesh.vertices.size());
  mesh.mesh.vertices.insert(mesh.mesh.vertices.end(), {{x, y0, 0}, {x, y1, 0}, {x, y1, height}, {x, y0, height}});
  mesh.mesh.faces.push_back({base, base + 1, base + 2});
  mesh.mesh.faces.push_back({base, base + 2, base + 3});
  for (int k = 0; k < 2; ++k) {
    mesh.labels.push_back(datasets::SurfaceLabel::kWall);
    mesh.slope_deg.push_back(90.0f);
  }
}

/// Road A [0, 20] x [0, 4] seen by two cameras; road B [30, 40] x [-10, 14], three times A's area,
/// hidden from them by a wall at x = 25: without the observation filter the pairs would be on B.
struct PairScene {
  datasets::LabeledMesh truth;
  std::vector<Eigen::Vector3d> cameras{{4, 2, 1.5}, {8, 2, 1.5}};
  PairScene() {
    addGrid(truth, 0, 20, 0, 4, 0, 20, datasets::SurfaceLabel::kRoad);
    addGrid(truth, 30, 40, -10, 14, 0, 20, datasets::SurfaceLabel::kRoad);
    addWall(truth, 25, -20, 20, 6);
  }
};

inline evaluation::GroundTruthTraversability labelled(const PairScene& scene) {
  evaluation::RobotLimits robot;
  robot.footprint_radius_m = 0.2;
  return evaluation::labelTraversability(scene.truth, robot, Eigen::Vector3d::UnitZ(), {});
}

}  // namespace terramesh::test
