#include "evaluation/road_under_path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "datasets/triangle_bvh.h"
#include "evaluation/mesh_refinement.h"

namespace terramesh::evaluation {
namespace {

double ratio(double num, double den) { return den > 0 ? num / den : std::numeric_limits<double>::quiet_NaN(); }

/// The value below which `share` of the total weight lies ((value, weight) pairs; NaN if empty).
double weightedQuantile(std::vector<std::pair<double, double>> values, double share) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  double total = 0;
  for (const auto& v : values) total += v.second;
  double sum = 0;
  for (const auto& v : values) {
    sum += v.second;
    if (sum >= share * total) return v.first;
  }
  return values.back().first;
}

}  // namespace

void RoadUnderPathConfig::validate() const {
  std::ostringstream problems;
  auto require = [&](bool ok, const char* field, double value, const char* expected) {
    if (ok) return;
    problems << (problems.tellp() > 0 ? "; " : "") << field << ": " << value << " (expected " << expected << ")";
  };
  require(lateral_m > 0 && std::isfinite(lateral_m), "lateral_m", lateral_m, "> 0");
  require(camera_height_m >= 0 && std::isfinite(camera_height_m), "camera_height_m", camera_height_m, ">= 0");
  require(height_tolerance_m > 0 && std::isfinite(height_tolerance_m), "height_tolerance_m", height_tolerance_m,
          "> 0");
  require(sample_edge_m >= 0 && std::isfinite(sample_edge_m), "sample_edge_m", sample_edge_m, ">= 0");
  if (problems.tellp() > 0) throw std::invalid_argument("RoadUnderPathConfig: " + problems.str());
}

Eigen::Vector3d upFromCameraRotations(const std::vector<Eigen::Quaterniond>& rotations_W_C) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Quaterniond& q : rotations_W_C) sum -= q.normalized().toRotationMatrix().col(1);
  if (!(sum.norm() > 1e-9)) throw std::invalid_argument("upFromCameraRotations: no rotations, or they cancel out");
  return sum.normalized();
}

RoadUnderPath roadUnderPath(const traversability::LayeredMesh& map, const std::vector<Eigen::Vector3d>& path_W,
                            const Eigen::Vector3d& up_W, const RoadUnderPathConfig& config,
                            const mesher::TriangleMesh* truth_m) {
  config.validate();
  if (path_W.size() < 2) throw std::invalid_argument("roadUnderPath: the path needs at least 2 points");
  if (!(up_W.norm() > 0) || !up_W.allFinite()) throw std::invalid_argument("roadUnderPath: up_W must be non-zero");
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("roadUnderPath: the map has not one layer record per face");
  }
  if (!(map.metres_per_unit > 0)) throw std::invalid_argument("roadUnderPath: metres_per_unit must be > 0");
  const Eigen::Vector3d up = up_W.normalized();
  const double scale = map.metres_per_unit;
  // Work in metres.
  std::vector<Eigen::Vector3d> path;
  for (const Eigen::Vector3d& p : path_W) path.push_back(p * scale);
  RoadUnderPath out;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) out.path_length_m += (path[i + 1] - path[i]).norm();

  mesher::TriangleMesh metric = map.mesh;
  for (Eigen::Vector3d& v : metric.vertices) v *= scale;
  const RefinedMesh pieces = refineMesh(metric, config.sample_edge_m);
  const std::unique_ptr<datasets::TriangleBvh> truth =
      truth_m && !truth_m->faces.empty() ? std::make_unique<datasets::TriangleBvh>(*truth_m) : nullptr;
  std::vector<std::pair<double, double>> free_distances;
  auto horizontal = [&](const Eigen::Vector3d& v) { return Eigen::Vector3d(v - up.dot(v) * up); };
  for (std::size_t p = 0; p < pieces.mesh.faces.size(); ++p) {
    const Eigen::Vector3d centroid = faceCentroid(pieces.mesh, p);
    // The nearest point of the path, horizontally (brute force: paths are short).
    double best = std::numeric_limits<double>::infinity();
    Eigen::Vector3d best_point = path.front();
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const Eigen::Vector3d a = horizontal(path[i]), b = horizontal(path[i + 1]);
      const Eigen::Vector3d c = horizontal(centroid);
      const Eigen::Vector3d ab = b - a;
      const double length_sq = ab.squaredNorm();
      const double t = length_sq > 0 ? std::clamp((c - a).dot(ab) / length_sq, 0.0, 1.0) : 0.0;
      const double distance = (a + t * ab - c).norm();
      if (distance < best) {
        best = distance;
        best_point = path[i] + t * (path[i + 1] - path[i]);
      }
    }
    if (best > config.lateral_m) continue;
    const double below = up.dot(best_point - centroid);
    if (std::abs(below - config.camera_height_m) > config.height_tolerance_m) continue;
    const double area = faceArea(pieces.mesh, p);
    switch (map.layers[pieces.parent_face[p]].face_class) {
      case traversability::FaceClass::kFree:
        out.areas.free_m2 += area;
        if (truth) free_distances.emplace_back(truth->closestPoint(centroid).distance, area);
        break;
      case traversability::FaceClass::kLethal: out.areas.lethal_m2 += area; break;
      case traversability::FaceClass::kUnknown: out.areas.unknown_m2 += area; break;
      case traversability::FaceClass::kUncertain: out.areas.uncertain_m2 += area; break;
    }
  }
  out.free_fraction = ratio(out.areas.free_m2, out.areas.total());
  out.lethal_fraction = ratio(out.areas.lethal_m2, out.areas.total());
  out.unknown_fraction = ratio(out.areas.unknown_m2, out.areas.total());
  out.uncertain_fraction = ratio(out.areas.uncertain_m2, out.areas.total());
  out.free_truth_distance_median_m = weightedQuantile(free_distances, 0.5);
  out.free_truth_distance_p90_m = weightedQuantile(free_distances, 0.9);
  return out;
}

}  // namespace terramesh::evaluation
