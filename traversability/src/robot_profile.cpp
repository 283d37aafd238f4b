#include "traversability/robot_profile.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "robot_profile_schema.h"

namespace terramesh::traversability {
namespace internal {
namespace {

void addMountingProblems(const RobotProfile& profile, std::vector<std::string>& problems) {
  if (profile.sensor_height_m && !kSensorHeightRange.contains(*profile.sensor_height_m)) {
    problems.push_back("sensor_height_m: " + formatNumber(*profile.sensor_height_m) + " (expected " +
                       kSensorHeightRange.text() + ")");
  }
  if (!profile.T_B_S) return;
  const Eigen::Isometry3d& T = *profile.T_B_S;
  const Eigen::Matrix3d R = T.linear();
  if (!T.matrix().allFinite() || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
      R.determinant() < 0) {
    problems.push_back("sensor_pose_in_base: not a finite rigid transform (expected a translation and a rotation)");
    return;
  }
  const double z = T.translation().z();
  if (!kSensorHeightRange.contains(z)) {
    problems.push_back("sensor_pose_in_base.translation_m[2]: " + formatNumber(z) + " (expected " +
                       kSensorHeightRange.text() + ")");
  }
  if (profile.sensor_height_m && std::abs(*profile.sensor_height_m - z) > 1e-6) {
    problems.push_back("sensor_height_m: " + formatNumber(*profile.sensor_height_m) +
                       " (expected the height of sensor_pose_in_base, " + formatNumber(z) + ")");
  }
}

}  // namespace

const std::vector<NumericKey>& numericKeys() {
  static const std::vector<NumericKey> keys = {
      {"footprint.radius_m", {0, 50, true, false}, false, [](RobotProfile& p) -> double& { return p.footprint_radius_m; }},
      {"footprint.length_m", {0, 50, true, false}, false, [](RobotProfile& p) -> double& { return p.footprint_length_m; }},
      {"footprint.width_m", {0, 50, true, false}, false, [](RobotProfile& p) -> double& { return p.footprint_width_m; }},
      {"max_slope_deg", {0, 90, true, true}, false, [](RobotProfile& p) -> double& { return p.max_slope_deg; }},
      {"max_step_m", {0, 10, false, false}, false, [](RobotProfile& p) -> double& { return p.max_step_m; }},
      {"max_roughness_m", {0, 10, true, false}, false, [](RobotProfile& p) -> double& { return p.max_roughness_m; }},
      {"min_clearance_m", {0, 50, true, false}, false, [](RobotProfile& p) -> double& { return p.min_clearance_m; }},
      {"contact_tolerance_m", {0, 10, true, false}, false, [](RobotProfile& p) -> double& { return p.contact_tolerance_m; }},
      {"min_support", {0, 1, false, false}, false, [](RobotProfile& p) -> double& { return p.min_support; }},
      {"inscribed_radius_m", {0, 100, false, false}, false, [](RobotProfile& p) -> double& { return p.inscribed_radius_m; }},
      {"inflation_radius_m", {0, 100, false, false}, false, [](RobotProfile& p) -> double& { return p.inflation_radius_m; }},
      {"cost_scaling_factor", {0, 1000, true, false}, false, [](RobotProfile& p) -> double& { return p.cost_scaling_factor; }},
      {"weights.slope", {0, 1000, false, false}, false, [](RobotProfile& p) -> double& { return p.weights.slope; }},
      {"weights.step", {0, 1000, false, false}, false, [](RobotProfile& p) -> double& { return p.weights.step; }},
      {"weights.roughness", {0, 1000, false, false}, false, [](RobotProfile& p) -> double& { return p.weights.roughness; }},
      {"weights.contact", {0, 1000, false, false}, false, [](RobotProfile& p) -> double& { return p.weights.contact; }},
      {"weights.inflation", {0, 1000, false, false}, false, [](RobotProfile& p) -> double& { return p.weights.inflation; }},
      {"evidence.point_noise_m", {0, 10, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.point_noise_m; }},
      {"evidence.relief_per_m_observed", {0, 10, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.relief_per_m_observed; }},
      {"evidence.relief_per_m_unobserved", {0, 10, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.relief_per_m_unobserved; }},
      {"evidence.driven_uncertainty_m", {0, 10, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.driven_uncertainty_m; }},
      {"evidence.obstacle_extension", {0, 10, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.obstacle_extension; }},
      {"evidence.max_obstacle_extension_m", {0, 100, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.max_obstacle_extension_m; }},
      {"evidence.obstacle_support_m", {0, 100, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.obstacle_support_m; }},
      {"evidence.unconfirmed_point_extension_m", {0, 100, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.unconfirmed_point_extension_m; }},
      {"evidence.proud_point_rise_m", {0, 10, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.proud_point_rise_m; }},
      {"evidence.uncertain_cost", {0, 1, false, false}, false,
       [](RobotProfile& p) -> double& { return p.evidence.uncertain_cost; }},
  };
  return keys;
}

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

std::vector<std::string> problemsOf(const RobotProfile& profile) {
  std::vector<std::string> problems;
  RobotProfile copy = profile;
  if (copy.name.empty()) problems.push_back("name: \"\" (expected a non-empty string)");
  for (const NumericKey& key : numericKeys()) {
    const std::string k = key.key;
    const bool disc_key = k == "footprint.radius_m";
    const bool rect_key = k == "footprint.length_m" || k == "footprint.width_m";
    if ((disc_key && copy.footprint != FootprintShape::kDisc) ||
        (rect_key && copy.footprint != FootprintShape::kRectangle)) {
      continue;
    }
    const double value = key.field(copy);
    if (!key.range.contains(value)) {
      problems.push_back(k + ": " + formatNumber(value) + " (expected " + key.range.text() + ")");
    }
  }
  if (!kHeadingsRange.contains(copy.contact_headings)) {
    problems.push_back("contact_headings: " + std::to_string(copy.contact_headings) + " (expected an integer in " +
                       kHeadingsRange.text() + ")");
  }
  if (!kMinRaysRange.contains(copy.min_rays)) {
    problems.push_back("min_rays: " + std::to_string(copy.min_rays) + " (expected an integer in " +
                       kMinRaysRange.text() + ")");
  }
  if (copy.inflation_radius_m < copy.inscribed_radius_m) {
    problems.push_back("inflation_radius_m: " + formatNumber(copy.inflation_radius_m) +
                       " (expected >= inscribed_radius_m = " + formatNumber(copy.inscribed_radius_m) + ")");
  }
  const LayerWeights& w = copy.weights;
  if (!(w.slope + w.step + w.roughness + w.contact + w.inflation > 0)) {
    problems.push_back("weights: all zero (expected at least one weight > 0)");
  }
  if (copy.gravity_W && (!copy.gravity_W->allFinite() || copy.gravity_W->norm() < 1e-12)) {
    problems.push_back("gravity: not a finite non-zero vector (expected auto or [x, y, z])");
  }
  addMountingProblems(copy, problems);
  return problems;
}

}  // namespace internal

const char* toString(MotionModel model) {
  switch (model) {
    case MotionModel::kDiffDrive: return "diff_drive";
    case MotionModel::kOmni: return "omni";
  }
  return "?";
}

double RobotProfile::footprintCircumradiusM() const {
  if (footprint == FootprintShape::kDisc) return footprint_radius_m;
  return 0.5 * std::hypot(footprint_length_m, footprint_width_m);
}

double RobotProfile::inflationTerm(double distance_m) const {
  if (!(distance_m <= inflation_radius_m)) return 0.0;
  if (distance_m <= inscribed_radius_m) return 1.0;
  return std::exp(-cost_scaling_factor * (distance_m - inscribed_radius_m));
}

std::optional<double> RobotProfile::mountedSensorHeightM() const {
  if (sensor_height_m) return sensor_height_m;
  if (T_B_S) return T_B_S->translation().z();
  return std::nullopt;
}

void RobotProfile::validate() const {
  const std::vector<std::string> problems = internal::problemsOf(*this);
  if (problems.empty()) return;
  std::string message = "invalid robot profile \"" + name + "\":";
  for (const std::string& p : problems) message += "\n  " + p;
  throw std::invalid_argument(message);
}

}  // namespace terramesh::traversability
