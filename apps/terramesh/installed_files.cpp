#include "installed_files.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <thread>

extern char** environ;

namespace terramesh::cli {
namespace {

namespace fs = std::filesystem;

/// posix_spawn(p) of argv, stdout (and with `all`, stderr) to /dev/null when `silence`.
pid_t spawn(const std::vector<std::string>& argv, bool search_path, bool silence, bool all) {
  if (argv.empty()) return -1;
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (silence) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    if (all) posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  }
  pid_t pid = -1;
  const int error = search_path ? posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ)
                                : posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

}  // namespace

fs::path shippedFolder(const std::string& subdir, const std::string& probe) {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (error) return {};
  const fs::path bin = exe.parent_path();
  for (const fs::path& root : {bin.parent_path(), bin.parent_path().parent_path()}) {
    const fs::path folder = root / subdir;
    if (fs::is_regular_file(folder / probe, error)) return folder;
  }
  return {};
}

int runProgram(const std::vector<std::string>& argv, bool quiet) {
  const pid_t pid = spawn(argv, false, quiet, false);
  if (pid < 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool startProgram(const std::vector<std::string>& argv) {
  const pid_t pid = spawn(argv, true, true, true);
  if (pid < 0) return false;
  std::thread([pid] {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  }).detach();
  return true;
}

}  // namespace terramesh::cli
