#pragma once

// Where the CLI finds the files it ships beside itself (the viewer bundle, the figure scripts), and
// how it runs another program: by argument vector, never through a shell.
#include <filesystem>
#include <string>
#include <vector>

namespace terramesh::cli {

/// A folder the CLI ships, found relative to the running executable: `<prefix>/<subdir>` of an
/// installation (bin/../<subdir>), else `<build>/<subdir>` of the build tree (apps/terramesh/../../
/// <subdir>), the first that holds `probe`. Empty if neither does.
std::filesystem::path shippedFolder(const std::string& subdir, const std::string& probe);

/// Runs argv[0] (a path) with the arguments argv[1..], without a shell, and waits for it. With
/// `quiet`, its standard output goes to /dev/null. Returns its exit status; -1 if it could not be
/// started or did not exit normally.
int runProgram(const std::vector<std::string>& argv, bool quiet);

/// Starts argv[0] (searched on PATH) with the arguments argv[1..], without a shell and without
/// waiting (reaped in the background); its output goes to /dev/null. False if it could not start.
bool startProgram(const std::vector<std::string>& argv);

}  // namespace terramesh::cli
