#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace terramesh::datasets::internal {

/// Splits one line into whitespace-separated tokens; a token starting with '#' starts a comment.
std::vector<std::string_view> tokenize(std::string_view line);

/// Reads a text file line by line and turns bad content into terramesh::InputError naming the
/// file and the current line. Tokens are views into the current line: valid until the next read.
class TextLineReader {
 public:
  /// @throw terramesh::InputError if the file cannot be opened.
  explicit TextLineReader(const std::filesystem::path& path);

  /// Reads up to the next line with a token (blank and comment lines are skipped).
  /// @return false at the end of the file.
  /// @throw terramesh::InputError on a read error.
  bool nextTokens(std::vector<std::string_view>& tokens);
  /// Reads the next line, blank or not. @return false at the end of the file.
  /// @throw terramesh::InputError on a read error.
  bool nextLine(std::vector<std::string_view>& tokens);

  const std::string& file() const { return file_; }
  /// The current line as read (without its newline).
  const std::string& line() const { return line_; }
  /// 1-based number of the current line (0 before the first read).
  std::size_t lineNumber() const { return line_number_; }

  /// @throw terramesh::InputError naming the file and the current line.
  [[noreturn]] void fail(const std::string& problem) const;
  /// @throw terramesh::InputError unless `tokens` has exactly `count` tokens.
  void expectCount(const std::vector<std::string_view>& tokens, std::size_t count,
                   const std::string& syntax) const;
  /// @throw terramesh::InputError unless `token` is a non-negative decimal integer.
  std::uint64_t integer(std::string_view token, const std::string& what) const;
  /// @throw terramesh::InputError unless `token` is a decimal integer.
  std::int64_t signedInteger(std::string_view token, const std::string& what) const;
  /// @throw terramesh::InputError unless `token` is a finite number.
  double real(std::string_view token, const std::string& what) const;

 private:
  template <class Int>
  Int parseInteger(std::string_view token, const std::string& what, const char* expected) const;

  std::string file_;
  std::ifstream in_;
  std::string line_;
  std::size_t line_number_ = 0;
};

}  // namespace terramesh::datasets::internal
