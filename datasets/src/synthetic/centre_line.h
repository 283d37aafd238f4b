#pragma once
// The centre line of a road or track, resampled at a fixed arc-length step, with a horizontal
// frame per station; and what is built on it: procedural centre lines, camera trajectories,
// and a planar grid for "which stations are near this point" queries.

#include <Eigen/Geometry>
#include <functional>
#include <unordered_map>
#include <vector>

#include "common/grid_key.h"
#include "common/plan_frame.h"
#include "datasets/kitti_trajectory.h"
#include "rng.h"

namespace terramesh::datasets::synthetic {

struct PathStation {
  /// Arc length from the start.
  double s_m = 0.0;
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  /// Horizontal unit direction of travel.
  Eigen::Vector3d heading_W = Eigen::Vector3d::UnitX();
  /// Horizontal unit vector to the left: up x heading.
  Eigen::Vector3d left_W = Eigen::Vector3d::UnitY();
  /// Signed horizontal curvature, positive when turning left.
  double curvature_per_m = 0.0;
};

class CentreLine {
 public:
  /// Resamples `polyline_W` every `spacing_m` of arc length and smooths the positions with a
  /// moving average `smoothing_m` long (0: none).
  /// @throw std::invalid_argument if the polyline is shorter than two spacings.
  CentreLine(const std::vector<Eigen::Vector3d>& polyline_W, const Eigen::Vector3d& up_W,
             double spacing_m, double smoothing_m);

  const std::vector<PathStation>& stations() const { return stations_; }
  const Eigen::Vector3d& up() const { return up_; }
  double length() const { return stations_.back().s_m; }
  double spacing() const { return spacing_; }
  /// The station at arc length `s_m` (clamped to the line), interpolated linearly.
  PathStation at(double s_m) const;

 private:
  Eigen::Vector3d up_;
  double spacing_;
  std::vector<PathStation> stations_;
};

/// A gently curving, z-up centre line from the origin along +x, sampled every 0.5 m: curvature
/// and grade are sums of two sines of random phase, bounded by 1 / min_turn_radius_m and
/// max_grade (a fraction, 0.04 = 4 %).
std::vector<Eigen::Vector3d> proceduralCentreline(double length_m, double min_turn_radius_m,
                                                  double max_grade, Rng& rng);

/// Camera-to-world rotation of a camera (x right, y down, z forward) looking along `forward_W`
/// with no roll with respect to `up_W`.
Eigen::Matrix3d cameraRotation(const Eigen::Vector3d& forward_W, const Eigen::Vector3d& up_W);

/// Camera poses every `frame_spacing_m` of `line`, at `camera_position(s)`, looking along the
/// direction of travel of that position (so the camera pitches with grades).
PoseList camerasAlong(const CentreLine& line, double frame_spacing_m,
                      const std::function<Eigen::Vector3d(double)>& camera_position);

/// Points indexed by their horizontal coordinates (orthogonal to `up_W`) in square cells.
class PlanarPointGrid {
 public:
  PlanarPointGrid(const Eigen::Vector3d& up_W, double cell_m);

  void insert(const Eigen::Vector3d& point_W, std::size_t id);
  /// Calls `visit(id)` for every point whose horizontal distance to `point_W` is < `radius_m`.
  void forEachWithin(const Eigen::Vector3d& point_W, double radius_m,
                     const std::function<void(std::size_t)>& visit) const;

 private:
  Eigen::Vector2d planar(const Eigen::Vector3d& p) const { return plane_.project(p); }
  static std::uint64_t key(std::int64_t i, std::int64_t j) { return geometry::packCell2(i, j); }

  geometry::PlanFrame plane_;
  double cell_m_;
  std::unordered_map<std::uint64_t, std::vector<std::pair<Eigen::Vector2d, std::size_t>>> cells_;
};

}  // namespace terramesh::datasets::synthetic
