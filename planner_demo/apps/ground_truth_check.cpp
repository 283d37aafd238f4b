#include "ground_truth_check.h"

#include <cmath>
#include <sstream>

namespace terramesh::planning::demo {
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

}  // namespace

TruthCheck checkAgainstTruth(const datasets::LabeledMesh& truth, const datasets::TriangleBvh& bvh,
                             const std::vector<Eigen::Vector3d>& path_W, const Eigen::Vector3d& up_W,
                             double metres_per_unit, double max_slope_deg, double spacing_m, double lift_m) {
  TruthCheck check;
  const Eigen::Vector3d up = up_W.normalized();
  const double unit = 1.0 / metres_per_unit;
  std::vector<Eigen::Vector3d> samples;
  for (std::size_t i = 0; i + 1 < path_W.size(); ++i) {
    const Eigen::Vector3d& a = path_W[i];
    const Eigen::Vector3d& b = path_W[i + 1];
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() * metres_per_unit / spacing_m)));
    for (int s = 0; s < steps; ++s) samples.push_back(a + (b - a) * (static_cast<double>(s) / steps));
  }
  if (!path_W.empty()) samples.push_back(path_W.back());
  check.samples = samples.size();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d& p = samples[i];
    const auto hit = bvh.firstHit(p + 0.5 * unit * up, -up, 1.5 * unit);
    if (!hit) {
      check.valid = false;
      check.reason = "no true ground under the path at " + at(p);
      return check;
    }
    const datasets::SurfaceLabel label = truth.labels[hit->face];
    if (!drivable(label)) {
      check.valid = false;
      check.reason = std::string(datasets::toString(label)) + " under the path at " + at(p);
      return check;
    }
    if (truth.slope_deg[hit->face] > max_slope_deg) {
      check.valid = false;
      check.reason = "true slope " + std::to_string(truth.slope_deg[hit->face]) + " deg under the path at " + at(p);
      return check;
    }
    if (i > 0 && bvh.segmentOccluded(samples[i - 1] + lift_m * unit * up, p + lift_m * unit * up, 0.0)) {
      check.valid = false;
      check.reason = "the path crosses the true surface between " + at(samples[i - 1]) + " and " + at(p);
      return check;
    }
  }
  return check;
}

}  // namespace terramesh::planning::demo
