#include "column_index.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "common/plan_frame.h"

namespace terramesh::evaluation {
namespace {

/// Keeps the part of the polygon where sign * (height - level) >= 0 (Sutherland-Hodgman).
std::vector<Eigen::Vector3d> clip(const std::vector<Eigen::Vector3d>& polygon, const Eigen::Vector3d& up,
                                  double level, double sign) {
  std::vector<Eigen::Vector3d> out;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = polygon[i];
    const Eigen::Vector3d& q = polygon[(i + 1) % n];
    const double dp = sign * (up.dot(p) - level);
    const double dq = sign * (up.dot(q) - level);
    if (dp >= 0) out.push_back(p);
    if ((dp >= 0) != (dq >= 0)) out.push_back(p + (dp / (dp - dq)) * (q - p));
  }
  return out;
}

/// Distance from the origin to the segment [a, b] in 2D.
double segmentDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_sq = ab.squaredNorm();
  const double t = length_sq > 0 ? std::clamp(-a.dot(ab) / length_sq, 0.0, 1.0) : 0.0;
  return (a + t * ab).norm();
}

}  // namespace

ColumnIndex::ColumnIndex(const mesher::TriangleMesh& mesh, const Eigen::Vector3d& up_W, double cell_size)
    : mesh_(mesh), up_(up_W.normalized()), cell_(cell_size) {
  std::tie(east_, north_) = acrossBasis(up_);
  min_height_.resize(mesh.faces.size());
  max_height_.resize(mesh.faces.size());
  stamp_.assign(mesh.faces.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
    double hi[3] = {-lo[0], -lo[0], -lo[0]};
    for (const std::uint32_t v : mesh.faces[f]) {
      const Eigen::Vector3d& p = mesh.vertices[v];
      const double coords[3] = {east_.dot(p), north_.dot(p), up_.dot(p)};
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], coords[k]);
        hi[k] = std::max(hi[k], coords[k]);
      }
    }
    min_height_[f] = lo[2];
    max_height_[f] = hi[2];
    const long i0 = std::lround(std::floor(lo[0] / cell_)), i1 = std::lround(std::floor(hi[0] / cell_));
    const long j0 = std::lround(std::floor(lo[1] / cell_)), j1 = std::lround(std::floor(hi[1] / cell_));
    for (long i = i0; i <= i1; ++i) {
      for (long j = j0; j <= j1; ++j) buckets_[key(i, j)].push_back(static_cast<std::uint32_t>(f));
    }
  }
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> ColumnIndex::acrossBasis(const Eigen::Vector3d& axis) {
  const geometry::PlanFrame frame = geometry::planFrame(axis, geometry::acrossFrameRule());
  return {frame.e1, frame.e2};
}

bool ColumnIndex::faceInColumn(std::uint32_t face, const Column& column, std::vector<Eigen::Vector2d>& shadow) const {
  std::vector<Eigen::Vector3d> polygon;
  for (const std::uint32_t v : mesh_.faces[face]) polygon.push_back(mesh_.vertices[v] - column.centre);
  // Strictly above `above_min`: nudge the level by a relative epsilon.
  const double lower = column.above_min + 1e-9 * std::max(1.0, std::abs(column.above_min));
  polygon = clip(polygon, column.axis, lower, 1.0);
  if (polygon.empty()) return false;
  polygon = clip(polygon, column.axis, column.above_max, -1.0);
  if (polygon.empty()) return false;
  const auto [first, second] = acrossBasis(column.axis);
  shadow.clear();
  for (const Eigen::Vector3d& p : polygon) shadow.emplace_back(first.dot(p), second.dot(p));
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < shadow.size(); ++i) {
    nearest = std::min(nearest, segmentDistance(shadow[i], shadow[(i + 1) % shadow.size()]));
  }
  if (nearest <= column.radius) return true;
  // The centre may be inside a shadow of non-zero area: same side of every edge.
  int positive = 0, negative = 0;
  for (std::size_t i = 0; i < shadow.size(); ++i) {
    const Eigen::Vector2d& a = shadow[i];
    const Eigen::Vector2d& b = shadow[(i + 1) % shadow.size()];
    const double cross = a.x() * b.y() - a.y() * b.x();  // (a - 0) x (b - 0)
    if (cross > 0) ++positive;
    if (cross < 0) ++negative;
  }
  return shadow.size() >= 3 && positive + negative > 0 && (positive == 0 || negative == 0);
}

template <typename Visit>
void ColumnIndex::forEachCandidate(const Column& column, Visit visit) {
  if (++epoch_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    epoch_ = 1;
  }
  // The tilted column lies within this horizontal radius and these heights (along up).
  const double cos_tilt = std::clamp(column.axis.dot(up_), -1.0, 1.0);
  const double sin_tilt = std::sqrt(std::max(0.0, 1.0 - cos_tilt * cos_tilt));
  const double reach = std::max(std::abs(column.above_min), std::abs(column.above_max));
  const double radius = column.radius + reach * sin_tilt;
  const double lo = std::min(column.above_min * cos_tilt, column.above_max * cos_tilt) - column.radius * sin_tilt;
  const double hi = std::max(column.above_min * cos_tilt, column.above_max * cos_tilt) + column.radius * sin_tilt;
  const Eigen::Vector3d& centre = column.centre;
  const double height = up_.dot(centre);
  const double x = east_.dot(centre), y = north_.dot(centre);
  const long i0 = std::lround(std::floor((x - radius) / cell_)), i1 = std::lround(std::floor((x + radius) / cell_));
  const long j0 = std::lround(std::floor((y - radius) / cell_)), j1 = std::lround(std::floor((y + radius) / cell_));
  for (long i = i0; i <= i1; ++i) {
    for (long j = j0; j <= j1; ++j) {
      const auto bucket = buckets_.find(key(i, j));
      if (bucket == buckets_.end()) continue;
      for (const std::uint32_t f : bucket->second) {
        if (stamp_[f] == epoch_) continue;
        stamp_[f] = epoch_;
        if (max_height_[f] - height < lo || min_height_[f] - height > hi) continue;
        if (!visit(f)) return;
      }
    }
  }
}

bool ColumnIndex::anyInColumn(const Column& column) {
  bool found = false;
  std::vector<Eigen::Vector2d> shadow;
  forEachCandidate(column, [&](std::uint32_t f) {
    found = faceInColumn(f, column, shadow);
    return !found;
  });
  return found;
}

void ColumnIndex::collectInColumn(const Column& column, std::vector<std::vector<Eigen::Vector2d>>& shadows) {
  std::vector<Eigen::Vector2d> shadow;
  forEachCandidate(column, [&](std::uint32_t f) {
    if (faceInColumn(f, column, shadow)) shadows.push_back(shadow);
    return true;
  });
}

}  // namespace terramesh::evaluation
