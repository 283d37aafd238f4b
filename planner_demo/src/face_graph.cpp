#include "planning/face_graph.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "common/closest_point.h"
#include "common/plan_frame.h"

namespace terramesh::planning {

void WalkabilityConfig::validate() const {
  std::ostringstream problems;
  if (!(min_lethal_distance_m >= 0) || !std::isfinite(min_lethal_distance_m)) {
    problems << " min_lethal_distance_m: " << min_lethal_distance_m << " (expected >= 0);";
  }
  if (!(cost_weight >= 0) || !std::isfinite(cost_weight)) {
    problems << " cost_weight: " << cost_weight << " (expected >= 0);";
  }
  if (!(max_face_tilt_deg > 0 && max_face_tilt_deg <= 90)) {
    problems << " max_face_tilt_deg: " << max_face_tilt_deg << " (expected in (0, 90]);";
  }
  if (!(unknown_cost >= 0 && unknown_cost <= 1)) problems << " unknown_cost: " << unknown_cost << " (expected in [0, 1]);";
  if (heading_count < 0 || heading_count > 32) problems << " heading_count: " << heading_count << " (expected in [0, 32]);";
  if (!(turn_cost_m_per_rad >= 0) || !std::isfinite(turn_cost_m_per_rad)) {
    problems << " turn_cost_m_per_rad: " << turn_cost_m_per_rad << " (expected >= 0);";
  }
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("WalkabilityConfig:" + text);
}

const char* toString(WalkStop stop) {
  switch (stop) {
    case WalkStop::kReached: return "reached";
    case WalkStop::kBlocked: return "blocked";
    case WalkStop::kBoundary: return "boundary";
    case WalkStop::kStuck: return "stuck";
    case WalkStop::kTooLong: return "too_long";
  }
  return "?";
}

FaceGraph::FaceGraph(const traversability::LayeredMesh& map, const WalkabilityConfig& config)
    : config_(config), vertices_(map.mesh.vertices), faces_(map.mesh.faces), layers_(map.layers) {
  config_.validate();
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("FaceGraph: " + std::to_string(map.layers.size()) + " layer records for " +
                                std::to_string(map.mesh.faces.size()) + " faces");
  }
  if (!(map.metres_per_unit > 0) || !std::isfinite(map.metres_per_unit)) {
    throw std::invalid_argument("FaceGraph: metres_per_unit must be > 0");
  }
  const double up_norm = map.up_W.norm();
  if (!(up_norm > 0) || !map.up_W.allFinite()) throw std::invalid_argument("FaceGraph: up_W must be a non-zero vector");
  up_W_ = map.up_W / up_norm;
  const geometry::PlanFrame frame = geometry::planFrame(up_W_);
  heading_e1_ = frame.e1;
  heading_e2_ = frame.e2;
  metres_per_unit_ = map.metres_per_unit;
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    for (std::uint32_t v : faces_[f]) {
      if (v >= vertices_.size()) {
        throw std::invalid_argument("FaceGraph: face " + std::to_string(f) + " indexes missing vertex " +
                                    std::to_string(v));
      }
    }
  }
  computeWalkability(map);
  computeNeighbours();
  computeComponents();
}

WalkabilityConfig walkabilityFor(const traversability::RobotProfile& profile) {
  WalkabilityConfig config;
  config.min_lethal_distance_m = profile.inscribed_radius_m;
  if (profile.footprint == traversability::FootprintShape::kRectangle) {
    config.heading_count = profile.contact_headings;
    config.omni = profile.motion_model == traversability::MotionModel::kOmni;
  }
  return config;
}

bool FaceGraph::judgedHeadingFits(std::uint32_t f, int k) const {
  const std::uint32_t fits = layers_[f].heading_fits;
  const int n = config_.heading_count;
  if (n == 0 || fits == 0) return true;
  return (fits >> (((k % n) + n) % n) & 1u) != 0;
}

Eigen::Vector3d FaceGraph::judgedHeading(int k) const {
  const double angle = config_.heading_count > 0 ? M_PI * k / config_.heading_count : 0.0;
  return std::cos(angle) * heading_e1_ + std::sin(angle) * heading_e2_;
}

bool FaceGraph::headingFits(std::uint32_t f, const Eigen::Vector3d& direction_W) const {
  return turnFits(f, direction_W, 0.0);
}

bool FaceGraph::turnFits(std::uint32_t f, const Eigen::Vector3d& from_W, double turn_rad) const {
  const int n = config_.heading_count;
  if (n == 0 || layers_[f].heading_fits == 0) return true;
  const double x = from_W.dot(heading_e1_), y = from_W.dot(heading_e2_);
  if (x == 0 && y == 0) return true;  // no horizontal heading
  // Positions among the judged headings (k at k x 180 / n deg): the start and the end of the turn.
  const double a = std::atan2(y, x) / M_PI * n;
  const double b = a + turn_rad / M_PI * n;
  const double lo = std::min(a, b), hi = std::max(a, b);
  // Every judged heading from the one at or below lo to the one at or above hi; a position on a
  // judged heading (within rounding) needs only that one.
  const double tolerance = 1e-9 * n;
  const auto first = static_cast<long>(std::floor(lo + tolerance));
  const auto last = std::max(first, static_cast<long>(std::ceil(hi - tolerance)));
  for (long k = first; k <= last && k - first < n; ++k) {
    if (!judgedHeadingFits(f, static_cast<int>(((k % n) + n) % n))) return false;
  }
  return true;
}

double FaceGraph::plannedCost(std::uint32_t f) const {
  if (!walkable_[f]) return std::numeric_limits<double>::quiet_NaN();
  if (layers_[f].face_class == traversability::FaceClass::kUnknown) return config_.unknown_cost;
  return std::clamp(static_cast<double>(layers_[f].cost), 0.0, 1.0);
}

Eigen::Vector3d FaceGraph::centroid(std::uint32_t f) const {
  const auto& t = faces_[f];
  return (vertices_[t[0]] + vertices_[t[1]] + vertices_[t[2]]) / 3.0;
}

void FaceGraph::computeWalkability(const traversability::LayeredMesh& map) {
  const std::size_t n = faces_.size();
  normals_.resize(n);
  areas_.resize(n);
  walkable_.assign(n, 0);
  multipliers_.assign(n, 1.0);
  const double min_up = std::cos(config_.max_face_tilt_deg * M_PI / 180.0);
  for (std::size_t f = 0; f < n; ++f) {
    const auto& t = faces_[f];
    const Eigen::Vector3d cross = (vertices_[t[1]] - vertices_[t[0]]).cross(vertices_[t[2]] - vertices_[t[0]]);
    const double norm = cross.norm();
    areas_[f] = 0.5 * norm;
    normals_[f] = norm > 0 ? Eigen::Vector3d(cross / norm) : Eigen::Vector3d::Zero();
    const traversability::FaceLayers& layer = map.layers[f];
    const bool free = layer.face_class == traversability::FaceClass::kFree && std::isfinite(layer.cost);
    const bool unknown = config_.allow_unknown && layer.face_class == traversability::FaceClass::kUnknown;
    const bool uncertain = config_.allow_uncertain && layer.face_class == traversability::FaceClass::kUncertain &&
                           std::isfinite(layer.cost);
    const bool far_from_lethal = !(layer.lethal_distance_m < config_.min_lethal_distance_m);
    const bool facing_up = normals_[f].dot(up_W_) >= min_up;
    if ((free || unknown || uncertain) && far_from_lethal && facing_up && norm > 0) {
      walkable_[f] = 1;
      const double cost = free || uncertain ? std::clamp(static_cast<double>(layer.cost), 0.0, 1.0) : config_.unknown_cost;
      multipliers_[f] = 1.0 + config_.cost_weight * cost;
      walkable_faces_.push_back(static_cast<std::uint32_t>(f));
    }
  }
}

void FaceGraph::computeNeighbours() {
  // Undirected edge -> the faces using it; an edge with exactly two faces joins them.
  std::unordered_map<std::uint64_t, std::array<std::uint32_t, 3>> edge_faces;
  edge_faces.reserve(faces_.size() * 2);
  auto key = [](std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | b;
  };
  for (std::uint32_t f = 0; f < faces_.size(); ++f) {
    for (int e = 0; e < 3; ++e) {
      const auto& t = faces_[f];
      auto& slot = edge_faces.try_emplace(key(t[static_cast<std::size_t>(e)], t[static_cast<std::size_t>((e + 1) % 3)]),
                                          std::array<std::uint32_t, 3>{kNoFace, kNoFace, 0})
                       .first->second;
      if (slot[2] < 2) slot[slot[2]] = f;
      ++slot[2];
    }
  }
  neighbours_.assign(faces_.size(), {kNoFace, kNoFace, kNoFace});
  face_edges_.assign(faces_.size(), {kNoFace, kNoFace, kNoFace});
  std::unordered_map<std::uint64_t, std::uint32_t> edge_ids;
  edge_ids.reserve(edge_faces.size());
  for (std::uint32_t f = 0; f < faces_.size(); ++f) {
    for (int e = 0; e < 3; ++e) {
      const auto& t = faces_[f];
      const std::uint32_t a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
      const auto [it, added] = edge_ids.try_emplace(key(a, b), static_cast<std::uint32_t>(edge_vertices_.size()));
      const auto& slot = edge_faces.at(key(a, b));
      if (added) {
        edge_vertices_.push_back({std::min(a, b), std::max(a, b)});
        edge_faces_.push_back({f, slot[2] == 2 ? (slot[0] == f ? slot[1] : slot[0]) : kNoFace});
      }
      face_edges_[f][static_cast<std::size_t>(e)] = it->second;
      if (slot[2] != 2) continue;
      neighbours_[f][static_cast<std::size_t>(e)] = slot[0] == f ? slot[1] : slot[0];
    }
  }
}

void FaceGraph::computeComponents() {
  components_.assign(faces_.size(), kNoFace);
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed : walkable_faces_) {
    if (components_[seed] != kNoFace) continue;
    const auto id = static_cast<std::uint32_t>(component_areas_.size());
    double area = 0;
    components_[seed] = id;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      area += areas_[f];
      for (std::uint32_t g : neighbours_[f]) {
        if (g == kNoFace || !walkable_[g] || components_[g] != kNoFace) continue;
        components_[g] = id;
        stack.push_back(g);
      }
    }
    component_areas_.push_back(area);
  }
}

std::optional<SurfaceLocation> FaceGraph::snap(const Eigen::Vector3d& query_W, double radius_m) const {
  if (!query_W.allFinite()) throw std::invalid_argument("FaceGraph::snap: query is not finite");
  const double radius = radius_m / metres_per_unit_;
  double best = radius * radius;
  std::optional<SurfaceLocation> result;
  for (std::uint32_t f : walkable_faces_) {
    const auto& t = faces_[f];
    // Walkable faces have a non-zero normal: Ericson's regions without the zero-area test.
    const Eigen::Vector3d p = geometry::closestPointOnTriangle(
        query_W, vertices_[t[0]], vertices_[t[1]], vertices_[t[2]], geometry::DegenerateTriangles::kUnchecked);
    const double d2 = (p - query_W).squaredNorm();
    if (d2 < best || (!result && d2 <= best)) {
      best = d2;
      result = SurfaceLocation{f, p};
    }
  }
  return result;
}

}  // namespace terramesh::planning
