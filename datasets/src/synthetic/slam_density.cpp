#include "datasets/slam_density.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "problem_list.h"

namespace terramesh::datasets {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// Whether the simulated camera at `T_W_C` could create a feature at `point_W` on a face of unit
/// normal `normal_W` (the same tests as the simulation's ray casts, from the point's side).
bool seenFrom(const Eigen::Isometry3d& T_W_C, const Eigen::Vector3d& point_W, const Eigen::Vector3d& normal_W,
              const TriangleBvh& bvh, const SlamSimulationConfig& simulation, double cos_incidence) {
  const Eigen::Vector3d ray = point_W - T_W_C.translation();
  const double distance = ray.norm();
  if (distance < simulation.min_range_m || distance > simulation.max_range_m) return false;
  const Eigen::Vector3d p_C = T_W_C.linear().transpose() * ray;
  if (p_C.z() <= 0) return false;
  const double u = simulation.focal_length_px * p_C.x() / p_C.z() + simulation.image_width_px / 2.0;
  const double v = simulation.focal_length_px * p_C.y() / p_C.z() + simulation.image_height_px / 2.0;
  if (u < 0 || u >= simulation.image_width_px || v < 0 || v >= simulation.image_height_px) return false;
  if (std::abs(normal_W.dot(ray)) < cos_incidence * distance) return false;
  return !bvh.segmentOccluded(T_W_C.translation(), point_W, simulation.occlusion_tolerance_m);
}

/// Calls `visit(centroid, area)` for the n x n sub-triangles of (a, b, c), n from the longest edge.
template <class Visit>
void forEachPiece(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double spacing,
                  Visit&& visit) {
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
  const Eigen::Vector3d u = (b - a) / n, v = (c - a) / n;
  const double area = 0.5 * u.cross(v).norm();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; i + j < n; ++j) {
      const Eigen::Vector3d corner = a + i * u + j * v;
      visit(Eigen::Vector3d(corner + (u + v) / 3.0), area);                     // upright piece
      if (i + j + 1 < n) visit(Eigen::Vector3d(corner + 2.0 * (u + v) / 3.0), area);  // inverted piece
    }
  }
}

}  // namespace

void GroundDensityConfig::validate() const {
  synthetic::ProblemList problems("GroundDensityConfig");
  problems.require(sample_spacing_m > 0 && std::isfinite(sample_spacing_m), "sample_spacing_m must be > 0");
  problems.require(ground_slope_deg > 0 && ground_slope_deg < 90, "ground_slope_deg must be in (0, 90)");
  problems.throwIfAny();
}

GroundDensity measureGroundDensity(const SyntheticScene& scene, const TriangleBvh& bvh, const SimulatedSlam& slam,
                                   const SlamSimulationConfig& simulation, const GroundDensityConfig& config) {
  config.validate();
  simulation.validate();
  const LabeledMesh& truth = scene.ground_truth;
  truth.validate();
  if (bvh.faceCount() != truth.mesh.faces.size()) {
    throw std::invalid_argument("measureGroundDensity: the bvh was not built from the scene's ground truth");
  }
  GroundDensity out;
  const double cos_incidence = std::cos(simulation.max_incidence_deg * kDegToRad);
  std::vector<Eigen::Isometry3d> cameras;
  for (const SimulatedKeyframe& keyframe : slam.keyframes) cameras.push_back(keyframe.true_T_W_C);
  for (std::size_t f = 0; f < truth.mesh.faces.size(); ++f) {
    if (!(truth.slope_deg[f] < config.ground_slope_deg)) continue;
    const auto& face = truth.mesh.faces[f];
    const Eigen::Vector3d& a = truth.mesh.vertices[face[0]];
    const Eigen::Vector3d& b = truth.mesh.vertices[face[1]];
    const Eigen::Vector3d& c = truth.mesh.vertices[face[2]];
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    forEachPiece(a, b, c, config.sample_spacing_m, [&](const Eigen::Vector3d& centroid, double area) {
      out.ground_area_m2 += area;
      for (const Eigen::Isometry3d& T_W_C : cameras) {
        if (seenFrom(T_W_C, centroid, normal, bvh, simulation, cos_incidence)) {
          out.seen_area_m2 += area;
          break;
        }
      }
    });
  }
  std::vector<double> errors;
  for (const SimulatedPoint& point : slam.points) {
    if (point.outlier) continue;
    errors.push_back((point.final_estimate_W - point.true_position_W).norm());
    if (!(truth.slope_deg.at(point.face) < config.ground_slope_deg)) continue;
    ++out.ground_points;
    if (point.observations >= 2) ++out.ground_points_seen_twice;
  }
  if (out.seen_area_m2 > 0) {
    out.points_per_m2 = static_cast<double>(out.ground_points) / out.seen_area_m2;
    out.points_seen_twice_per_m2 = static_cast<double>(out.ground_points_seen_twice) / out.seen_area_m2;
  }
  if (!errors.empty()) {
    double sum_sq = 0;
    for (const double e : errors) sum_sq += e * e;
    out.rms_error_m = std::sqrt(sum_sq / static_cast<double>(errors.size()));
    const auto middle = errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2);
    std::nth_element(errors.begin(), middle, errors.end());
    out.median_error_m = *middle;
  }
  return out;
}

}  // namespace terramesh::datasets
