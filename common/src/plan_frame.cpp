#include "common/plan_frame.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

namespace terramesh::geometry {

void PlanFrameRule::validate() const {
  std::string problems;
  if (!(x_helper_below_abs_up_x > 0.0 && x_helper_below_abs_up_x <= 1.0)) {
    problems += " x_helper_below_abs_up_x must be in (0, 1];";
  }
  if (!(x_helper_min_projected_norm >= 0.0 && x_helper_min_projected_norm < 1.0)) {
    problems += " x_helper_min_projected_norm must be in [0, 1);";
  }
  if (!problems.empty()) throw std::invalid_argument("PlanFrameRule:" + problems);
}

PlanFrameRule exportFrameRule() {
  PlanFrameRule rule;
  // x while |up.x| <= cos 30 degrees: the first double above it is the strict bound.
  rule.x_helper_below_abs_up_x = std::nextafter(std::cos(30.0 * M_PI / 180.0), 2.0);
  return rule;
}

PlanFrameRule headingFrameRule() {
  PlanFrameRule rule;
  rule.x_helper_min_projected_norm = 0.3;
  return rule;
}

Eigen::Vector3d headingDirection(double yaw_rad, const Eigen::Vector3d& up) {
  const PlanFrame frame = planFrame(up, headingFrameRule());
  return std::cos(yaw_rad) * frame.e1 + std::sin(yaw_rad) * frame.e2;
}

PlanFrameRule acrossFrameRule() {
  PlanFrameRule rule;
  rule.first_axis = FirstAxis::kUpCrossHelper;
  return rule;
}

PlanFrame planFrame(const Eigen::Vector3d& up, const PlanFrameRule& rule) {
  rule.validate();
  const auto inPlane = [&up](const Eigen::Vector3d& axis) -> Eigen::Vector3d { return axis - axis.dot(up) * up; };
  Eigen::Vector3d helper = Eigen::Vector3d::UnitX();
  if (rule.x_helper_min_projected_norm > 0.0) {
    if (inPlane(helper).norm() < rule.x_helper_min_projected_norm) helper = Eigen::Vector3d::UnitY();
  } else if (!(std::abs(up.x()) < rule.x_helper_below_abs_up_x)) {
    helper = Eigen::Vector3d::UnitY();
  }
  PlanFrame frame;
  frame.up = up;
  frame.e1 = rule.first_axis == FirstAxis::kProjectedHelper ? inPlane(helper).normalized()
                                                            : up.cross(helper).normalized();
  frame.e2 = up.cross(frame.e1);
  return frame;
}

Eigen::Matrix3d rotationUpToZ(const Eigen::Vector3d& up) {
  return Eigen::Quaterniond::FromTwoVectors(up.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace terramesh::geometry
