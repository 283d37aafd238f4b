#include "evaluation/road_under_path.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

#include "common/grid_key.h"
#include "common/plan_frame.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/mesh_refinement.h"

namespace terramesh::evaluation {
namespace {

double ratio(double num, double den) { return den > 0 ? num / den : std::numeric_limits<double>::quiet_NaN(); }

/// Adds `weight` to the total of every reason bit set in `reasons`.
void addReasons(std::uint16_t reasons, double weight, std::array<double, traversability::reason::kCount>& totals) {
  for (std::size_t b = 0; b < totals.size(); ++b) {
    if ((reasons >> b) & 1u) totals[b] += weight;
  }
}

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

/// Whether something at horizontal distance `distance_m` from the path lies in its strip of half
/// width `lateral_m`: strictly inside, by more than rounding. Surface standing on the strip's very
/// edge (a wall, or a slope rising outwards from it) covers none of the strip's ground, and where
/// the edge falls on a column or a piece's centroid it would otherwise count as if it did.
bool inStrip(double distance_m, double lateral_m) {
  constexpr double kEdgeM = 1e-9;
  return distance_m < lateral_m - kEdgeM;
}

/// The nearest point of a polyline (metres), horizontally: its horizontal distance and the point.
struct PathFoot {
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  std::size_t segment = 0;
  double t = 0;
};

PathFoot nearestOnPath(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& up, const Eigen::Vector3d& p) {
  auto horizontal = [&](const Eigen::Vector3d& v) { return Eigen::Vector3d(v - up.dot(v) * up); };
  PathFoot foot;
  foot.point = path.front();
  const Eigen::Vector3d c = horizontal(p);
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector3d a = horizontal(path[i]), b = horizontal(path[i + 1]);
    const Eigen::Vector3d ab = b - a;
    const double length_sq = ab.squaredNorm();
    const double t = length_sq > 0 ? std::clamp((c - a).dot(ab) / length_sq, 0.0, 1.0) : 0.0;
    const double distance = (a + t * ab - c).norm();
    if (distance < foot.distance) {
      foot = {distance, path[i] + t * (path[i + 1] - path[i]), i, t};
    }
  }
  return foot;
}

/// Whether face f's normal (out of the matter) lies within 60 degrees of down: a ceiling or a
/// deck's underside, not a road; walls and overhangs are not.
bool facesDown(const mesher::TriangleMesh& mesh, std::size_t f, const Eigen::Vector3d& up) {
  const auto& face = mesh.faces[f];
  const Eigen::Vector3d normal =
      (mesh.vertices[face[1]] - mesh.vertices[face[0]]).cross(mesh.vertices[face[2]] - mesh.vertices[face[0]]);
  const double norm = normal.norm();
  return norm > 0 && up.dot(normal) / norm < -0.5;
}

/// The inputs common to both checks, validated, in metres.
struct MetricPath {
  Eigen::Vector3d up;
  std::vector<Eigen::Vector3d> path;
  double length_m = 0;
};

MetricPath metricPath(const traversability::LayeredMesh& map, const std::vector<Eigen::Vector3d>& path_W,
                      const Eigen::Vector3d& up_W, const RoadUnderPathConfig& config, const char* who) {
  config.validate();
  const std::string name(who);
  if (path_W.size() < 2) throw std::invalid_argument(name + ": the path needs at least 2 points");
  if (!(up_W.norm() > 0) || !up_W.allFinite()) throw std::invalid_argument(name + ": up_W must be non-zero");
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument(name + ": the map has not one layer record per face");
  }
  if (!(map.metres_per_unit > 0)) throw std::invalid_argument(name + ": metres_per_unit must be > 0");
  MetricPath out;
  out.up = up_W.normalized();
  for (const Eigen::Vector3d& p : path_W) out.path.push_back(p * map.metres_per_unit);
  for (std::size_t i = 0; i + 1 < out.path.size(); ++i) out.length_m += (out.path[i + 1] - out.path[i]).norm();
  return out;
}

/// Whether the truth rules the robot out at truth face `face`: ground where its footprint does not
/// fit (a piece nearest a non-ground face stays in: the robot drove there).
bool truthRulesOut(const GroundTruthTraversability& truth, std::uint32_t face) {
  return !truth.traversable[face] && truth.reasons[face] != TruthReason::kNotGround;
}

/// The highest face of `bvh` that does not face down on the vertical down from `top` (metres),
/// within `depth` of it.
std::optional<datasets::RayHit> highestFacingUp(const datasets::TriangleBvh& bvh, const mesher::TriangleMesh& mesh,
                                                const Eigen::Vector3d& up, Eigen::Vector3d top, double depth) {
  constexpr int kMaxSkipped = 16;
  constexpr double kStepM = 1e-6;
  for (int skipped = 0; skipped <= kMaxSkipped && depth > 0; ++skipped) {
    const std::optional<datasets::RayHit> hit = bvh.firstHit(top, -up, depth);
    if (!hit || !facesDown(mesh, hit->face, up)) return hit;
    top = hit->point - kStepM * up;
    depth -= hit->distance + kStepM;
  }
  return std::nullopt;
}

/// Fills `out`'s underfoot figures: the strip judged column by column (RoadUnderPath::underfoot).
void judgeColumns(const traversability::LayeredMesh& map, const mesher::TriangleMesh& metric, const MetricPath& path,
                  const RoadUnderPathConfig& config, const GroundTruthTraversability* truth_labels,
                  const datasets::TriangleBvh* truth, RoadUnderPath& out) {
  const Eigen::Vector3d& up = path.up;
  const geometry::PlanFrame frame = geometry::planFrame(up, geometry::acrossFrameRule());
  const Eigen::Vector3d& e1 = frame.e1;
  const Eigen::Vector3d& e2 = frame.e2;
  const double s = config.column_spacing_m;
  const double cell_m2 = s * s;
  const std::unique_ptr<datasets::TriangleBvh> bvh =
      metric.faces.empty() ? nullptr : std::make_unique<datasets::TriangleBvh>(metric);
  std::unordered_set<std::uint64_t> seen;
  ClassAreas fits;
  double fits_none_m2 = 0;
  for (std::size_t i = 0; i + 1 < path.path.size(); ++i) {
    const Eigen::Vector2d a(e1.dot(path.path[i]), e2.dot(path.path[i]));
    const Eigen::Vector2d b(e1.dot(path.path[i + 1]), e2.dot(path.path[i + 1]));
    const Eigen::Vector2d lo = (a.cwiseMin(b).array() - config.lateral_m) / s - 1;
    const Eigen::Vector2d hi = (a.cwiseMax(b).array() + config.lateral_m) / s;
    const auto u0 = static_cast<std::int64_t>(std::floor(lo.x())), u1 = static_cast<std::int64_t>(std::ceil(hi.x()));
    const auto v0 = static_cast<std::int64_t>(std::floor(lo.y())), v1 = static_cast<std::int64_t>(std::ceil(hi.y()));
    for (std::int64_t u = u0; u <= u1; ++u) {
      for (std::int64_t v = v0; v <= v1; ++v) {
        if (!seen.insert(geometry::packCell2(u, v)).second) continue;
        // Node centres sit half a cell off the grid lines, so axis-aligned edges split no node.
        const Eigen::Vector3d ground =
            (static_cast<double>(u) + 0.5) * s * e1 + (static_cast<double>(v) + 0.5) * s * e2;
        const PathFoot foot = nearestOnPath(path.path, up, ground);
        if (!inStrip(foot.distance, config.lateral_m)) continue;
        const double road_height = up.dot(foot.point) - config.camera_height_m;
        const std::optional<datasets::RayHit> hit =
            bvh ? highestFacingUp(*bvh, metric, up, ground + (road_height + config.height_tolerance_m) * up,
                                  2 * config.height_tolerance_m)
                : std::nullopt;
        const bool in = !truth || !hit || !truthRulesOut(*truth_labels, truth->closestPoint(hit->point).face);
        if (!hit) {
          out.underfoot_none_m2 += cell_m2;
          if (in) fits_none_m2 += cell_m2;
          continue;
        }
        out.underfoot.add(map.layers[hit->face].face_class, cell_m2);
        if (in) fits.add(map.layers[hit->face].face_class, cell_m2);
      }
    }
  }
  const double total = out.underfoot.total() + out.underfoot_none_m2;
  out.underfoot_free_fraction = ratio(out.underfoot.free_m2, total);
  out.underfoot_lethal_fraction = ratio(out.underfoot.lethal_m2, total);
  out.underfoot_unknown_fraction = ratio(out.underfoot.unknown_m2, total);
  out.underfoot_uncertain_fraction = ratio(out.underfoot.uncertain_m2, total);
  out.underfoot_none_fraction = ratio(out.underfoot_none_m2, total);
  if (truth) out.underfoot_free_where_truth_fits_fraction = ratio(fits.free_m2, fits.total() + fits_none_m2);
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
  require(column_spacing_m > 0 && std::isfinite(column_spacing_m), "column_spacing_m", column_spacing_m, "> 0");
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
                            const GroundTruthTraversability* truth_labels) {
  const MetricPath metric_path = metricPath(map, path_W, up_W, config, "roadUnderPath");
  const Eigen::Vector3d& up = metric_path.up;
  const double scale = map.metres_per_unit;
  const std::vector<Eigen::Vector3d>& path = metric_path.path;
  RoadUnderPath out;
  out.path_length_m = metric_path.length_m;

  mesher::TriangleMesh metric = map.mesh;
  for (Eigen::Vector3d& v : metric.vertices) v *= scale;
  const RefinedMesh pieces = refineMesh(metric, config.sample_edge_m);
  if (truth_labels && (truth_labels->traversable.size() != truth_labels->mesh.mesh.faces.size() ||
                       truth_labels->reasons.size() != truth_labels->mesh.mesh.faces.size())) {
    throw std::invalid_argument("roadUnderPath: the truth has not one answer per face");
  }
  const std::unique_ptr<datasets::TriangleBvh> truth =
      truth_labels && !truth_labels->mesh.mesh.faces.empty()
          ? std::make_unique<datasets::TriangleBvh>(truth_labels->mesh.mesh)
          : nullptr;
  std::vector<std::pair<double, double>> free_distances;
  std::array<double, traversability::reason::kCount> reason_m2{};
  for (std::size_t p = 0; p < pieces.mesh.faces.size(); ++p) {
    const Eigen::Vector3d centroid = faceCentroid(pieces.mesh, p);
    const PathFoot foot = nearestOnPath(path, up, centroid);
    const double best = foot.distance;
    const Eigen::Vector3d& best_point = foot.point;
    if (!inStrip(best, config.lateral_m)) continue;
    const double below = up.dot(best_point - centroid);
    if (std::abs(below - config.camera_height_m) > config.height_tolerance_m) continue;
    const double area = faceArea(pieces.mesh, p);
    if (facesDown(metric, pieces.parent_face[p], up)) {
      out.facing_down_m2 += area;
      continue;
    }
    addReasons(map.layers[pieces.parent_face[p]].reasons, area, reason_m2);
    const traversability::FaceClass face_class = map.layers[pieces.parent_face[p]].face_class;
    out.areas.add(face_class, area);
    if (!truth) continue;
    const datasets::SurfacePoint nearest = truth->closestPoint(centroid);
    if (face_class == traversability::FaceClass::kFree) free_distances.emplace_back(nearest.distance, area);
    if (!truthRulesOut(*truth_labels, nearest.face)) out.where_truth_fits.add(face_class, area);
  }
  judgeColumns(map, metric, metric_path, config, truth_labels, truth.get(), out);
  if (truth) {
    out.truth_fits_fraction = ratio(out.where_truth_fits.total(), out.areas.total());
    out.free_where_truth_fits_fraction = ratio(out.where_truth_fits.free_m2, out.where_truth_fits.total());
  }
  out.free_fraction = ratio(out.areas.free_m2, out.areas.total());
  out.lethal_fraction = ratio(out.areas.lethal_m2, out.areas.total());
  out.unknown_fraction = ratio(out.areas.unknown_m2, out.areas.total());
  out.uncertain_fraction = ratio(out.areas.uncertain_m2, out.areas.total());
  for (std::size_t b = 0; b < reason_m2.size(); ++b) out.reason_fraction[b] = ratio(reason_m2[b], out.areas.total());
  out.free_truth_distance_median_m = weightedQuantile(free_distances, 0.5);
  out.free_truth_distance_p90_m = weightedQuantile(free_distances, 0.9);
  return out;
}

GroundUnderPath groundUnderPath(const traversability::LayeredMesh& map, const std::vector<Eigen::Vector3d>& path_W,
                                const Eigen::Vector3d& up_W, const RoadUnderPathConfig& config,
                                const std::vector<Eigen::Vector3d>& ground_W) {
  const MetricPath metric_path = metricPath(map, path_W, up_W, config, "groundUnderPath");
  const Eigen::Vector3d& up = metric_path.up;
  const std::vector<Eigen::Vector3d>& path = metric_path.path;
  mesher::TriangleMesh metric = map.mesh;
  for (Eigen::Vector3d& v : metric.vertices) v *= map.metres_per_unit;
  const std::unique_ptr<datasets::TriangleBvh> bvh =
      metric.faces.empty() ? nullptr : std::make_unique<datasets::TriangleBvh>(metric);
  GroundUnderPath out;
  std::vector<std::pair<double, double>> free_heights, heights;
  std::array<double, traversability::reason::kCount> reason_points{};
  // Which 0.5 m stretches of the path have ground beside them.
  constexpr double kStretchM = 0.5;
  std::vector<std::vector<char>> covered(path.size());
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    covered[i].assign(static_cast<std::size_t>(std::ceil((path[i + 1] - path[i]).norm() / kStretchM)) + 1, 0);
  }
  for (const Eigen::Vector3d& g_W : ground_W) {
    if (!g_W.allFinite()) throw std::invalid_argument("groundUnderPath: a ground point is not finite");
    const Eigen::Vector3d g = g_W * map.metres_per_unit;
    const PathFoot foot = nearestOnPath(path, up, g);
    if (!inStrip(foot.distance, config.lateral_m)) continue;
    if (std::abs(up.dot(foot.point - g) - config.camera_height_m) > config.height_tolerance_m) continue;
    ++out.points;
    std::vector<char>& stretches = covered[foot.segment];
    if (!stretches.empty()) stretches[static_cast<std::size_t>(foot.t * static_cast<double>(stretches.size() - 1))] = 1;
    std::optional<datasets::RayHit> hit;
    if (bvh) {
      const auto above = bvh->firstHit(g, up, config.height_tolerance_m);
      const auto below = bvh->firstHit(g, -up, config.height_tolerance_m);
      hit = above && (!below || above->distance <= below->distance) ? above : below;
    }
    if (!hit) {
      ++out.missing;
      continue;
    }
    heights.emplace_back(hit->distance, 1.0);
    addReasons(map.layers[hit->face].reasons, 1.0, reason_points);
    switch (map.layers[hit->face].face_class) {
      case traversability::FaceClass::kFree:
        ++out.free;
        free_heights.emplace_back(hit->distance, 1.0);
        break;
      case traversability::FaceClass::kLethal: ++out.lethal; break;
      case traversability::FaceClass::kUnknown: ++out.unknown; break;
      case traversability::FaceClass::kUncertain: ++out.uncertain; break;
    }
  }
  const double n = static_cast<double>(out.points);
  out.free_fraction = ratio(static_cast<double>(out.free), n);
  out.lethal_fraction = ratio(static_cast<double>(out.lethal), n);
  out.unknown_fraction = ratio(static_cast<double>(out.unknown), n);
  out.uncertain_fraction = ratio(static_cast<double>(out.uncertain), n);
  out.missing_fraction = ratio(static_cast<double>(out.missing), n);
  for (std::size_t b = 0; b < reason_points.size(); ++b) out.reason_fraction[b] = ratio(reason_points[b], n);
  out.free_height_median_m = weightedQuantile(free_heights, 0.5);
  out.free_height_p90_m = weightedQuantile(free_heights, 0.9);
  out.height_median_m = weightedQuantile(heights, 0.5);
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double length = (path[i + 1] - path[i]).norm();
    if (covered[i].empty()) continue;
    std::size_t hits = 0;
    for (char c : covered[i]) hits += c ? 1 : 0;
    out.covered_path_m += length * static_cast<double>(hits) / static_cast<double>(covered[i].size());
  }
  return out;
}

}  // namespace terramesh::evaluation
