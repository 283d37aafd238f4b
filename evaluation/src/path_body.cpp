#include "path_body.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace terramesh::evaluation::internal {
namespace {

using Polygon = std::vector<Eigen::Vector3d>;

/// The part of a convex polygon (box coordinates) where sign * coordinate[axis] <= limit
/// (Sutherland-Hodgman against one plane).
Polygon clip(const Polygon& polygon, int axis, double sign, double limit) {
  Polygon out;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = polygon[i];
    const Eigen::Vector3d& q = polygon[(i + 1) % n];
    const double dp = sign * p[axis] - limit;
    const double dq = sign * q[axis] - limit;
    if (dp <= 0) out.push_back(p);
    if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
  return out;
}

/// The path point `s` along it (path units), given the cumulative lengths `along`.
Eigen::Vector3d pointAt(const std::vector<Eigen::Vector3d>& path, const std::vector<double>& along, double s) {
  if (s <= 0) return path.front();
  if (s >= along.back()) return path.back();
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(along.begin(), along.end(), s) - along.begin());
  const double span = along[i] - along[i - 1];
  const double t = span > 0 ? (s - along[i - 1]) / span : 0.0;
  return path[i - 1] + t * (path[i] - path[i - 1]);
}

}  // namespace

Eigen::Vector3d BodyBox::centre() const { return base + 0.5 * (bottom + top) * up; }

double BodyBox::circumradius() const {
  return std::sqrt(half_length * half_length + half_width * half_width + 0.25 * (top - bottom) * (top - bottom));
}

Eigen::Vector3d BodyBox::local(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d d = point - base;
  return {d.dot(ahead), d.dot(up.cross(ahead)), d.dot(up)};
}

std::optional<Eigen::Vector3d> triangleInBox(const BodyBox& box, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                             const Eigen::Vector3d& c) {
  Polygon polygon{box.local(a), box.local(b), box.local(c)};
  const double limits[3][2] = {{-box.half_length, box.half_length},
                               {-box.half_width, box.half_width},
                               {box.bottom, box.top}};
  for (int axis = 0; axis < 3 && !polygon.empty(); ++axis) {
    polygon = clip(polygon, axis, 1.0, limits[axis][1]);
    polygon = clip(polygon, axis, -1.0, -limits[axis][0]);
  }
  if (polygon.empty()) return std::nullopt;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : polygon) mean += p;
  mean /= static_cast<double>(polygon.size());
  // Strictly inside on every axis: a triangle lying in a face of the box, or touching it along an
  // edge or at a corner, does not enter the body.
  for (int axis = 0; axis < 3; ++axis) {
    if (!(mean[axis] > limits[axis][0] && mean[axis] < limits[axis][1])) return std::nullopt;
  }
  const Eigen::Vector3d beside = box.up.cross(box.ahead);
  return box.base + mean.x() * box.ahead + mean.y() * beside + mean.z() * box.up;
}

std::vector<Eigen::Vector3d> travelHeadings(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& up,
                                            double half_reach) {
  if (path.empty()) return {};
  std::vector<double> along(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i) along[i] = along[i - 1] + (path[i] - path[i - 1]).norm();
  std::vector<Eigen::Vector3d> headings(path.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Eigen::Vector3d chord = pointAt(path, along, along[i] + half_reach) - pointAt(path, along, along[i] - half_reach);
    const Eigen::Vector3d flat = chord - chord.dot(up) * up;
    if (flat.norm() > 1e-12 * std::max(1.0, chord.norm())) headings[i] = flat.normalized();
  }
  // Chords without a horizontal length take the heading before them (or after, at the start).
  for (std::size_t i = 1; i < headings.size(); ++i) {
    if (headings[i].isZero()) headings[i] = headings[i - 1];
  }
  for (std::size_t i = headings.size() - 1; i > 0; --i) {
    if (headings[i - 1].isZero()) headings[i - 1] = headings[i];
  }
  if (headings.front().isZero()) return {};
  return headings;
}

Eigen::Vector3d turned(const Eigen::Vector3d& heading, const Eigen::Vector3d& up, double angle_rad) {
  return std::cos(angle_rad) * heading + std::sin(angle_rad) * up.cross(heading);
}

double turnAngle(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const Eigen::Vector3d& up) {
  return std::atan2(up.cross(from).dot(to), from.dot(to));
}

}  // namespace terramesh::evaluation::internal
