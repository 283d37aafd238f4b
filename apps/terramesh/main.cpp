// terramesh: one CLI with subcommands; each lives in its own file.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli_args.h"
#include "commands.h"
#include "common/input_error.h"

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const std::vector<std::string>&);
};

const Command kCommands[] = {
    {"mesh", "incremental manifold mesh from a SLAM stream", terramesh::cli::runMesh},
    {"bench", "run modes on one stream; print the paper's Tables II and IV", terramesh::cli::runBench},
    {"eval", "mesh accuracy against a ground-truth mesh or KITTI LiDAR (depth, accuracy, completeness)",
     terramesh::cli::runEval},
    {"traverse", "traversability map of a finished mesh for a robot: PLY layers, Nav2 maps, GeoTIFF",
     terramesh::cli::runTraverse},
    {"traverse-eval", "traversability map against per-robot ground truth (precision, recall, F1) or the road under a path",
     terramesh::cli::runTraverseEval},
    {"view", "serve a run folder's web viewer on 127.0.0.1 (mesh layers, snapshots, timings, paths)",
     terramesh::cli::runView},
    {"plan", "drivable path on a traversability map (OMPL on the surface; exit 3 if unreachable)",
     terramesh::cli::runPlan},
    {"generate", "synthetic SLAM stream with ground truth (street, offroad, garage, hazards)", terramesh::cli::runGenerate},
    {"compare", "mesher vs OctoMap vs PCL surfaces on one stream: time, memory, accuracy, manifoldness, traversability, planning",
     terramesh::cli::runCompare},
    {"convert", "maps to and from PCL (PolygonMesh, PCD) and OctoMap (.bt), by extension", terramesh::cli::runConvert},
    {"pairs", "start/goal pairs on a labelled ground truth with whether the truth joins them for a robot",
     terramesh::cli::runPairs},
    {"tiles", "cut a stream into tiles meshed apart (plan), join the meshed tiles into a tiled map (merge)",
     terramesh::cli::runTiles},
};

void printUsage(std::ostream& out) {
  out << "usage: terramesh COMMAND [options]   (terramesh COMMAND --help for details)\n\ncommands:\n";
  for (const Command& command : kCommands) out << "  " << command.name << "\t" << command.summary << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    printUsage(std::cerr);
    return terramesh::cli::kExitBadInput;
  }
  const std::string name = argv[1];
  if (name == "-h" || name == "--help" || name == "help") {
    printUsage(std::cout);
    return terramesh::cli::kExitOk;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const Command& command : kCommands) {
    if (name != command.name) continue;
    try {
      return command.run(args);
    } catch (const terramesh::cli::UsageError& error) {
      std::cerr << "terramesh: " << error.what() << " (see terramesh " << name << " --help)\n";
      return terramesh::cli::kExitBadInput;
    } catch (const terramesh::InputError& error) {
      std::cerr << "terramesh: " << error.what() << '\n';
      return terramesh::cli::kExitBadInput;
    } catch (const std::invalid_argument& error) {
      std::cerr << "terramesh: " << error.what() << '\n';
      return terramesh::cli::kExitBadInput;
    } catch (const std::filesystem::filesystem_error& error) {
      // An output directory that cannot be created or written: the caller's to fix.
      std::cerr << "terramesh: cannot write " << error.path1() << ": " << error.code().message() << '\n';
      return terramesh::cli::kExitBadInput;
    } catch (const std::exception& error) {
      std::cerr << "terramesh: " << error.what() << '\n';
      return terramesh::cli::kExitFailure;
    }
  }
  std::cerr << "terramesh: unknown command \"" << name << "\"\n";
  printUsage(std::cerr);
  return terramesh::cli::kExitBadInput;
}
