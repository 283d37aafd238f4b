#pragma once

#include <cstddef>
#include <cstdio>
#include <string>

namespace terramesh::cli {

/// A one-line progress bar on stderr, drawn only when stderr is a terminal.
class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void update(std::size_t done);

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  int last_permille_ = -1;
};

}  // namespace terramesh::cli
