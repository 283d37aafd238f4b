#include "cli_args.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace terramesh::cli {

ArgParser& ArgParser::option(const std::string& name, const std::string& value_name,
                             const std::string& help, std::optional<std::string> default_value) {
  specs_[name] = Spec{value_name, help, std::move(default_value), false};
  spec_order_.push_back(name);
  return *this;
}

ArgParser& ArgParser::flag(const std::string& name, const std::string& help) {
  specs_[name] = Spec{"", help, std::nullopt, true};
  spec_order_.push_back(name);
  return *this;
}

ArgParser& ArgParser::positional(const std::string& name, const std::string& help) {
  positional_specs_.emplace_back(name, help);
  return *this;
}

ArgParser& ArgParser::alias(const std::string& short_name, const std::string& long_name) {
  aliases_[short_name] = long_name;
  return *this;
}

void ArgParser::parse(const std::vector<std::string>& args) {
  std::size_t next_positional = 0;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string arg = args[i];
    if (arg == "-h" || arg == "--help") {
      help_ = true;
      return;
    }
    if (const auto it = aliases_.find(arg); it != aliases_.end()) arg = it->second;
    if (arg.size() > 2 && arg.compare(0, 2, "--") == 0) {
      std::string name = arg;
      std::optional<std::string> inline_value;
      if (const auto eq = arg.find('='); eq != std::string::npos) {
        name = arg.substr(0, eq);
        inline_value = arg.substr(eq + 1);
      }
      const auto spec = specs_.find(name);
      if (spec == specs_.end()) throw UsageError(command_ + ": unknown option " + name);
      if (spec->second.is_flag) {
        if (inline_value) throw UsageError(command_ + ": " + name + " takes no value");
        values_[name] = "1";
      } else if (inline_value) {
        values_[name] = *inline_value;
      } else {
        if (i + 1 >= args.size()) {
          throw UsageError(command_ + ": " + name + " needs a value (" + spec->second.value_name + ")");
        }
        values_[name] = args[++i];
      }
      continue;
    }
    if (next_positional >= positional_specs_.size()) {
      throw UsageError(command_ + ": unexpected argument \"" + arg + "\"");
    }
    positionals_[positional_specs_[next_positional++].first] = arg;
  }
  if (next_positional < positional_specs_.size()) {
    throw UsageError(command_ + ": missing " + positional_specs_[next_positional].first);
  }
}

bool ArgParser::has(const std::string& name) const {
  if (values_.count(name)) return true;
  const auto spec = specs_.find(name);
  return spec != specs_.end() && spec->second.default_value.has_value();
}

std::string ArgParser::get(const std::string& name) const {
  if (const auto it = values_.find(name); it != values_.end()) return it->second;
  const auto spec = specs_.find(name);
  if (spec != specs_.end() && spec->second.default_value) return *spec->second.default_value;
  throw UsageError(command_ + ": missing required option " + name);
}

double ArgParser::getDouble(const std::string& name) const {
  const std::string text = get(name);
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno != 0 || !std::isfinite(value)) {
    throw UsageError(command_ + ": " + name + " expects a number, got \"" + text + "\"");
  }
  return value;
}

long ArgParser::getInt(const std::string& name) const {
  const std::string text = get(name);
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0) {
    throw UsageError(command_ + ": " + name + " expects an integer, got \"" + text + "\"");
  }
  return value;
}

bool ArgParser::flagSet(const std::string& name) const { return values_.count(name) != 0; }

const std::string& ArgParser::positionalValue(const std::string& name) const {
  return positionals_.at(name);
}

std::string ArgParser::usage() const {
  std::ostringstream out;
  out << "usage: terramesh " << command_;
  for (const auto& [name, help] : positional_specs_) out << ' ' << name;
  out << " [options]\n";
  for (const auto& [name, help] : positional_specs_) out << "  " << name << "\n      " << help << '\n';
  for (const std::string& name : spec_order_) {
    const Spec& spec = specs_.at(name);
    out << "  " << name;
    for (const auto& [short_name, long_name] : aliases_) {
      if (long_name == name) out << ", " << short_name;
    }
    if (!spec.is_flag) out << ' ' << spec.value_name;
    out << "\n      " << spec.help;
    if (spec.default_value) out << " (default " << *spec.default_value << ")";
    out << '\n';
  }
  return out.str();
}

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
