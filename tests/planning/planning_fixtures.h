#pragma once

// Small hand-built traversability maps with known geometry, for the planning tests.

#include <Eigen/Core>
#include <functional>
#include <optional>

#include "traversability/layered_mesh.h"

namespace terramesh::test {

/// Builds a LayeredMesh from rectangular sheets; vertices at the same position are shared, so
/// sheets meeting along a grid line are joined.
class LayeredMeshBuilder {
 public:
  /// A sheet over [x0, x1] x [y0, y1] with `cell_m` cells, height z(x, y), faces facing +z.
  /// `class_of(centroid)` gives each face's class (nullopt: a hole).
  void sheet(double x0, double x1, double y0, double y1, double cell_m, const std::function<double(double, double)>& z,
             const std::function<std::optional<traversability::FaceClass>(const Eigen::Vector3d&)>& class_of);
  /// A vertical wall quad from (x0, y0) to (x1, y1) between heights z0 and z1, split into cells,
  /// all faces lethal. Its normal points to the left of (x1 - x0, y1 - y0).
  void wall(double x0, double y0, double x1, double y1, double z0, double z1, double cell_m);
  /// The mesh with layers: cost 0.2 for free faces (1 lethal, NaN unknown) and lethal_distance_m
  /// from each free face's centroid to the nearest lethal face centroid (straight line).
  traversability::LayeredMesh finish() const;

 private:
  std::uint32_t vertex(const Eigen::Vector3d& p);
  traversability::LayeredMesh map_;
  std::vector<traversability::FaceClass> classes_;
};

/// A 20 x 10 m floor (0.5 m cells) at z = 0 with a lethal strip x in [9.5, 10.5], y < 7: the way
/// from x < 9.5 to x > 10.5 is round its end.
traversability::LayeredMesh wallWithGapMap();

/// A 20 x 10 m floor (0.5 m cells) at z = 0 cut by a strip x in [9.5, 10.5] across its whole
/// width: lethal for y < 6, unknown for y > 6 (or lethal throughout with `all_lethal`). The only
/// way from x < 9.5 to x > 10.5 is over the unknown part.
traversability::LayeredMesh unknownGapMap(bool all_lethal = false);

/// Two floors over the same ground: level 0 at z = 0 over [0, 20] x [0, 10], level 1 at z = 3 over
/// [0, 40] x [4, 10], joined only by a ramp over [20, 40] x [0, 4] (z from 0 to 3, 8.5 degrees)
/// and a landing at z = 3 over [40, 44] x [0, 10]. Also a box [10, 12] x [1, 3], 1 m high, with
/// lethal sides and a free top, and an unknown patch [2, 4] x [1, 3] on level 0.
traversability::LayeredMesh twoLevelMap();

}  // namespace terramesh::test
