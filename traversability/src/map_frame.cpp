// The map frame's check and the estimate of up from the sensors' orientations.
#include <stdexcept>
#include <string>

#include "traversability/traversability_map.h"

namespace terramesh::traversability {

void MapFrame::validate() const {
  std::string problems;
  if (!up_W.allFinite() || up_W.norm() < 1e-12) problems += "\n  up_W: not a finite non-zero vector";
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    problems += "\n  metres_per_unit: " + std::to_string(metres_per_unit) + " (expected > 0)";
  }
  if (!problems.empty()) throw std::invalid_argument("invalid map frame:" + problems);
}

Eigen::Vector3d estimateUpFromCameras(const std::vector<Eigen::Matrix3d>& rotations_W_C,
                                      const Eigen::Vector3d& up_C) {
  if (rotations_W_C.empty()) throw std::invalid_argument("estimateUpFromCameras: no camera rotations");
  if (!up_C.allFinite() || up_C.norm() == 0.0) {
    throw std::invalid_argument("estimateUpFromCameras: the sensor's up axis is not a finite non-zero vector");
  }
  const Eigen::Vector3d axis = up_C.normalized();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Matrix3d& R : rotations_W_C) sum += R * axis;
  if (!sum.allFinite() || sum.norm() < 1e-6 * static_cast<double>(rotations_W_C.size())) {
    throw std::invalid_argument("estimateUpFromCameras: the cameras' up axes cancel out");
  }
  return sum.normalized();
}

}  // namespace terramesh::traversability
