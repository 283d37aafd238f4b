#include "centre_line.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace terramesh::datasets::synthetic {
namespace {

/// Points every `spacing` of arc length along a polyline (the last point may be closer).
std::vector<Eigen::Vector3d> resample(const std::vector<Eigen::Vector3d>& polyline, double spacing) {
  std::vector<Eigen::Vector3d> result = {polyline.front()};
  double carried = 0.0;  // arc length since the last emitted point
  for (std::size_t i = 1; i < polyline.size(); ++i) {
    const Eigen::Vector3d a = polyline[i - 1], b = polyline[i];
    const double length = (b - a).norm();
    double along = spacing - carried;
    while (along <= length) {
      result.push_back(a + (b - a) * (along / length));
      along += spacing;
    }
    carried = length - (along - spacing);
  }
  if (carried > 0.25 * spacing) result.push_back(polyline.back());
  return result;
}

std::vector<Eigen::Vector3d> movingAverage(const std::vector<Eigen::Vector3d>& points, int half_window) {
  if (half_window <= 0) return points;
  const int n = static_cast<int>(points.size());
  std::vector<Eigen::Vector3d> result(points.size());
  for (int i = 0; i < n; ++i) {
    const int half = std::min({half_window, i, n - 1 - i});  // symmetric, so the ends stay put
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = i - half; k <= i + half; ++k) sum += points[static_cast<std::size_t>(k)];
    result[static_cast<std::size_t>(i)] = sum / (2 * half + 1);
  }
  return result;
}

Eigen::Vector3d horizontal(const Eigen::Vector3d& v, const Eigen::Vector3d& up) { return v - v.dot(up) * up; }

}  // namespace

CentreLine::CentreLine(const std::vector<Eigen::Vector3d>& polyline_W, const Eigen::Vector3d& up_W,
                       double spacing_m, double smoothing_m)
    : up_(up_W.normalized()), spacing_(spacing_m) {
  if (polyline_W.size() < 2) throw std::invalid_argument("CentreLine: fewer than two points");
  std::vector<Eigen::Vector3d> points = resample(polyline_W, spacing_m);
  if (points.size() < 3) throw std::invalid_argument("CentreLine: path shorter than two spacings");
  points = movingAverage(points, static_cast<int>(std::lround(smoothing_m / (2 * spacing_m))));
  const std::size_t n = points.size();
  stations_.resize(n);
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) s += (points[i] - points[i - 1]).norm();
    PathStation& station = stations_[i];
    station.s_m = s;
    station.centre_W = points[i];
    const Eigen::Vector3d along = points[std::min(i + 1, n - 1)] - points[i > 0 ? i - 1 : 0];
    Eigen::Vector3d heading = horizontal(along, up_);
    if (heading.norm() < 1e-9) heading = i > 0 ? stations_[i - 1].heading_W : Eigen::Vector3d(horizontal(Eigen::Vector3d::UnitX(), up_));
    station.heading_W = heading.normalized();
    station.left_W = up_.cross(station.heading_W).normalized();
  }
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Eigen::Vector3d& h0 = stations_[i - 1].heading_W;
    const Eigen::Vector3d& h1 = stations_[i + 1].heading_W;
    const double angle = std::atan2(up_.dot(h0.cross(h1)), h0.dot(h1));
    stations_[i].curvature_per_m = angle / std::max(stations_[i + 1].s_m - stations_[i - 1].s_m, 1e-9);
  }
}

PathStation CentreLine::at(double s_m) const {
  const double s = std::clamp(s_m, 0.0, length());
  const auto next = std::lower_bound(stations_.begin(), stations_.end(), s,
                                     [](const PathStation& station, double value) { return station.s_m < value; });
  if (next == stations_.begin()) return stations_.front();
  const PathStation& b = *next;
  const PathStation& a = *(next - 1);
  const double t = (s - a.s_m) / std::max(b.s_m - a.s_m, 1e-12);
  PathStation result;
  result.s_m = s;
  result.centre_W = a.centre_W + t * (b.centre_W - a.centre_W);
  result.heading_W = (a.heading_W + t * (b.heading_W - a.heading_W)).normalized();
  result.left_W = up_.cross(result.heading_W).normalized();
  result.curvature_per_m = a.curvature_per_m + t * (b.curvature_per_m - a.curvature_per_m);
  return result;
}

std::vector<Eigen::Vector3d> proceduralCentreline(double length_m, double min_turn_radius_m,
                                                  double max_grade, Rng& rng) {
  constexpr double kStep = 0.5;
  const double max_curvature = 1.0 / min_turn_radius_m;
  const double phase[4] = {rng.uniform(0, 2 * M_PI), rng.uniform(0, 2 * M_PI), rng.uniform(0, 2 * M_PI),
                           rng.uniform(0, 2 * M_PI)};
  std::vector<Eigen::Vector3d> points = {Eigen::Vector3d::Zero()};
  double heading = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (double s = 0.0; s < length_m; s += kStep) {
    const double curvature = max_curvature * (0.6 * std::sin(2 * M_PI * s / 420.0 + phase[0]) +
                                              0.4 * std::sin(2 * M_PI * s / 170.0 + phase[1]));
    const double grade = max_grade * (0.6 * std::sin(2 * M_PI * s / 310.0 + phase[2]) +
                                      0.4 * std::sin(2 * M_PI * s / 130.0 + phase[3]));
    heading += curvature * kStep;
    p += kStep * Eigen::Vector3d(std::cos(heading), std::sin(heading), grade) / std::sqrt(1 + grade * grade);
    points.push_back(p);
  }
  return points;
}

Eigen::Matrix3d cameraRotation(const Eigen::Vector3d& forward_W, const Eigen::Vector3d& up_W) {
  const Eigen::Vector3d z = forward_W.normalized();
  const Eigen::Vector3d x = z.cross(up_W).normalized();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return R;
}

PoseList camerasAlong(const CentreLine& line, double frame_spacing_m,
                      const std::function<Eigen::Vector3d(double)>& camera_position) {
  PoseList poses;
  constexpr double kLookAhead = 1.0;
  for (double s = 0.0; s <= line.length(); s += frame_spacing_m) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = camera_position(s);
    const Eigen::Vector3d forward = camera_position(std::min(s + kLookAhead, line.length())) -
                                    camera_position(std::max(s - kLookAhead, 0.0));
    pose.linear() = cameraRotation(forward, line.up());
    poses.push_back(pose);
  }
  return poses;
}

PlanarPointGrid::PlanarPointGrid(const Eigen::Vector3d& up_W, double cell_m)
    : plane_(geometry::planFrame(up_W.normalized())), cell_m_(cell_m) {}

void PlanarPointGrid::insert(const Eigen::Vector3d& point_W, std::size_t id) {
  const Eigen::Vector2d p = planar(point_W);
  const auto i = static_cast<std::int64_t>(std::floor(p.x() / cell_m_));
  const auto j = static_cast<std::int64_t>(std::floor(p.y() / cell_m_));
  cells_[key(i, j)].emplace_back(p, id);
}

void PlanarPointGrid::forEachWithin(const Eigen::Vector3d& point_W, double radius_m,
                                    const std::function<void(std::size_t)>& visit) const {
  const Eigen::Vector2d p = planar(point_W);
  const auto i0 = static_cast<std::int64_t>(std::floor((p.x() - radius_m) / cell_m_));
  const auto i1 = static_cast<std::int64_t>(std::floor((p.x() + radius_m) / cell_m_));
  const auto j0 = static_cast<std::int64_t>(std::floor((p.y() - radius_m) / cell_m_));
  const auto j1 = static_cast<std::int64_t>(std::floor((p.y() + radius_m) / cell_m_));
  const double radius2 = radius_m * radius_m;
  for (std::int64_t i = i0; i <= i1; ++i) {
    for (std::int64_t j = j0; j <= j1; ++j) {
      const auto cell = cells_.find(key(i, j));
      if (cell == cells_.end()) continue;
      for (const auto& [q, id] : cell->second) {
        if ((q - p).squaredNorm() < radius2) visit(id);
      }
    }
  }
}

}  // namespace terramesh::datasets::synthetic
