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
#include "common/machine_info.h"
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
  CLI::App app{"run modes on one stream; print the paper's Tables II and IV", "terramesh bench"};
  app.option_defaults()->always_capture_default();
  std::string stream_file, output_dir, mode_list = "proposed,romanoni15,litvinov13";
  long camera_frames = 0, max_keyframes = 0;
  double rate = 10;
  InputOptions input_options;
  MesherOptions mesher_options;
  app.add_option("STREAM", stream_file, "SLAM stream to run (any format terramesh mesh reads)")->required();
  app.add_option("-o,--output", output_dir, "where the CSVs and the report go")->option_text("DIR");
  app.add_option("--modes", mode_list, "comma-separated modes; the first is compared with the others");
  app.add_option("--camera-frames", camera_frames, "camera frames the stream covers, for frame rates");
  app.add_option("--camera-rate-hz", rate, "camera frame rate, for the real-time factor");
  app.add_option("--max-keyframes", max_keyframes, "stop each run after N keyframes (0: all)");
  addInputOptions(app, input_options);
  addMesherOptions(app, mesher_options);
  if (!parseCommandLine(app, args)) return kExitOk;
  if (output_dir.empty()) throw UsageError("bench: -o/--output DIR is required");
  const std::vector<mesher::MesherMode> modes = parseModes(mode_list);
  if (camera_frames < 0 || max_keyframes < 0 || !(rate > 0)) {
    throw UsageError("bench: --camera-frames and --max-keyframes must be >= 0, --camera-rate-hz > 0");
  }

  const std::filesystem::path input = stream_file;
  const datasets::SlamStream stream = datasets::readAnyStream(input, streamReadOptionsFrom(input_options));
  printReaderNotes(std::cerr, stream);
  std::vector<mesher::MesherConfig> configs;
  for (mesher::MesherMode mode : modes) configs.push_back(mesherConfigFrom(mesher_options, mode, stream));
  const std::filesystem::path output = output_dir;
  std::filesystem::create_directories(output);

  BenchContext context;
  context.stream_name = input.string();
  context.machine = terramesh::describeMachine();
  context.camera_frames = static_cast<std::size_t>(camera_frames);
  context.camera_rate_hz = rate;
  std::vector<BenchRun> runs;
  for (const mesher::MesherConfig& config : configs) {
    std::cerr << "bench: running " << mesher::toString(config.mode()) << "...\n";
    runs.push_back(runModeIsolated(stream, config, output / mesher::toString(config.mode()),
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
