#include "compare_runner.h"

#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "process_memory.h"

namespace terramesh::cli {

namespace {

void writeAll(int fd, const std::string& text) {
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    written += static_cast<std::size_t>(n);
  }
}

std::string clean(std::string text) {
  for (char& c : text) {
    if (c == '\t' || c == '\n') c = ' ';
  }
  return text;
}

}  // namespace

IsolatedRun runIsolated(const std::function<JobResults()>& job) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const auto started = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    std::ostringstream out;
    out << "start_rss_mb\t" << residentMib() << '\n';
    int code = 0;
    try {
      for (const auto& [key, value] : job()) out << clean(key) << '\t' << clean(value) << '\n';
    } catch (const std::exception& error) {
      out << "error\t" << clean(error.what()) << '\n';
      code = 1;
    }
    writeAll(fds[1], out.str());
    ::close(fds[1]);
    ::_exit(code);
  }
  ::close(fds[1]);
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  struct rusage usage {};
  while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  IsolatedRun run;
  run.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  run.peak_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t tab = line.find('\t');
    if (tab == std::string::npos) continue;
    run.results[line.substr(0, tab)] = line.substr(tab + 1);
  }
  if (const auto found = run.results.find("start_rss_mb"); found != run.results.end()) {
    run.start_rss_mb = std::stod(found->second);
    run.results.erase(found);
  }
  if (const auto found = run.results.find("error"); found != run.results.end()) {
    run.error = found->second;
    run.results.erase(found);
  }
  run.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!run.ok && run.error.empty()) {
    run.error = WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status))
                                    : "exit status " + std::to_string(WEXITSTATUS(status));
  }
  return run;
}

}  // namespace terramesh::cli
