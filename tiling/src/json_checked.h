#pragma once

// Checked reads from a parsed JSON document: a missing or mistyped field becomes
// terramesh::InputError naming the file and the field's path (internal).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace terramesh::tiling::internal {

/// Parses a whole JSON file; `expected` names what it should be.
/// @throw terramesh::InputError for a missing file or a syntax error.
nlohmann::json readJson(const std::filesystem::path& path, const std::string& expected);

class JsonChecked {
 public:
  explicit JsonChecked(std::filesystem::path file) : file_(std::move(file)) {}
  [[noreturn]] void fail(const std::string& where, const std::string& problem) const;
  const nlohmann::json& field(const nlohmann::json& object, const std::string& key, const std::string& path) const;
  double number(const nlohmann::json& object, const std::string& key, const std::string& path) const;
  std::uint64_t count(const nlohmann::json& object, const std::string& key, const std::string& path) const;
  long integer(const nlohmann::json& object, const std::string& key, const std::string& path) const;
  std::string text(const nlohmann::json& object, const std::string& key, const std::string& path) const;
  const nlohmann::json& array(const nlohmann::json& object, const std::string& key, const std::string& path) const;
  /// Checks the "format" and "version" fields.
  void header(const nlohmann::json& root, const std::string& format, int version) const;

 private:
  std::filesystem::path file_;
};

/// "path.key" (or "key" at the top).
std::string joinPath(const std::string& path, const std::string& key);

/// Writes `value` as indented JSON and a newline, atomically.
void writeJson(const std::filesystem::path& path, const nlohmann::json& value);

}  // namespace terramesh::tiling::internal
