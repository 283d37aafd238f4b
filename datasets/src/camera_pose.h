#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mesher/keyframe.h"

namespace terramesh::datasets::internal {

/// Largest Frobenius norm of R^T R - I accepted for a rotation read from a file (files print
/// rotations with as few as 6 digits).
constexpr double kRotationTolerance = 1e-2;

/// Whether `rotation` is orthonormal with determinant +1, within kRotationTolerance.
inline bool isRotationMatrix(const Eigen::Matrix3d& rotation) {
  return (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm() <=
             kRotationTolerance &&
         rotation.determinant() > 0;
}

/// A keyframe (no observations) from a world-to-camera pose x_C = R_C_W x_W + t_C_W, with the
/// camera axes x right, y down, z forward: centre -R_C_W^T t_C_W, rotation R_C_W^T.
inline mesher::Keyframe keyframeFromWorldToCamera(std::uint64_t id,
                                                  const Eigen::Quaterniond& rotation_C_W,
                                                  const Eigen::Vector3d& translation_C_W) {
  mesher::Keyframe keyframe;
  keyframe.id.value = id;
  const Eigen::Quaterniond unit = rotation_C_W.normalized();
  keyframe.position_W_C = -(unit.toRotationMatrix().transpose() * translation_C_W);
  keyframe.rotation_W_C = unit.conjugate();
  return keyframe;
}

}  // namespace terramesh::datasets::internal
