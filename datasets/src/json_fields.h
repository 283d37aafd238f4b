#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "common/json_fields.h"

namespace terramesh::datasets::internal {

/// json::FieldReader with the values the SLAM and SfM readers take: ids, points and rotations.
class JsonFieldReader : public json::FieldReader {
 public:
  using json::FieldReader::FieldReader;

  /// A non-negative integer id.
  std::uint64_t id(const nlohmann::json& value, const std::string& path) const;
  /// An array of 3 finite numbers.
  Eigen::Vector3d vector3(const nlohmann::json& value, const std::string& path) const;
  /// A 3x3 rotation given as 3 rows; orthonormal with determinant +1 within 1e-2.
  Eigen::Matrix3d rotationRows(const nlohmann::json& value, const std::string& path) const;
};

}  // namespace terramesh::datasets::internal
