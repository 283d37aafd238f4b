#include "evaluation/truth_checker.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "path_body.h"
#include "traversability/robot_profile.h"

namespace terramesh::evaluation {
namespace {

bool drivable(datasets::SurfaceLabel label) {
  using datasets::SurfaceLabel;
  return label == SurfaceLabel::kRoad || label == SurfaceLabel::kSidewalk || label == SurfaceLabel::kCurb ||
         label == SurfaceLabel::kVegetation || label == SurfaceLabel::kRamp;
}

std::string at(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out.precision(4);
  out << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return out.str();
}

std::string metres(double value_m, int decimals = 2) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(decimals);
  out << value_m << " m";
  return out.str();
}

std::string label(const datasets::LabeledMesh& truth, std::uint32_t face) {
  return std::string(datasets::toString(truth.labels[face]));
}

/// The indices of the true faces a robot must not touch, after checking the truth's labels.
std::vector<std::uint32_t> nonDrivableFaces(const datasets::LabeledMesh& truth) {
  truth.validate();
  std::vector<std::uint32_t> faces;
  for (std::uint32_t f = 0; f < truth.mesh.faces.size(); ++f) {
    if (!drivable(truth.labels[f])) faces.push_back(f);
  }
  return faces;
}

/// The faces `faces` of `mesh`, over all of its vertices.
mesher::TriangleMesh subMesh(const mesher::TriangleMesh& mesh, const std::vector<std::uint32_t>& faces) {
  mesher::TriangleMesh sub;
  sub.vertices = mesh.vertices;
  sub.faces.reserve(faces.size());
  for (const std::uint32_t f : faces) sub.faces.push_back(mesh.faces[f]);
  return sub;
}

/// The true surface nearest to `p` along the vertical, within `range` (map units) above or
/// below; `offset` is its height above p (negative: below p).
struct Ground {
  datasets::RayHit hit;
  double offset = 0.0;
};

std::optional<Ground> groundNear(const datasets::TriangleBvh& bvh, const Eigen::Vector3d& p, const Eigen::Vector3d& up,
                                 double range) {
  const auto below = bvh.firstHit(p, -up, range);
  const auto above = bvh.firstHit(p, up, range);
  if (below && (!above || below->distance <= above->distance)) return Ground{*below, -below->distance};
  if (above) return Ground{*above, above->distance};
  return std::nullopt;
}

TruthCheck fail(TruthCheck check, std::string reason) {
  check.valid = false;
  check.reason = std::move(reason);
  return check;
}

}  // namespace

TruthCheckConfig truthCheckConfigFrom(const traversability::RobotProfile& profile) {
  TruthCheckConfig config;
  config.footprint_radius_m = profile.footprintCircumradiusM();
  if (profile.footprint == traversability::FootprintShape::kRectangle) {
    config.footprint_length_m = profile.footprint_length_m;
    config.footprint_width_m = profile.footprint_width_m;
  }
  config.max_step_m = profile.max_step_m;
  config.min_clearance_m = profile.min_clearance_m;
  config.max_slope_deg = profile.max_slope_deg;
  config.own_heading = config.rectangle() && profile.motion_model == traversability::MotionModel::kOmni;
  return config;
}

void TruthCheckConfig::validate() const {
  std::ostringstream problems;
  auto positive = [&](const char* name, double value) {
    if (!(value > 0.0) || !std::isfinite(value)) problems << name << ": " << value << " (expected > 0); ";
  };
  auto nonNegative = [&](const char* name, double value) {
    if (!(value >= 0.0) || !std::isfinite(value)) problems << name << ": " << value << " (expected >= 0); ";
  };
  positive("footprint_radius_m", footprint_radius_m);
  nonNegative("footprint_length_m", footprint_length_m);
  nonNegative("footprint_width_m", footprint_width_m);
  if ((footprint_length_m > 0.0) != (footprint_width_m > 0.0)) {
    problems << "footprint_length_m, footprint_width_m: " << footprint_length_m << ", " << footprint_width_m
             << " (expected both > 0, a rectangle, or both 0, a disc); ";
  }
  nonNegative("max_step_m", max_step_m);
  positive("min_clearance_m", min_clearance_m);
  if (std::isfinite(max_step_m) && std::isfinite(min_clearance_m) && min_clearance_m < max_step_m) {
    problems << "min_clearance_m: " << min_clearance_m << " (expected >= max_step_m " << max_step_m << "); ";
  }
  if (!(max_slope_deg > 0.0 && max_slope_deg <= 90.0)) {
    problems << "max_slope_deg: " << max_slope_deg << " (expected (0, 90]); ";
  }
  positive("vertical_tolerance_m", vertical_tolerance_m);
  positive("spacing_m", spacing_m);
  nonNegative("crossing_lift_m", crossing_lift_m);
  positive("body_slice_m", body_slice_m);
  if (!(ground_search_m >= vertical_tolerance_m) || !std::isfinite(ground_search_m)) {
    problems << "ground_search_m: " << ground_search_m << " (expected >= vertical_tolerance_m); ";
  }
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("TruthCheckConfig: " + text.substr(0, text.size() - 2));
}

TruthChecker::TruthChecker(const datasets::LabeledMesh& truth, const datasets::TriangleBvh& bvh)
    : truth_(truth),
      bvh_(bvh),
      obstacle_truth_face_(nonDrivableFaces(truth)),
      obstacle_bvh_(subMesh(truth.mesh, obstacle_truth_face_)) {}

TruthCheck checkAgainstTruth(const datasets::LabeledMesh& truth, const datasets::TriangleBvh& bvh,
                             const std::vector<Eigen::Vector3d>& path_W, const Eigen::Vector3d& up_W,
                             double metres_per_unit, const TruthCheckConfig& config) {
  config.validate();  // before the tree is built: a bad config fails fast
  return TruthChecker(truth, bvh).check(path_W, up_W, metres_per_unit, config);
}

TruthCheck TruthChecker::check(const std::vector<Eigen::Vector3d>& path_W, const Eigen::Vector3d& up_W,
                               double metres_per_unit, const TruthCheckConfig& config,
                               const std::vector<Eigen::Vector3d>& body_headings_W) const {
  const datasets::LabeledMesh& truth = truth_;
  const datasets::TriangleBvh& bvh = bvh_;
  config.validate();
  if (!(metres_per_unit > 0.0) || !std::isfinite(metres_per_unit)) {
    throw std::invalid_argument("TruthChecker::check: metres_per_unit " + std::to_string(metres_per_unit) +
                                " (expected > 0)");
  }
  if (!(up_W.norm() > 0.0) || !up_W.allFinite()) throw std::invalid_argument("TruthChecker::check: up_W is zero");

  TruthCheck check;
  const Eigen::Vector3d up = up_W.normalized();
  const double unit = 1.0 / metres_per_unit;  // map units per metre
  const bool own_heading = config.rectangle() && !body_headings_W.empty();
  std::vector<Eigen::Vector3d> body;  // the path's body headings, horizontal and unit
  for (const Eigen::Vector3d& h : body_headings_W) {
    const Eigen::Vector3d flat = h - h.dot(up) * up;
    if (!(flat.norm() > 1e-9) || !flat.allFinite()) {
      throw std::invalid_argument("TruthChecker::check: a body heading has no horizontal direction");
    }
    body.push_back(flat.normalized());
  }
  if (!body.empty() && body.size() != path_W.size()) {
    throw std::invalid_argument("TruthChecker::check: " + std::to_string(body.size()) + " body headings for " +
                                std::to_string(path_W.size()) + " path points");
  }
  std::vector<Eigen::Vector3d> samples, sample_headings;
  for (std::size_t i = 0; i + 1 < path_W.size(); ++i) {
    const Eigen::Vector3d& a = path_W[i];
    const Eigen::Vector3d& b = path_W[i + 1];
    const int steps =
        std::max(1, static_cast<int>(std::ceil((b - a).norm() * metres_per_unit / config.spacing_m)));
    const double turn = own_heading ? internal::turnAngle(body[i], body[i + 1], up) : 0.0;
    for (int s = 0; s < steps; ++s) {
      samples.push_back(a + (b - a) * (static_cast<double>(s) / steps));
      if (own_heading) sample_headings.push_back(internal::turned(body[i], up, turn * s / steps));
    }
  }
  if (!path_W.empty()) samples.push_back(path_W.back());
  if (own_heading && !path_W.empty()) sample_headings.push_back(body.back());
  check.samples = samples.size();
  if (samples.empty()) return check;

  // The heading of travel at each sample (a rectangle's body turns with it), or the body's own.
  const std::vector<Eigen::Vector3d> headings =
      own_heading ? sample_headings
      : config.rectangle() ? internal::travelHeadings(samples, up, 0.5 * config.footprint_length_m * unit)
                           : std::vector<Eigen::Vector3d>{};
  const std::string tolerance_note = " (tolerance " + metres(config.vertical_tolerance_m) +
                                     "; the path lies on our reconstructed surface, so this is also the "
                                     "reconstruction error there)";

  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d& p = samples[i];
    // 1. The true ground under the sample, within the vertical tolerance.
    const auto ground = groundNear(bvh, p, up, config.vertical_tolerance_m * unit);
    if (!ground) {
      const auto far = groundNear(bvh, p, up, config.ground_search_m * unit);
      if (!far) {
        return fail(check, "no true surface within " + metres(config.ground_search_m) +
                               " above or below the path at " + at(p));
      }
      const double offset_m = far->offset * metres_per_unit;
      return fail(check, "the path is " + metres(std::abs(offset_m), 3) + (offset_m < 0 ? " above" : " below") +
                             " the true " + label(truth, far->hit.face) + " surface at " + at(p) + ", " +
                             metres(std::abs(offset_m) - config.vertical_tolerance_m, 3) + " beyond the tolerance" +
                             tolerance_note);
    }
    check.max_ground_offset_m = std::max(check.max_ground_offset_m, std::abs(ground->offset) * metres_per_unit);
    const std::uint32_t face = ground->hit.face;
    const Eigen::Vector3d& g = ground->hit.point;
    // 2. Its label.
    if (!drivable(truth.labels[face])) {
      return fail(check, "true " + label(truth, face) + " face " + metres(std::abs(ground->offset) * metres_per_unit) +
                             (ground->offset <= 0 ? " below" : " above") + " the path at " + at(p) +
                             " (not drivable)");
    }
    // 3. Its true slope.
    if (truth.slope_deg[face] > config.max_slope_deg) {
      std::ostringstream out;
      out.precision(3);
      out << "true slope " << truth.slope_deg[face] << " deg > " << config.max_slope_deg << " deg (by "
          << truth.slope_deg[face] - config.max_slope_deg << " deg) under the path at " << at(p);
      return fail(check, out.str());
    }
    // 4. The body: no non-drivable face in it above the true ground.
    if (obstacle_bvh_.faceCount() > 0) {
      const std::string body =
          headings.empty()
              ? discFailure(p, g, up, metres_per_unit, config)
              : boxFailure(p, g, up, headings[i > 0 ? i - 1 : 0], headings[i], metres_per_unit, config, own_heading);
      if (!body.empty()) return fail(check, body);
    }
    // 5. Crossing the true surface between samples.
    const Eigen::Vector3d lift = config.crossing_lift_m * unit * up;
    if (i > 0 && bvh.segmentOccluded(samples[i - 1] + lift, p + lift, 0.0)) {
      return fail(check, "the path lifted by " + metres(config.crossing_lift_m) +
                             " crosses the true surface between " + at(samples[i - 1]) + " and " + at(p));
    }
  }
  return check;
}

std::string TruthChecker::discFailure(const Eigen::Vector3d& p, const Eigen::Vector3d& g, const Eigen::Vector3d& up,
                                      double metres_per_unit, const TruthCheckConfig& config) const {
  const double unit = 1.0 / metres_per_unit;
  const double radius_m = config.footprint_radius_m;
  const int slices =
      1 + static_cast<int>(std::ceil((config.min_clearance_m - config.max_step_m) / config.body_slice_m - 1e-9));
  for (int s = 0; s < slices; ++s) {
    const double h_m = std::min(config.max_step_m + s * config.body_slice_m, config.min_clearance_m);
    const datasets::SurfacePoint q = obstacle_bvh_.closestPoint(g + h_m * unit * up);
    const Eigen::Vector3d d = q.point - g;
    const double height_m = d.dot(up) * metres_per_unit;
    const double across_m = (d - d.dot(up) * up).norm() * metres_per_unit;
    if (height_m > config.max_step_m && height_m < config.min_clearance_m && across_m < radius_m) {
      return "true " + label(truth_, obstacle_truth_face_[q.face]) + " face " + metres(across_m) + " from the path at " +
             at(p) + ", inside the " + metres(radius_m) + " footprint by " + metres(radius_m - across_m) + ", " +
             metres(height_m) + " above the true ground (body from " + metres(config.max_step_m) + " to " +
             metres(config.min_clearance_m) + "), at " + at(q.point);
    }
  }
  return {};
}

std::string TruthChecker::boxFailure(const Eigen::Vector3d& p, const Eigen::Vector3d& g, const Eigen::Vector3d& up,
                                     const Eigen::Vector3d& from, const Eigen::Vector3d& to, double metres_per_unit,
                                     const TruthCheckConfig& config, bool own_heading) const {
  const double unit = 1.0 / metres_per_unit;
  internal::BodyBox box;
  box.base = g;
  box.up = up;
  box.half_length = 0.5 * config.footprint_length_m * unit;
  box.half_width = 0.5 * config.footprint_width_m * unit;
  box.bottom = config.max_step_m * unit;
  box.top = config.min_clearance_m * unit;
  // Headings close enough that the corners move at most spacing_m between them.
  const double turn = internal::turnAngle(from, to, up);
  const double corner_m = std::hypot(0.5 * config.footprint_length_m, 0.5 * config.footprint_width_m);
  // (A turn that moves the corners by less than a micrometre is none: rounding of straight pieces.)
  const double sweep_m = std::abs(turn) * corner_m;
  const int steps = sweep_m < 1e-6 ? 0 : static_cast<int>(std::ceil(sweep_m / config.spacing_m));
  for (int k = 0; k <= steps; ++k) {
    box.ahead = steps > 0 ? internal::turned(from, up, turn * k / steps) : to;
    for (const std::uint32_t f : obstacle_bvh_.facesWithin(box.centre(), box.circumradius())) {
      const std::uint32_t face = obstacle_truth_face_[f];
      const auto& corners = truth_.mesh.faces[face];
      const auto& v = truth_.mesh.vertices;
      const auto q = internal::triangleInBox(box, v[corners[0]], v[corners[1]], v[corners[2]]);
      if (!q) continue;
      const Eigen::Vector3d l = box.local(*q) * metres_per_unit;
      std::string turning;
      if (k < steps) {  // met between the previous heading and this sample's
        std::ostringstream out;
        out.precision(3);
        out << ", turning by " << std::abs(turn) * 180.0 / M_PI << " deg there";
        turning = out.str();
      }
      // Printed to 0.01 m: a point within rounding of the axis reads as ahead of and left of it.
      return "true " + label(truth_, face) + " face inside the " + metres(config.footprint_length_m) + " x " +
             metres(config.footprint_width_m) + " footprint turned to " +
             (own_heading ? "the body's heading" : "the heading of travel") + turning + ": " +
             metres(std::abs(l.x())) + (l.x() > -0.005 ? " ahead of" : " behind") + " and " + metres(std::abs(l.y())) +
             (l.y() > -0.005 ? " left of" : " right of") + " the path at " + at(p) + ", " + metres(l.z()) +
             " above the true ground (body from " + metres(config.max_step_m) + " to " +
             metres(config.min_clearance_m) + "), at " + at(*q);
    }
  }
  return {};
}

}  // namespace terramesh::evaluation
