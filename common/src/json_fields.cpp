#include "common/json_fields.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "common/atomic_file.h"
#include "common/input_error.h"

namespace terramesh::json {
namespace {

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

nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& expected) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading (expected " + expected + ")");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw InputError(path.string(), "", "read error");
  const std::string text = content.str();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& error) {
    throw InputError(path.string(), lineAndColumn(text, error.byte), "malformed JSON (expected " + expected + ")");
  } catch (const nlohmann::json::out_of_range& error) {
    // A number too large for a double (1e999): nlohmann names the token, not where it is.
    throw InputError(path.string(), "", std::string("number out of range (") + error.what() + "; expected " + expected + ")");
  }
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value) {
  writeFileAtomically(path, value.dump(2) + "\n");
}

std::string FieldReader::join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

std::string FieldReader::at(const std::string& path, std::size_t index) { return path + "[" + std::to_string(index) + "]"; }

void FieldReader::fail(const std::string& where, const std::string& problem) const {
  throw InputError(file_, where, problem);
}

const nlohmann::json& FieldReader::member(const nlohmann::json& object, const std::string& key,
                                          const std::string& path) const {
  if (!object.is_object()) fail(path.empty() ? "top level" : path, "expected a JSON object");
  const auto found = object.find(key);
  if (found == object.end()) fail(join(path, key), "missing field");
  return *found;
}

const nlohmann::json& FieldReader::array(const nlohmann::json& value, const std::string& path) const {
  if (!value.is_array()) fail(path, "expected an array");
  return value;
}

double FieldReader::number(const nlohmann::json& value, const std::string& path) const {
  if (!value.is_number()) fail(path, "expected a number");
  return value.get<double>();
}

std::uint64_t FieldReader::count(const nlohmann::json& value, const std::string& path) const {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0) return static_cast<std::uint64_t>(value.get<std::int64_t>());
  fail(path, "expected an integer >= 0");
}

long FieldReader::integer(const nlohmann::json& value, const std::string& path) const {
  if (!value.is_number_integer()) fail(path, "expected an integer");
  return value.get<long>();
}

std::string FieldReader::string(const nlohmann::json& value, const std::string& path) const {
  if (!value.is_string()) fail(path, "expected a string");
  return value.get<std::string>();
}

void FieldReader::header(const nlohmann::json& root, const std::string& format, int version) const {
  if (string(root, "format", "") != format) fail("format", "expected \"" + format + "\"");
  if (integer(root, "version", "") != version) fail("version", "expected " + std::to_string(version));
}

}  // namespace terramesh::json
