#include "binary_input.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/input_error.h"

namespace terramesh::datasets::internal {

std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw InputError(path.string(), "", "read error");
  return content.str();
}

BinaryCursor::BinaryCursor(const std::filesystem::path& path)
    : file_(path.string()), bytes_(readWholeFile(path)) {}

void BinaryCursor::fail(std::size_t offset, const std::string& problem) const {
  std::string where = "byte " + std::to_string(offset);
  if (!record_.empty()) where += " (" + record_ + ")";
  throw InputError(file_, where, problem);
}

void BinaryCursor::require(std::size_t count, std::string_view what) const {
  if (!has(count)) {
    fail(offset_, "file ends inside " + std::string(what) + ": " + std::to_string(count) +
                      " bytes needed, " + std::to_string(bytes_.size() - offset_) +
                      " left (truncated file?)");
  }
}

double BinaryCursor::readFinite(const char* field) {
  const std::size_t start = offset_;
  const double value = read<double>(field);
  if (!std::isfinite(value)) fail(start, std::string(field) + ": expected a finite number");
  return value;
}

std::string BinaryCursor::readCString(const char* field) {
  const std::size_t end = bytes_.find('\0', offset_);
  if (end == std::string::npos) {
    fail(offset_, std::string("file ends inside ") + field + " (no terminating NUL byte)");
  }
  std::string value = bytes_.substr(offset_, end - offset_);
  offset_ = end + 1;
  return value;
}

std::uint64_t BinaryCursor::readCount(const char* field, std::size_t min_record_bytes) {
  const std::size_t start = offset_;
  const auto count = read<std::uint64_t>(field);
  const std::size_t left = bytes_.size() - offset_;
  if (min_record_bytes > 0 && count > left / min_record_bytes) {
    fail(start, std::string(field) + " is " + std::to_string(count) + " but only " +
                    std::to_string(left) + " bytes follow (at least " +
                    std::to_string(min_record_bytes) +
                    " per record): wrong count or truncated file");
  }
  return count;
}

void BinaryCursor::expectEnd(const std::string& what) const {
  if (offset_ != bytes_.size()) {
    fail(offset_, std::to_string(bytes_.size() - offset_) + " unexpected bytes after " + what +
                      " (wrong count?)");
  }
}

}  // namespace terramesh::datasets::internal
