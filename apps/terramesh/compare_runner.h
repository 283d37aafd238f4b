#pragma once

#include <functional>
#include <map>
#include <string>

namespace terramesh::cli {

/// Named results of a job run in a child process (values without tabs or newlines).
using JobResults = std::map<std::string, std::string>;

/// What a job run in its own process cost.
struct IsolatedRun {
  bool ok = false;
  std::string error;          ///< the child's exception message, or how it died
  JobResults results;
  double wall_seconds = 0;    ///< fork to exit, as seen by the parent
  double peak_rss_mb = 0;     ///< the child's peak resident set (getrusage via wait4: ru_maxrss)
  double start_rss_mb = 0;    ///< its resident set when the job started (VmRSS, inherited pages)
  double extraPeakMb() const { return peak_rss_mb - start_rss_mb; }
};

/// Runs `job` in a forked child process and measures its peak memory on its own: the child's
/// ru_maxrss counts only that process, so jobs run one after another do not see each other's
/// memory. The child shares the parent's pages at the fork (copy-on-write): start_rss_mb is
/// what it held then, and extraPeakMb() what the job added. The job's results or its exception
/// message come back through a pipe. Call only while the process runs a single thread.
/// @throw std::runtime_error if fork or pipe fail.
IsolatedRun runIsolated(const std::function<JobResults()>& job);

}  // namespace terramesh::cli
