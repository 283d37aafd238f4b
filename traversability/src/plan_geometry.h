#pragma once

// Faces of a layered mesh seen in the horizontal map plane (internal to the exports).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "common/grid_key.h"
#include "mesher/triangle_mesh.h"
#include "traversability/map_levels.h"

namespace terramesh::traversability::internal {

/// A cell of a square plan grid: floor(x / size), floor(y / size).
using CellKey = geometry::CellKey2;
using CellKeyHash = geometry::CellKey2Hash;

/// A closed height interval, metres.
struct HeightRange {
  double lo = 0;
  double hi = 0;
  HeightRange merged(const HeightRange& other) const {
    return {lo < other.lo ? lo : other.lo, hi > other.hi ? hi : other.hi};
  }
};

/// One face in the map plane, metres.
struct FacePlan {
  bool valid = false;  ///< finite, non-degenerate in 3D
  std::array<Eigen::Vector2d, 3> corners_m;
  std::array<double, 3> heights_m{};
  Eigen::Vector2d min_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d max_m = Eigen::Vector2d::Zero();
  double min_height_m = 0;
  double max_height_m = 0;
  double centroid_height_m = 0;
  double plan_area_m2 = 0;  ///< area of the projection on the plane
  double up_cosine = 0;     ///< cosine between the face normal and up (1: facing straight up)
};

FacePlan planFace(const mesher::TriangleMesh& mesh, std::size_t face, const MapPlane& plane);

/// True if the interiors of the square [lo, lo + size]^2 and the triangle intersect (SAT; touching
/// along a boundary does not count).
bool squareTouchesTriangle(const Eigen::Vector2d& lo, double size, const std::array<Eigen::Vector2d, 3>& t);

/// True if `point` lies inside the triangle or on its boundary (either winding).
bool triangleContains(const std::array<Eigen::Vector2d, 3>& t, const Eigen::Vector2d& point);

/// Height of the face's plane over a plan point; clamped to the face's height range. @pre a
/// face with plan area.
double heightAt(const FacePlan& face, const Eigen::Vector2d& point_m);

/// The cells of size `cell_m` that the face touches in plan, each with the face's height range
/// over the cell (its plane at the cell's corners, clamped to the face's range).
std::vector<std::pair<CellKey, HeightRange>> cellHeightRanges(const FacePlan& face, double cell_m);

}  // namespace terramesh::traversability::internal
