#pragma once

#include <stdexcept>
#include <string>

namespace terramesh::datasets::synthetic {

/// Collects every problem of a config so that validate() reports them all at once.
class ProblemList {
 public:
  explicit ProblemList(std::string owner) : owner_(std::move(owner)) {}

  /// Records `message` unless `ok`.
  void require(bool ok, const std::string& message) {
    if (ok) return;
    message_ += message_.empty() ? owner_ + ": " : "; ";
    message_ += message;
  }

  /// @throw std::invalid_argument with all recorded problems, if any.
  void throwIfAny() const {
    if (!message_.empty()) throw std::invalid_argument(message_);
  }

 private:
  std::string owner_;
  std::string message_;
};

}  // namespace terramesh::datasets::synthetic
