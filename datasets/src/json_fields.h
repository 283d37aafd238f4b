#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace terramesh::datasets::internal {

/// Parses a whole JSON file.
/// @throw terramesh::InputError naming the file and, for syntax errors, the line and column;
///        `expected` says what the file should be (e.g. "OpenMVG sfm_data JSON").
nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& expected);

/// Checked access to the fields of a parsed JSON document: a missing field or a value of the
/// wrong type becomes terramesh::InputError naming the file and the JSON path
/// (e.g. "views[3].extrinsic.center[1]").
class JsonFieldReader {
 public:
  explicit JsonFieldReader(std::string file) : file_(std::move(file)) {}

  /// "a.b" (or "b" when `path` is empty).
  static std::string join(const std::string& path, const std::string& key);
  /// "path[index]".
  static std::string at(const std::string& path, std::size_t index);

  [[noreturn]] void fail(const std::string& where, const std::string& problem) const;

  /// The member `key` of the object at `path`.
  const nlohmann::json& member(const nlohmann::json& object, const char* key,
                               const std::string& path) const;
  /// `value` itself, checked to be an array.
  const nlohmann::json& array(const nlohmann::json& value, const std::string& path) const;
  std::uint64_t id(const nlohmann::json& value, const std::string& path) const;
  std::string string(const nlohmann::json& value, const std::string& path) const;
  Eigen::Vector3d vector3(const nlohmann::json& value, const std::string& path) const;
  /// A 3x3 rotation given as 3 rows; orthonormal with determinant +1 within 1e-2.
  Eigen::Matrix3d rotationRows(const nlohmann::json& value, const std::string& path) const;

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

}  // namespace terramesh::datasets::internal
