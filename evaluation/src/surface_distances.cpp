#include <algorithm>
#include <random>

#include "evaluation/mesh_evaluation.h"

namespace terramesh::evaluation {
namespace {

DistanceStats summarise(std::vector<double> distances, std::size_t samples) {
  DistanceStats stats;
  stats.samples = samples;
  stats.matched = distances.size();
  if (distances.empty()) return stats;
  std::sort(distances.begin(), distances.end());
  double sum = 0.0;
  for (double d : distances) sum += d;
  stats.mean_m = sum / static_cast<double>(distances.size());
  stats.median_m = distances[distances.size() / 2];
  stats.p90_m = distances[std::min(distances.size() - 1, distances.size() * 9 / 10)];
  for (std::size_t t = 0; t < DistanceStats::kThresholdsM.size(); ++t) {
    const auto within = std::upper_bound(distances.begin(), distances.end(), DistanceStats::kThresholdsM[t]) -
                        distances.begin();
    stats.within[t] = static_cast<double>(within) / static_cast<double>(samples);
  }
  return stats;
}

}  // namespace

std::vector<Eigen::Vector3d> sampleSurface(const mesher::TriangleMesh& mesh, std::size_t count,
                                           std::uint64_t seed, bool skip_steiner) {
  const bool flags = skip_steiner && mesh.is_steiner.size() == mesh.vertices.size();
  std::vector<double> cumulative;
  std::vector<std::uint32_t> faces;
  double total = 0.0;
  for (std::uint32_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    if (flags && (mesh.is_steiner[face[0]] || mesh.is_steiner[face[1]] || mesh.is_steiner[face[2]])) continue;
    const Eigen::Vector3d& a = mesh.vertices[face[0]];
    total += 0.5 * (mesh.vertices[face[1]] - a).cross(mesh.vertices[face[2]] - a).norm();
    cumulative.push_back(total);
    faces.push_back(f);
  }
  std::vector<Eigen::Vector3d> samples;
  if (faces.empty() || !(total > 0)) return samples;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  samples.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const auto it = std::lower_bound(cumulative.begin(), cumulative.end(), unit(rng) * total);
    const auto& face = mesh.faces[faces[static_cast<std::size_t>(std::min<long>(it - cumulative.begin(), static_cast<long>(faces.size()) - 1))]];
    double r1 = unit(rng), r2 = unit(rng);
    if (r1 + r2 > 1.0) {
      r1 = 1.0 - r1;
      r2 = 1.0 - r2;
    }
    const Eigen::Vector3d& a = mesh.vertices[face[0]];
    samples.push_back(a + r1 * (mesh.vertices[face[1]] - a) + r2 * (mesh.vertices[face[2]] - a));
  }
  return samples;
}

DistanceStats distancesToSurface(const std::vector<Eigen::Vector3d>& samples, const datasets::TriangleBvh& surface) {
  std::vector<double> distances;
  distances.reserve(samples.size());
  for (const Eigen::Vector3d& p : samples) distances.push_back(surface.closestPoint(p).distance);
  return summarise(std::move(distances), samples.size());
}

DistanceStats distancesToPoints(const std::vector<Eigen::Vector3d>& samples, const datasets::PointCloudIndex& cloud,
                                double max_distance_m) {
  std::vector<double> distances;
  distances.reserve(samples.size());
  for (const Eigen::Vector3d& p : samples) {
    if (const auto nearest = cloud.nearest(p, max_distance_m)) distances.push_back(nearest->distance);
  }
  return summarise(std::move(distances), samples.size());
}

}  // namespace terramesh::evaluation
