#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace terramesh {

/// Error in an input file: names the file, where in it (line or field), and what was expected.
/// Readers throw it; applications print what() on one line and exit with code 2.
class InputError : public std::runtime_error {
 public:
  /// @param file path of the offending file.
  /// @param where a location such as "line 12" or "views[3].extrinsic.center".
  /// @param problem what is wrong and what was expected.
  InputError(std::string file, std::string where, std::string problem);

  const std::string& file() const { return file_; }
  const std::string& where() const { return where_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string where_;
  std::string problem_;
};

/// Formats "line N" for InputError locations.
std::string lineLocation(std::size_t line_number);

}  // namespace terramesh
