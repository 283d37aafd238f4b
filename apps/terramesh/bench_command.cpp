// terramesh bench STREAM -o DIR: runs several modes on the same stream and reports the paper's
// Table II and Table IV, latency percentiles, growth over the run and memory, in one invocation.
// Figures are drawn from its CSVs by scripts/figures/bench_figures.py, whose command it prints.
#include <filesystem>
#include <iostream>
#include <sstream>

#include "bench_report.h"
#include "bench_run.h"
#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "datasets/stream_reader.h"
#include "input_options.h"
#include "machine_info.h"
#include "mesher_options.h"

namespace terramesh::cli {
namespace {

std::vector<mesher::MesherMode> parseModes(const std::string& list) {
  std::vector<mesher::MesherMode> modes;
  std::stringstream names(list);
  for (std::string name; std::getline(names, name, ',');) {
    const auto mode = mesher::parseMesherMode(name);
    if (!mode) throw UsageError("bench: unknown mode \"" + name + "\" in --modes");
    modes.push_back(*mode);
  }
  if (modes.empty()) throw UsageError("bench: --modes lists no mode");
  return modes;
}

}  // namespace

int runBench(const std::vector<std::string>& args) {
  ArgParser parser("bench");
  parser.positional("STREAM", "SLAM stream to run (any format terramesh mesh reads)")
      .option("--output", "DIR", "where the CSVs and the report go")
      .alias("-o", "--output")
      .option("--modes", "LIST", "comma-separated modes; the first is compared with the others",
              "proposed,romanoni15,litvinov13")
      .option("--camera-frames", "N", "camera frames the stream covers, for frame rates", "0")
      .option("--camera-rate-hz", "HZ", "camera frame rate, for the real-time factor", "10")
      .option("--max-keyframes", "N", "stop each run after N keyframes (0: all)", "0");
  declareInputOptions(parser);
  declareMesherOptions(parser);
  parser.parse(args);
  if (parser.helpRequested()) {
    std::cout << parser.usage();
    return kExitOk;
  }
  if (!parser.has("--output")) throw UsageError("bench: -o/--output DIR is required");
  const std::vector<mesher::MesherMode> modes = parseModes(parser.get("--modes"));
  const long camera_frames = parser.getInt("--camera-frames");
  const long max_keyframes = parser.getInt("--max-keyframes");
  const double rate = parser.getDouble("--camera-rate-hz");
  if (camera_frames < 0 || max_keyframes < 0 || !(rate > 0)) {
    throw UsageError("bench: --camera-frames and --max-keyframes must be >= 0, --camera-rate-hz > 0");
  }

  const std::filesystem::path input = parser.positionalValue("STREAM");
  const datasets::SlamStream stream = datasets::readAnyStream(input, streamReadOptionsFromArgs(parser));
  std::vector<mesher::MesherConfig> configs;
  for (mesher::MesherMode mode : modes) configs.push_back(mesherConfigFromArgs(parser, mode, stream));
  const std::filesystem::path output = parser.get("--output");
  std::filesystem::create_directories(output);

  BenchContext context;
  context.stream_name = input.string();
  context.machine = describeMachine();
  context.camera_frames = static_cast<std::size_t>(camera_frames);
  context.camera_rate_hz = rate;
  std::vector<BenchRun> runs;
  for (const mesher::MesherConfig& config : configs) {
    std::cerr << "bench: running " << mesher::toString(config.mode) << "...\n";
    runs.push_back(runModeIsolated(stream, config, output / mesher::toString(config.mode),
                                   max_keyframes > 0 ? static_cast<std::size_t>(max_keyframes)
                                                     : static_cast<std::size_t>(-1)));
  }
  std::ostringstream report;
  printBenchReport(report, context, runs);
  writeBenchIndex(output, context, runs);
  report << "\nfigures (from the terramesh source tree): " << benchFiguresCommand(output) << '\n';
  writeFileAtomically(output / "report.txt", report.str());
  std::cout << report.str();
  return kExitOk;
}

}  // namespace terramesh::cli
