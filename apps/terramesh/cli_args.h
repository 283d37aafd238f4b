#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace terramesh::cli {

/// A usage error: the CLI prints it on one line and exits with code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses the arguments of one subcommand (argv after its name) with `app`, whose name is
/// "terramesh NAME". Returns false when --help was asked for: the help went to stdout and the
/// caller exits 0.
/// @throw UsageError with CLI11's message, prefixed by the subcommand's name, for any other
/// parse error (unknown option, missing or malformed value, missing positional).
bool parseCommandLine(CLI::App& app, const std::vector<std::string>& args);

/// CLI11 validators with one-line messages (CLI11's own print the type's whole range): a finite
/// number >= 0, and a finite number > 0.
CLI::Validator nonNegativeNumber();
CLI::Validator positiveNumber();

/// Splits `text` at ':' into at most `max_fields` non-negative integers, e.g. a frame range "A:B";
/// an empty field (as in "A:") is nullopt, for the caller to accept or refuse.
/// @throw UsageError naming `option` and the expected `form` for anything else.
std::vector<std::optional<std::size_t>> parseColonIntegers(const std::string& text, const std::string& option,
                                                          const std::string& form, std::size_t max_fields);

}  // namespace terramesh::cli
