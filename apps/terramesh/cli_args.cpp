#include "cli_args.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace terramesh::cli {

bool parseCommandLine(CLI::App& app, const std::vector<std::string>& args) {
  // As before CLI11: an option given twice keeps its last value (scripts append overrides).
  for (CLI::Option* option : app.get_options()) option->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return false;
  } catch (const CLI::ParseError& error) {
    std::string command = app.get_name();
    if (command.rfind("terramesh ", 0) == 0) command.erase(0, 10);
    throw UsageError(command + ": " + error.what());
  }
  return true;
}

namespace {

CLI::Validator numberAbove(double bound, bool inclusive, const std::string& name) {
  return CLI::Validator(
      [bound, inclusive](std::string& text) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) {
          return "expects a number, got \"" + text + "\"";
        }
        const bool ok = inclusive ? value >= bound : value > bound;
        return ok ? std::string() : std::string("must be ") + (inclusive ? ">= " : "> ") + "0, got " + text;
      },
      name);
}

}  // namespace

CLI::Validator nonNegativeNumber() { return numberAbove(0.0, true, "NONNEGATIVE"); }
CLI::Validator positiveNumber() { return numberAbove(0.0, false, "POSITIVE"); }

std::vector<std::optional<std::size_t>> parseColonIntegers(const std::string& text, const std::string& option,
                                                          const std::string& form, std::size_t max_fields) {
  auto fail = [&]() {
    return UsageError(option + " expects " + form + " with non-negative integers, got \"" + text + "\"");
  };
  std::vector<std::optional<std::size_t>> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t colon = std::min(text.find(':', start), text.size());
    const std::string part = text.substr(start, colon - start);
    if (part.empty()) {
      fields.emplace_back();
    } else {
      if (part.find_first_not_of("0123456789") != std::string::npos || part.size() > 18) throw fail();
      fields.emplace_back(static_cast<std::size_t>(std::stoull(part)));
    }
    if (fields.size() > max_fields) throw fail();
    if (colon == text.size()) break;
    start = colon + 1;
  }
  return fields;
}

}  // namespace terramesh::cli
