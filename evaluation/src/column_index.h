#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "common/grid_key.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::evaluation {

/// The faces of a mesh bucketed by their shadow on the horizontal plane, to answer "does any
/// surface lie inside this cylinder (axis through a centre along a given unit `axis`, e.g. the
/// normal of the ground there), between these heights along the axis?" exactly: each candidate
/// triangle is clipped to the height slab and its shadow on the plane across the axis compared
/// with the disc. Units are the mesh's. Build O(F + total shadow area / cell^2); not
/// thread-safe (keeps a visit stamp).
class ColumnIndex {
 public:
  /// @param up_W unit vector pointing up. @param cell_size side of the square buckets.
  ColumnIndex(const mesher::TriangleMesh& mesh, const Eigen::Vector3d& up_W, double cell_size);

  /// A query cylinder: axis through `centre` along unit `axis`, `radius` across it, and the
  /// slab `above_min` < axis.(q - centre) <= `above_max` along it.
  struct Column {
    Eigen::Vector3d centre;
    Eigen::Vector3d axis;
    double radius;
    double above_min;
    double above_max;
  };

  /// Whether a point of some face lies in the column.
  bool anyInColumn(const Column& column);

  /// The parts of faces in the column, each as its shadow: a convex polygon in coordinates
  /// across the axis (acrossBasis) relative to the centre, appended to `shadows`.
  void collectInColumn(const Column& column, std::vector<std::vector<Eigen::Vector2d>>& shadows);

  /// Two unit vectors across `axis`, the coordinates of the shadows (deterministic).
  static std::pair<Eigen::Vector3d, Eigen::Vector3d> acrossBasis(const Eigen::Vector3d& axis);

 private:
  /// Visits the faces that may reach the column; `visit(face)` returns false to stop.
  template <typename Visit>
  void forEachCandidate(const Column& column, Visit visit);
  /// The low 32 bits of i and j side by side (shifted as unsigned: i may be negative).
  std::int64_t key(long i, long j) const { return static_cast<std::int64_t>(geometry::packCell2(i, j)); }
  /// The shadow of the part of `face` in the slab, if it comes within the radius.
  bool faceInColumn(std::uint32_t face, const Column& column, std::vector<Eigen::Vector2d>& shadow) const;

  const mesher::TriangleMesh& mesh_;
  Eigen::Vector3d up_;
  Eigen::Vector3d east_;   ///< first horizontal axis
  Eigen::Vector3d north_;  ///< second horizontal axis
  double cell_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> buckets_;
  std::vector<double> min_height_, max_height_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t epoch_ = 0;
};

}  // namespace terramesh::evaluation
