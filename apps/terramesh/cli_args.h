#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace terramesh::cli {

/// A usage error: the CLI prints it on one line and exits with code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Declares the options of a subcommand, then parses argv. Options are "--name VALUE" or
/// "--name=VALUE"; flags are "--name". Unknown options are usage errors.
class ArgParser {
 public:
  explicit ArgParser(std::string command) : command_(std::move(command)) {}

  ArgParser& option(const std::string& name, const std::string& value_name, const std::string& help,
                    std::optional<std::string> default_value = std::nullopt);
  ArgParser& flag(const std::string& name, const std::string& help);
  ArgParser& positional(const std::string& name, const std::string& help);
  /// Short alias, e.g. alias("-o", "--output").
  ArgParser& alias(const std::string& short_name, const std::string& long_name);

  /// @throw UsageError for unknown options, missing values or positionals.
  void parse(const std::vector<std::string>& args);

  bool has(const std::string& name) const;
  std::string get(const std::string& name) const;
  double getDouble(const std::string& name) const;
  long getInt(const std::string& name) const;
  bool flagSet(const std::string& name) const;
  const std::string& positionalValue(const std::string& name) const;
  bool helpRequested() const { return help_; }

  std::string usage() const;

 private:
  struct Spec {
    std::string value_name;
    std::string help;
    std::optional<std::string> default_value;
    bool is_flag = false;
  };
  std::string command_;
  std::map<std::string, Spec> specs_;
  std::vector<std::string> spec_order_;
  std::vector<std::pair<std::string, std::string>> positional_specs_;
  std::map<std::string, std::string> aliases_;
  std::map<std::string, std::string> values_;
  std::map<std::string, std::string> positionals_;
  bool help_ = false;
};

/// Splits `text` at ':' into at most `max_fields` non-negative integers, e.g. a frame range "A:B";
/// an empty field (as in "A:") is nullopt, for the caller to accept or refuse.
/// @throw UsageError naming `option` and the expected `form` for anything else.
std::vector<std::optional<std::size_t>> parseColonIntegers(const std::string& text, const std::string& option,
                                                          const std::string& form, std::size_t max_fields);

}  // namespace terramesh::cli
