#include "json_fields.h"

#include <algorithm>
#include <cmath>

#include "binary_input.h"
#include "camera_pose.h"
#include "common/input_error.h"

namespace terramesh::datasets::internal {
namespace {

using nlohmann::json;

std::string lineAndColumn(const std::string& text, std::size_t byte) {
  byte = std::min(byte, text.size());
  std::size_t line = 1;
  std::size_t column = 1;
  for (std::size_t i = 0; i + 1 < byte; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

json readJsonFile(const std::filesystem::path& path, const std::string& expected) {
  const std::string text = readWholeFile(path);
  try {
    return json::parse(text);
  } catch (const json::parse_error& error) {
    throw InputError(path.string(), lineAndColumn(text, error.byte),
                     "malformed JSON (expected " + expected + ")");
  } catch (const json::out_of_range& error) {
    // A number too large for a double (1e999): nlohmann names the token, not where it is.
    throw InputError(path.string(), "",
                     std::string("number out of range (") + error.what() + "; expected " + expected + ")");
  }
}

std::string JsonFieldReader::join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string JsonFieldReader::at(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

void JsonFieldReader::fail(const std::string& where, const std::string& problem) const {
  throw InputError(file_, where, problem);
}

const json& JsonFieldReader::member(const json& object, const char* key,
                                    const std::string& path) const {
  if (!object.is_object()) fail(path, "expected a JSON object");
  const auto it = object.find(key);
  if (it == object.end()) fail(join(path, key), "missing field");
  return *it;
}

const json& JsonFieldReader::array(const json& value, const std::string& path) const {
  if (!value.is_array()) fail(path, "expected an array");
  return value;
}

std::uint64_t JsonFieldReader::id(const json& value, const std::string& path) const {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0) {
    return static_cast<std::uint64_t>(value.get<std::int64_t>());
  }
  fail(path, "expected a non-negative integer id");
}

std::string JsonFieldReader::string(const json& value, const std::string& path) const {
  if (!value.is_string()) fail(path, "expected a string");
  return value.get<std::string>();
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
