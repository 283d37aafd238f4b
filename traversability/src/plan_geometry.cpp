#include "plan_geometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace terramesh::traversability::internal {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

FacePlan planFace(const mesher::TriangleMesh& mesh, std::size_t face, const MapPlane& plane) {
  FacePlan p;
  const auto& f = mesh.faces[face];
  const Eigen::Vector3d& a = mesh.vertices[f[0]];
  const Eigen::Vector3d& b = mesh.vertices[f[1]];
  const Eigen::Vector3d& c = mesh.vertices[f[2]];
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  const double norm = normal.norm();
  if (!std::isfinite(norm) || norm <= 0) return p;
  p.valid = true;
  p.up_cosine = normal.dot(plane.z_W) / norm;
  const std::array<const Eigen::Vector3d*, 3> corners{&a, &b, &c};
  for (std::size_t k = 0; k < 3; ++k) {
    p.corners_m[k] = plane.planM(*corners[k]);
    p.heights_m[k] = plane.heightM(*corners[k]);
  }
  p.min_m = p.corners_m[0].cwiseMin(p.corners_m[1]).cwiseMin(p.corners_m[2]);
  p.max_m = p.corners_m[0].cwiseMax(p.corners_m[1]).cwiseMax(p.corners_m[2]);
  p.min_height_m = std::min({p.heights_m[0], p.heights_m[1], p.heights_m[2]});
  p.max_height_m = std::max({p.heights_m[0], p.heights_m[1], p.heights_m[2]});
  p.centroid_height_m = (p.heights_m[0] + p.heights_m[1] + p.heights_m[2]) / 3;
  p.plan_area_m2 = 0.5 * std::abs(cross(p.corners_m[1] - p.corners_m[0], p.corners_m[2] - p.corners_m[0]));
  return p;
}

bool squareTouchesTriangle(const Eigen::Vector2d& lo, double size, const std::array<Eigen::Vector2d, 3>& t) {
  const Eigen::Vector2d hi = lo + Eigen::Vector2d(size, size);
  const Eigen::Vector2d tmin = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
  const Eigen::Vector2d tmax = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
  if (tmax.x() <= lo.x() || tmin.x() >= hi.x() || tmax.y() <= lo.y() || tmin.y() >= hi.y()) return false;
  const std::array<Eigen::Vector2d, 4> square{lo, Eigen::Vector2d(hi.x(), lo.y()), hi, Eigen::Vector2d(lo.x(), hi.y())};
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector2d edge = t[(k + 1) % 3] - t[k];
    const Eigen::Vector2d axis(-edge.y(), edge.x());
    if (axis.squaredNorm() == 0) continue;
    double smin = axis.dot(square[0]), smax = smin;
    for (const auto& q : square) {
      smin = std::min(smin, axis.dot(q));
      smax = std::max(smax, axis.dot(q));
    }
    const double t0 = axis.dot(t[0]), t1 = axis.dot(t[1]), t2 = axis.dot(t[2]);
    if (std::max({t0, t1, t2}) <= smin || std::min({t0, t1, t2}) >= smax) return false;
  }
  return true;
}

bool triangleContains(const std::array<Eigen::Vector2d, 3>& t, const Eigen::Vector2d& point) {
  const double d0 = cross(t[1] - t[0], point - t[0]);
  const double d1 = cross(t[2] - t[1], point - t[1]);
  const double d2 = cross(t[0] - t[2], point - t[2]);
  const bool negative = d0 < 0 || d1 < 0 || d2 < 0;
  const bool positive = d0 > 0 || d1 > 0 || d2 > 0;
  return !(negative && positive);
}

double heightAt(const FacePlan& face, const Eigen::Vector2d& point_m) {
  const Eigen::Vector2d e1 = face.corners_m[1] - face.corners_m[0];
  const Eigen::Vector2d e2 = face.corners_m[2] - face.corners_m[0];
  const double det = cross(e1, e2);
  if (std::abs(det) < 1e-12) return face.centroid_height_m;
  const Eigen::Vector2d d = point_m - face.corners_m[0];
  const double u = cross(d, e2) / det, v = cross(e1, d) / det;
  const double h = face.heights_m[0] + u * (face.heights_m[1] - face.heights_m[0]) +
                   v * (face.heights_m[2] - face.heights_m[0]);
  return std::clamp(h, face.min_height_m, face.max_height_m);
}

std::vector<std::pair<CellKey, HeightRange>> cellHeightRanges(const FacePlan& face, double cell_m) {
  std::vector<std::pair<CellKey, HeightRange>> result;
  if (!face.valid) return result;
  const CellKey lo = geometry::cellOf(face.min_m, cell_m), hi = geometry::cellOf(face.max_m, cell_m);
  const bool has_area = face.plan_area_m2 > 1e-9;
  for (std::int64_t i = lo.i; i <= hi.i; ++i) {
    for (std::int64_t j = lo.j; j <= hi.j; ++j) {
      const Eigen::Vector2d corner(static_cast<double>(i) * cell_m, static_cast<double>(j) * cell_m);
      if (!squareTouchesTriangle(corner, cell_m, face.corners_m)) continue;
      HeightRange range{face.min_height_m, face.max_height_m};
      if (has_area) {
        range = {face.max_height_m, face.min_height_m};
        for (const Eigen::Vector2d& offset : {Eigen::Vector2d(0, 0), Eigen::Vector2d(cell_m, 0),
                                             Eigen::Vector2d(0, cell_m), Eigen::Vector2d(cell_m, cell_m)}) {
          const double h = heightAt(face, corner + offset);
          range.lo = std::min(range.lo, h);
          range.hi = std::max(range.hi, h);
        }
      }
      result.emplace_back(CellKey{i, j}, range);
    }
  }
  return result;
}

}  // namespace terramesh::traversability::internal
