#include <algorithm>
#include <cmath>

#include "evaluation/mesh_evaluation.h"

namespace terramesh::evaluation {

Eigen::Vector3d PinholeCamera::rayDirection_C(double u, double v) const {
  return Eigen::Vector3d((u - cx_px) / fx_px, (v - cy_px) / fy_px, 1.0).normalized();
}

bool PinholeCamera::sees(const Eigen::Vector3d& p_C) const {
  if (!(p_C.z() > 0)) return false;
  const double u = fx_px * p_C.x() / p_C.z() + cx_px;
  const double v = fy_px * p_C.y() / p_C.z() + cy_px;
  return u >= 0 && u < width_px && v >= 0 && v < height_px;
}

std::vector<DepthRay> renderTruthRays(const datasets::TriangleBvh& truth, const std::vector<EvaluationView>& views,
                                      const PinholeCamera& camera, const DepthComparisonConfig& config) {
  std::vector<DepthRay> rays;
  const int stride = std::max(1, config.stride_px);
  for (const EvaluationView& view : views) {
    const Eigen::Matrix3d rotation = view.rotation_W_C.normalized().toRotationMatrix();
    for (int v = stride / 2; v < camera.height_px; v += stride) {
      for (int u = stride / 2; u < camera.width_px; u += stride) {
        const Eigen::Vector3d direction = rotation * camera.rayDirection_C(u + 0.5, v + 0.5);
        const auto hit = truth.firstHit(view.centre_W, direction, config.max_depth_m);
        if (hit) rays.push_back({view.centre_W, direction, hit->distance});
      }
    }
  }
  return rays;
}

std::vector<DepthRay> raysToPoints(const Eigen::Vector3d& origin_W, const std::vector<Eigen::Vector3d>& points_W,
                                   const DepthComparisonConfig& config) {
  std::vector<DepthRay> rays;
  rays.reserve(points_W.size());
  for (const Eigen::Vector3d& p : points_W) {
    const Eigen::Vector3d offset = p - origin_W;
    const double depth = offset.norm();
    if (depth > 0 && depth <= config.max_depth_m) rays.push_back({origin_W, offset / depth, depth});
  }
  return rays;
}

DepthErrors compareDepths(const datasets::TriangleBvh& reconstruction, const mesher::TriangleMesh& mesh,
                          const std::vector<DepthRay>& truth, const DepthComparisonConfig& config) {
  DepthErrors errors;
  errors.truth_rays = truth.size();
  std::vector<double> absolute;
  absolute.reserve(truth.size());
  double sum_squares = 0.0;
  double sum_signed = 0.0;
  const bool flags = mesh.is_steiner.size() == mesh.vertices.size();
  for (const DepthRay& ray : truth) {
    const auto hit = reconstruction.firstHit(ray.origin_W, ray.direction_W, ray.truth_depth_m + config.max_overshoot_m);
    if (!hit) continue;
    const double error = hit->distance - ray.truth_depth_m;
    ++errors.compared;
    absolute.push_back(std::abs(error));
    sum_squares += error * error;
    sum_signed += error;
    errors.covered += std::abs(error) <= config.coverage_threshold_m;
    if (flags) {
      const auto& face = mesh.faces[hit->face];
      errors.steiner_hits += mesh.is_steiner[face[0]] || mesh.is_steiner[face[1]] || mesh.is_steiner[face[2]];
    }
  }
  if (!absolute.empty()) {
    const double n = static_cast<double>(absolute.size());
    double sum = 0.0;
    for (double a : absolute) sum += a;
    errors.mean_abs_m = sum / n;
    errors.rmse_m = std::sqrt(sum_squares / n);
    errors.mean_signed_m = sum_signed / n;
    std::nth_element(absolute.begin(), absolute.begin() + static_cast<long>(absolute.size() / 2), absolute.end());
    errors.median_abs_m = absolute[absolute.size() / 2];
  }
  return errors;
}

}  // namespace terramesh::evaluation
