#include "evaluation/ground_truth_traversability.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "column_index.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/mesh_refinement.h"

namespace terramesh::evaluation {

using datasets::SurfaceLabel;

std::string_view toString(TruthReason reason) {
  switch (reason) {
    case TruthReason::kTraversable: return "traversable";
    case TruthReason::kNotGround: return "not_ground";
    case TruthReason::kTooSteep: return "too_steep";
    case TruthReason::kCurbTooHigh: return "curb_too_high";
    case TruthReason::kLowClearance: return "low_clearance";
    case TruthReason::kStepInFootprint: return "step_in_footprint";
  }
  return "?";
}

bool isGroundLabel(SurfaceLabel label) {
  switch (label) {
    case SurfaceLabel::kRoad:
    case SurfaceLabel::kSidewalk:
    case SurfaceLabel::kCurb:
    case SurfaceLabel::kVegetation:
    case SurfaceLabel::kRamp: return true;
    case SurfaceLabel::kWall:
    case SurfaceLabel::kObstacle:
    case SurfaceLabel::kCeiling: return false;
  }
  return false;
}

void GroundTruthConfig::validate() const {
  std::ostringstream problems;
  if (!(max_edge_m >= 0) || !std::isfinite(max_edge_m)) problems << "max_edge_m: " << max_edge_m << " (expected >= 0)";
  if (!(index_cell_m > 0) || !std::isfinite(index_cell_m)) {
    problems << (problems.tellp() > 0 ? "; " : "") << "index_cell_m: " << index_cell_m << " (expected > 0)";
  }
  if (problems.tellp() > 0) throw std::invalid_argument("GroundTruthConfig: " + problems.str());
}

std::array<double, kTruthReasonCount> GroundTruthTraversability::areaByReason() const {
  std::array<double, kTruthReasonCount> areas{};
  for (std::size_t f = 0; f < reasons.size(); ++f) areas[static_cast<std::size_t>(reasons[f])] += faceArea(mesh.mesh, f);
  return areas;
}

Eigen::Vector3d estimateUpFromSlopes(const datasets::LabeledMesh& truth, double level_deg) {
  truth.validate();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t f = 0; f < truth.mesh.faces.size(); ++f) {
    if (!(truth.slope_deg[f] <= level_deg)) continue;
    const auto& face = truth.mesh.faces[f];
    const Eigen::Vector3d& a = truth.mesh.vertices[face[0]];
    sum += 0.5 * (truth.mesh.vertices[face[1]] - a).cross(truth.mesh.vertices[face[2]] - a);  // area * normal
  }
  if (!(sum.norm() > 0)) {
    throw std::invalid_argument("estimateUpFromSlopes: no face of the ground truth has a slope <= " +
                                std::to_string(level_deg) + " deg");
  }
  return sum.normalized();
}

namespace {

using Shadow = std::vector<Eigen::Vector2d>;

/// Whether the convex polygon `shadow` (possibly a segment or a point) meets the rectangle
/// centred at the origin with half extents a along `u` and b along `v` (separating axes).
bool meetsRectangle(const Shadow& shadow, const Eigen::Vector2d& u, const Eigen::Vector2d& v, double a, double b) {
  auto separated = [&](const Eigen::Vector2d& axis, double half) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Eigen::Vector2d& p : shadow) {
      lo = std::min(lo, p.dot(axis));
      hi = std::max(hi, p.dot(axis));
    }
    return hi < -half || lo > half;
  };
  if (separated(u, a) || separated(v, b)) return false;
  for (std::size_t i = 0; i < shadow.size(); ++i) {
    const Eigen::Vector2d edge = shadow[(i + 1) % shadow.size()] - shadow[i];
    if (!(edge.squaredNorm() > 0)) continue;
    const Eigen::Vector2d normal(-edge.y(), edge.x());
    if (separated(normal, a * std::abs(normal.dot(u)) + b * std::abs(normal.dot(v)))) return false;
  }
  return true;
}

/// Whether the robot's footprint, centred at the origin, avoids every shadow at some heading.
/// The shadows were collected within the footprint's circumradius, so a disc avoids none.
bool footprintFits(const std::vector<Shadow>& shadows, const RobotLimits& robot) {
  if (shadows.empty()) return true;
  if (!robot.isRectangle()) return false;
  for (int k = 0; k < robot.headings; ++k) {
    const double theta = M_PI * k / robot.headings;
    const Eigen::Vector2d u(std::cos(theta), std::sin(theta)), v(-std::sin(theta), std::cos(theta));
    bool blocked = false;
    for (const Shadow& shadow : shadows) {
      if (meetsRectangle(shadow, u, v, 0.5 * robot.footprint_length_m, 0.5 * robot.footprint_width_m)) {
        blocked = true;
        break;
      }
    }
    if (!blocked) return true;
  }
  return false;
}

/// The truth with the faces a robot might drive on (ground labels, slope within the limit) split
/// to `max_edge`, the others kept whole (they are not traversable whatever their size).
datasets::LabeledMesh refineCandidates(const datasets::LabeledMesh& truth, const RobotLimits& robot,
                                       double max_edge) {
  datasets::LabeledMesh candidates, others;
  for (std::size_t f = 0; f < truth.mesh.faces.size(); ++f) {
    const bool candidate = isGroundLabel(truth.labels[f]) && truth.slope_deg[f] <= robot.max_slope_deg;
    datasets::LabeledMesh& part = candidate ? candidates : others;
    const auto base = static_cast<std::uint32_t>(part.mesh.vertices.size());
    for (const std::uint32_t v : truth.mesh.faces[f]) part.mesh.vertices.push_back(truth.mesh.vertices.at(v));
    part.mesh.faces.push_back({base, base + 1, base + 2});
    part.labels.push_back(truth.labels[f]);
    part.slope_deg.push_back(truth.slope_deg[f]);
  }
  datasets::LabeledMesh out = refineLabeledMesh(candidates, max_edge);
  const auto offset = static_cast<std::uint32_t>(out.mesh.vertices.size());
  out.mesh.vertices.insert(out.mesh.vertices.end(), others.mesh.vertices.begin(), others.mesh.vertices.end());
  for (auto face : others.mesh.faces) {
    for (std::uint32_t& v : face) v += offset;
    out.mesh.faces.push_back(face);
  }
  out.labels.insert(out.labels.end(), others.labels.begin(), others.labels.end());
  out.slope_deg.insert(out.slope_deg.end(), others.slope_deg.begin(), others.slope_deg.end());
  return out;
}

}  // namespace

GroundTruthTraversability labelTraversability(const datasets::LabeledMesh& truth, const RobotLimits& robot,
                                              const Eigen::Vector3d& up_W, const GroundTruthConfig& config) {
  robot.validate();
  config.validate();
  if (!(up_W.norm() > 0) || !up_W.allFinite()) throw std::invalid_argument("labelTraversability: up_W must be non-zero");
  truth.validate();
  GroundTruthTraversability out;
  out.mesh = refineCandidates(truth, robot, config.max_edge_m);
  out.up_W = up_W.normalized();
  out.robot = robot;
  const mesher::TriangleMesh& mesh = out.mesh.mesh;
  const std::size_t count = mesh.faces.size();
  out.traversable.assign(count, 0);
  out.reasons.assign(count, TruthReason::kNotGround);
  if (count == 0) return out;

  const datasets::TriangleBvh bvh(mesh);
  ColumnIndex columns(mesh, out.up_W, config.index_cell_m);
  const double r = robot.footprint_radius_m;
  const double step = robot.max_step_m;
  const double height = robot.height_m;
  // Start the clearance ray just off the face so that the face itself is not hit.
  const double lift = 1e-6;
  std::vector<Shadow> shadows;
  for (std::size_t f = 0; f < count; ++f) {
    const SurfaceLabel label = out.mesh.labels[f];
    TruthReason& reason = out.reasons[f];
    if (!isGroundLabel(label)) {
      reason = TruthReason::kNotGround;
      continue;
    }
    if (!(out.mesh.slope_deg[f] <= robot.max_slope_deg)) {
      reason = TruthReason::kTooSteep;
      continue;
    }
    const Eigen::Vector3d centre = faceCentroid(mesh, f);
    // Heights and the footprint are measured in the plane of the face: the robot stands on it.
    const auto& corners = mesh.faces[f];
    Eigen::Vector3d normal = (mesh.vertices[corners[1]] - mesh.vertices[corners[0]])
                                 .cross(mesh.vertices[corners[2]] - mesh.vertices[corners[0]]);
    normal = normal.norm() > 0 ? normal.normalized() : out.up_W;
    if (normal.dot(out.up_W) < 0) normal = -normal;
    const ColumnIndex::Column rises{centre, normal, r, step, height};
    const ColumnIndex::Column drops{centre, normal, r, -height - 1e-9, -step - 1e-9};
    const auto hit = bvh.firstHit(centre + lift * out.up_W, out.up_W, height - lift);
    if (hit && hit->distance + lift < height) {
      reason = TruthReason::kLowClearance;
      continue;
    }
    if (robot.isRectangle()) {
      // Within half the width of the centre the rectangle is blocked at every heading.
      const double inscribed = 0.5 * std::min(robot.footprint_length_m, robot.footprint_width_m);
      shadows.clear();
      bool blocked = columns.anyInColumn({centre, normal, inscribed, step, height});
      if (!blocked) {
        columns.collectInColumn(rises, shadows);
        blocked = !footprintFits(shadows, robot);
      }
      if (blocked) {
        reason = TruthReason::kStepInFootprint;
        continue;
      }
      if (label == SurfaceLabel::kCurb) {
        columns.collectInColumn(drops, shadows);
        if (!footprintFits(shadows, robot)) {
          reason = TruthReason::kCurbTooHigh;
          continue;
        }
      }
    } else {
      if (columns.anyInColumn(rises)) {
        reason = TruthReason::kStepInFootprint;
        continue;
      }
      // The curb's height jump down off it (up onto it is the step above).
      if (label == SurfaceLabel::kCurb && columns.anyInColumn(drops)) {
        reason = TruthReason::kCurbTooHigh;
        continue;
      }
    }
    reason = TruthReason::kTraversable;
    out.traversable[f] = 1;
  }
  return out;
}

}  // namespace terramesh::evaluation
