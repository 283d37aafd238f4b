#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "datasets/point_cloud_index.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/geometry_truth.h"

namespace terramesh::evaluation {

void GeometryTruthConfig::validate() const {
  std::ostringstream problems;
  if (samples < 1) problems << " samples: 0 (expected >= 1);";
  if (!(match_radius_m > 0) || !std::isfinite(match_radius_m)) {
    problems << " match_radius_m: " << match_radius_m << " (expected > 0);";
  }
  if (depth.stride_px < 1) problems << " depth.stride_px: " << depth.stride_px << " (expected >= 1);";
  if (!(depth.max_depth_m > 0)) problems << " depth.max_depth_m: " << depth.max_depth_m << " (expected > 0);";
  if (!(depth.coverage_threshold_m > 0)) {
    problems << " depth.coverage_threshold_m: " << depth.coverage_threshold_m << " (expected > 0);";
  }
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("GeometryTruthConfig:" + text);
}

struct GeometryTruth::Impl {
  GeometryTruthConfig config;
  PinholeCamera camera;
  std::vector<DepthRay> rays;
  /// Completeness points: the truth ray ends, thinned to about config.samples.
  std::vector<Eigen::Vector3d> truth_points;
  // Mesh truth.
  std::optional<datasets::TriangleBvh> truth_bvh;
  // LiDAR truth.
  std::optional<LidarTruth> lidar;
  std::optional<datasets::PointCloudIndex> lidar_cloud;

  void finishRays() {
    if (rays.empty()) {
      throw std::invalid_argument("GeometryTruth: no ground-truth ray within " + std::to_string(config.depth.max_depth_m) +
                                  " m of a view");
    }
    const std::size_t step = std::max<std::size_t>(1, (rays.size() + config.samples - 1) / config.samples);
    for (std::size_t i = 0; i < rays.size(); i += step) {
      truth_points.push_back(rays[i].origin_W + rays[i].truth_depth_m * rays[i].direction_W);
    }
  }
};

GeometryTruth::GeometryTruth(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GeometryTruth::~GeometryTruth() = default;
GeometryTruth::GeometryTruth(GeometryTruth&&) noexcept = default;
GeometryTruth& GeometryTruth::operator=(GeometryTruth&&) noexcept = default;

GeometryTruth GeometryTruth::fromMesh(const mesher::TriangleMesh& truth,
                                      const std::vector<EvaluationView>& views,
                                      const GeometryTruthConfig& config) {
  config.validate();
  auto impl = std::make_unique<Impl>();
  impl->config = config;
  impl->truth_bvh.emplace(truth);
  impl->rays = renderTruthRays(*impl->truth_bvh, views, impl->camera, config.depth);
  impl->finishRays();
  return GeometryTruth(std::move(impl));
}

GeometryTruth GeometryTruth::fromLidar(const std::filesystem::path& sequence, const LidarTruthOptions& options,
                                       const GeometryTruthConfig& config) {
  config.validate();
  auto impl = std::make_unique<Impl>();
  impl->config = config;
  impl->lidar.emplace(readLidarTruth(sequence, options, impl->camera, config.depth));
  impl->rays = impl->lidar->rays;
  impl->lidar_cloud.emplace(impl->lidar->returns_W);
  impl->finishRays();
  return GeometryTruth(std::move(impl));
}

std::size_t GeometryTruth::truthRays() const { return impl_->rays.size(); }

GeometryScores GeometryTruth::score(const mesher::TriangleMesh& mesh) const {
  const GeometryTruthConfig& config = impl_->config;
  GeometryScores scores;
  scores.faces = mesh.faces.size();
  if (mesh.faces.empty()) {
    scores.depth.truth_rays = impl_->rays.size();
    return scores;
  }
  const bool flagged = mesh.is_steiner.size() == mesh.vertices.size();
  const mesher::TriangleMesh measured = flagged ? mesher::dropSteinerFaces(mesh) : mesh;
  scores.measured_faces = measured.faces.size();
  const datasets::TriangleBvh mesh_bvh(mesh);
  scores.depth = compareDepths(mesh_bvh, mesh, impl_->rays, config.depth);
  if (measured.faces.empty()) return scores;
  const datasets::TriangleBvh measured_bvh(measured);
  const std::vector<Eigen::Vector3d> samples = sampleSurface(measured, config.samples, config.seed, false);
  if (impl_->lidar) {
    std::vector<Eigen::Vector3d> covered;
    for (const Eigen::Vector3d& p : samples) {
      if (impl_->lidar->covers(p, config.depth.max_depth_m, &impl_->camera)) covered.push_back(p);
    }
    scores.accuracy = distancesToPoints(covered, *impl_->lidar_cloud, config.match_radius_m);
  } else {
    scores.accuracy = distancesToSurface(samples, *impl_->truth_bvh);
  }
  scores.completeness = distancesToSurface(impl_->truth_points, measured_bvh);
  return scores;
}

}  // namespace terramesh::evaluation
