#include "progress_bar.h"

#include <unistd.h>

namespace terramesh::cli {

ProgressBar::ProgressBar(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), enabled_(::isatty(STDERR_FILENO) == 1 && total > 0) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && last_permille_ >= 0) std::fputs("\n", stderr);
}

void ProgressBar::update(std::size_t done) {
  if (!enabled_) return;
  const int permille = static_cast<int>(1000 * done / total_);
  if (permille == last_permille_) return;
  last_permille_ = permille;
  constexpr int kWidth = 40;
  const int filled = kWidth * permille / 1000;
  std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu", label_.c_str(), filled,
               "========================================", kWidth - filled, "", done, total_);
  std::fflush(stderr);
}

}  // namespace terramesh::cli
