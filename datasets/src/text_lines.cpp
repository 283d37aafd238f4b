#include "text_lines.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "common/input_error.h"

namespace terramesh::datasets::internal {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }

}  // namespace

std::vector<std::string_view> tokenize(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const std::size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

TextLineReader::TextLineReader(const std::filesystem::path& path)
    : file_(path.string()), in_(path) {
  if (!in_) throw InputError(file_, "", "cannot open file for reading");
}

bool TextLineReader::nextLine(std::vector<std::string_view>& tokens) {
  if (!std::getline(in_, line_)) {
    if (in_.bad()) fail("read error");
    tokens.clear();
    return false;
  }
  ++line_number_;
  tokens = tokenize(line_);
  return true;
}

bool TextLineReader::nextTokens(std::vector<std::string_view>& tokens) {
  while (nextLine(tokens)) {
    if (!tokens.empty()) return true;
  }
  return false;
}

void TextLineReader::fail(const std::string& problem) const {
  throw InputError(file_, lineLocation(line_number_), problem);
}

void TextLineReader::expectCount(const std::vector<std::string_view>& tokens, std::size_t count,
                                 const std::string& syntax) const {
  if (tokens.size() != count) {
    fail("expected \"" + syntax + "\" (" + std::to_string(count) + " fields, got " +
         std::to_string(tokens.size()) + ")");
  }
}

std::uint64_t TextLineReader::integer(std::string_view token, const std::string& what) const {
  return parseInteger<std::uint64_t>(token, what, "a non-negative integer");
}

std::int64_t TextLineReader::signedInteger(std::string_view token, const std::string& what) const {
  return parseInteger<std::int64_t>(token, what, "an integer");
}

template <class Int>
Int TextLineReader::parseInteger(std::string_view token, const std::string& what,
                                 const char* expected) const {
  Int value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || end != token.data() + token.size()) {
    fail(what + ": expected " + expected + ", got \"" + std::string(token) + "\"");
  }
  return value;
}

double TextLineReader::real(std::string_view token, const std::string& what) const {
  // std::from_chars for double is not available in every libstdc++; strtod on a copy is exact.
  const std::string copy(token);
  char* end = nullptr;
  const double value = std::strtod(copy.c_str(), &end);
  if (copy.empty() || end != copy.c_str() + copy.size()) {
    fail(what + ": expected a number, got \"" + copy + "\"");
  }
  if (!std::isfinite(value)) fail(what + ": expected a finite number, got \"" + copy + "\"");
  return value;
}

}  // namespace terramesh::datasets::internal
