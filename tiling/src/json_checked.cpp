#include "json_checked.h"

#include <fstream>
#include <sstream>

#include "common/atomic_file.h"
#include "common/input_error.h"

namespace terramesh::tiling::internal {

nlohmann::json readJson(const std::filesystem::path& path, const std::string& expected) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading (expected " + expected + ")");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& error) {
    throw InputError(path.string(), "byte " + std::to_string(error.byte),
                     "not valid JSON (expected " + expected + "): " + error.what());
  }
}

std::string joinPath(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

void JsonChecked::fail(const std::string& where, const std::string& problem) const {
  throw InputError(file_.string(), where, problem);
}

const nlohmann::json& JsonChecked::field(const nlohmann::json& object, const std::string& key,
                                         const std::string& path) const {
  if (!object.is_object()) fail(path.empty() ? "top level" : path, "expected a JSON object");
  const auto found = object.find(key);
  if (found == object.end()) fail(joinPath(path, key), "missing");
  return *found;
}

double JsonChecked::number(const nlohmann::json& object, const std::string& key, const std::string& path) const {
  const nlohmann::json& value = field(object, key, path);
  if (!value.is_number()) fail(joinPath(path, key), "expected a number");
  return value.get<double>();
}

std::uint64_t JsonChecked::count(const nlohmann::json& object, const std::string& key, const std::string& path) const {
  const nlohmann::json& value = field(object, key, path);
  if (!value.is_number_unsigned()) fail(joinPath(path, key), "expected an integer >= 0");
  return value.get<std::uint64_t>();
}

long JsonChecked::integer(const nlohmann::json& object, const std::string& key, const std::string& path) const {
  const nlohmann::json& value = field(object, key, path);
  if (!value.is_number_integer()) fail(joinPath(path, key), "expected an integer");
  return value.get<long>();
}

std::string JsonChecked::text(const nlohmann::json& object, const std::string& key, const std::string& path) const {
  const nlohmann::json& value = field(object, key, path);
  if (!value.is_string()) fail(joinPath(path, key), "expected a string");
  return value.get<std::string>();
}

const nlohmann::json& JsonChecked::array(const nlohmann::json& object, const std::string& key,
                                         const std::string& path) const {
  const nlohmann::json& value = field(object, key, path);
  if (!value.is_array()) fail(joinPath(path, key), "expected an array");
  return value;
}

void JsonChecked::header(const nlohmann::json& root, const std::string& format, int version) const {
  if (text(root, "format", "") != format) fail("format", "expected \"" + format + "\"");
  if (integer(root, "version", "") != version) fail("version", "expected " + std::to_string(version));
}

void writeJson(const std::filesystem::path& path, const nlohmann::json& value) {
  writeFileAtomically(path, value.dump(2) + "\n");
}

}  // namespace terramesh::tiling::internal
