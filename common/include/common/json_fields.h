#pragma once
// The one home of checked JSON reading and writing (target terramesh::json): a file parsed with
// the line and column of a syntax error, and fields read by their JSON path, so that a missing
// field or a value of the wrong type becomes terramesh::InputError naming the file and the path
// (e.g. "tiles[0].bounds_m.min_x", "views[3].extrinsic.center[1]").

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace terramesh::json {

/// Parses a whole JSON file; `expected` says what it should be (e.g. "OpenMVG sfm_data JSON").
/// @throw terramesh::InputError for a file that cannot be read, malformed JSON (naming the line
///        and column) or a number out of range.
nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& expected);

/// Writes `value` as indented JSON and a newline, atomically (mode 0644).
/// @throw std::runtime_error if the file cannot be written.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value);

/// Checked access to the fields of a parsed document. Each reader takes the JSON path of what it
/// reads, for the error; the keyed forms (object, key, path) read member `key` of the object at
/// `path`.
class FieldReader {
 public:
  explicit FieldReader(std::string file) : file_(std::move(file)) {}

  /// "a.b" (or "b" when `path` is empty).
  static std::string join(const std::string& path, const std::string& key);
  /// "path[index]".
  static std::string at(const std::string& path, std::size_t index);

  /// @throw terramesh::InputError naming the file, `where` and `problem`, always.
  [[noreturn]] void fail(const std::string& where, const std::string& problem) const;

  /// The member `key` of the object at `path`.
  const nlohmann::json& member(const nlohmann::json& object, const std::string& key, const std::string& path) const;

  const nlohmann::json& array(const nlohmann::json& value, const std::string& path) const;
  double number(const nlohmann::json& value, const std::string& path) const;
  /// An integer >= 0.
  std::uint64_t count(const nlohmann::json& value, const std::string& path) const;
  long integer(const nlohmann::json& value, const std::string& path) const;
  std::string string(const nlohmann::json& value, const std::string& path) const;

  const nlohmann::json& array(const nlohmann::json& object, const std::string& key, const std::string& path) const {
    return array(member(object, key, path), join(path, key));
  }
  double number(const nlohmann::json& object, const std::string& key, const std::string& path) const {
    return number(member(object, key, path), join(path, key));
  }
  std::uint64_t count(const nlohmann::json& object, const std::string& key, const std::string& path) const {
    return count(member(object, key, path), join(path, key));
  }
  long integer(const nlohmann::json& object, const std::string& key, const std::string& path) const {
    return integer(member(object, key, path), join(path, key));
  }
  std::string string(const nlohmann::json& object, const std::string& key, const std::string& path) const {
    return string(member(object, key, path), join(path, key));
  }

  /// Checks the document's top-level "format" and "version" fields.
  void header(const nlohmann::json& root, const std::string& format, int version) const;

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

}  // namespace terramesh::json
