#include "json_fields.h"

#include <cmath>

#include "camera_pose.h"

namespace terramesh::datasets::internal {

using nlohmann::json;

std::uint64_t JsonFieldReader::id(const json& value, const std::string& path) const {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0) {
    return static_cast<std::uint64_t>(value.get<std::int64_t>());
  }
  fail(path, "expected a non-negative integer id");
}

Eigen::Vector3d JsonFieldReader::vector3(const json& value, const std::string& path) const {
  if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 numbers");
  Eigen::Vector3d result;
  for (std::size_t i = 0; i < 3; ++i) {
    const json& element = value[i];
    if (!element.is_number()) fail(at(path, i), "expected a number");
    result[static_cast<Eigen::Index>(i)] = element.get<double>();
    if (!std::isfinite(result[static_cast<Eigen::Index>(i)])) {
      fail(at(path, i), "expected a finite number");
    }
  }
  return result;
}

Eigen::Matrix3d JsonFieldReader::rotationRows(const json& value, const std::string& path) const {
  if (!value.is_array() || value.size() != 3) fail(path, "expected a 3x3 array of numbers");
  Eigen::Matrix3d rotation;
  for (std::size_t r = 0; r < 3; ++r) {
    rotation.row(static_cast<Eigen::Index>(r)) = vector3(value[r], at(path, r)).transpose();
  }
  if (!isRotationMatrix(rotation)) {
    fail(path, "expected a rotation matrix (orthonormal, determinant +1)");
  }
  return rotation;
}

}  // namespace terramesh::datasets::internal
