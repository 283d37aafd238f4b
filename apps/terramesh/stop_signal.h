#pragma once

// SIGINT/SIGTERM as a polite stop request for long runs (`terramesh mesh`): the first signal sets
// a flag that the run polls between updates; it finishes the update in progress, writes its
// outputs and exits with 128 + the signal number (130 for SIGINT, 143 for SIGTERM). A second
// signal while it is finishing ends the process at once (the default action).

namespace terramesh::cli {

/// Exit code of a run stopped by `signal`: 128 + signal (the shell's convention).
constexpr int exitCodeForSignal(int signal) { return 128 + signal; }

/// Installs the SIGINT and SIGTERM handlers for its lifetime and restores the previous ones on
/// destruction. One at a time.
class StopSignalScope {
 public:
  StopSignalScope();
  ~StopSignalScope();
  StopSignalScope(const StopSignalScope&) = delete;
  StopSignalScope& operator=(const StopSignalScope&) = delete;

  /// The first SIGINT or SIGTERM received since construction, or 0. Async-signal-safe to set.
  static int requested();
};

}  // namespace terramesh::cli
