#include "common/input_error.h"

#include <utility>

namespace terramesh {
namespace {

std::string composeMessage(const std::string& file, const std::string& where,
                           const std::string& problem) {
  std::string message = file;
  if (!where.empty()) message += ": " + where;
  message += ": " + problem;
  return message;
}

}  // namespace

InputError::InputError(std::string file, std::string where, std::string problem)
    : std::runtime_error(composeMessage(file, where, problem)),
      file_(std::move(file)),
      where_(std::move(where)),
      problem_(std::move(problem)) {}

std::string lineLocation(std::size_t line_number) { return "line " + std::to_string(line_number); }

}  // namespace terramesh
