#pragma once

#include <string>
#include <vector>

namespace terramesh::cli {

/// Exit codes shared by all subcommands.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;     ///< the job ran and failed (e.g. cannot write output)
inline constexpr int kExitBadInput = 2;    ///< usage error or unreadable/invalid input
inline constexpr int kExitUnreachable = 3; ///< plan: no path can exist (or no walkable face near start/goal)

/// Each subcommand: parses its own arguments, returns an exit code. Errors are reported by
/// throwing (UsageError, InputError, std::exception); main prints them on one line.
int runMesh(const std::vector<std::string>& args);
int runGenerate(const std::vector<std::string>& args);
int runBench(const std::vector<std::string>& args);
int runEval(const std::vector<std::string>& args);
int runTraverse(const std::vector<std::string>& args);
int runTraverseEval(const std::vector<std::string>& args);
int runView(const std::vector<std::string>& args);
int runPlan(const std::vector<std::string>& args);
int runCompare(const std::vector<std::string>& args);
int runConvert(const std::vector<std::string>& args);
int runPairs(const std::vector<std::string>& args);
int runTiles(const std::vector<std::string>& args);

}  // namespace terramesh::cli
