// terramesh_soak: long runs of the mesher with invariant checks and memory samples.
//
//   terramesh_soak [--mode M] [--keyframes N] [--window W] [--check-every K] [--seed S]
//                  [--history-bytes B]
//       A randomised stream (tests/reliability/random_stream.h): moving, culled and outlier
//       points, corrected and removed keyframes, a sliding window of W keyframes (0: none).
//       checkInvariants() every K updates and at the end; the final surface must be a closed
//       manifold. Exit 0 if every check was clean, 1 otherwise, 2 for bad options.
//   terramesh_soak --stream FILE [--mode M] [--sample-every K] [--metres-per-unit U] [--history-bytes B]
//       Replays a stream file, printing the map's size and accounting, and the process's
//       resident memory, every K keyframes (CSV on stdout).
//   --history-bytes B sets MesherConfig::surface_history_max_bytes (default: the config's).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <variant>

#include "datasets/stream_reader.h"
#include "mesher/mesher.h"
#include "random_stream.h"

namespace {

using terramesh::mesher::MapSize;
using terramesh::mesher::Mesher;
using terramesh::mesher::MesherConfig;
using terramesh::mesher::MesherMode;
using terramesh::mesher::UpdateStats;

struct Options {
  MesherMode mode = MesherMode::kProposed;
  std::size_t keyframes = 10000;
  std::size_t window = 30;
  std::size_t check_every = 50;
  std::uint64_t seed = 1;
  std::string stream;
  std::size_t sample_every = 50;
  double metres_per_unit = 0;  // 0: the stream's own
  std::size_t history_bytes = 0;  // 0: MesherConfig's default surface_history_max_bytes
};

/// Resident and peak resident memory of this process, MiB (VmRSS and VmHWM).
std::pair<double, double> residentMib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  double rss = 0, peak = 0;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) rss = std::strtod(line.c_str() + 6, nullptr) / 1024.0;
    if (line.rfind("VmHWM:", 0) == 0) peak = std::strtod(line.c_str() + 6, nullptr) / 1024.0;
  }
  return {rss, peak};
}

double mib(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

/// CPU time of this process so far (user + system), s: what the run costs on a shared machine,
/// where wall time depends on the load.
double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

void printHeader() {
  std::printf("keyframes_sent,keyframes,points,inserted_points,cells,rays,ray_crossings,"
              "triangulation_mib,ray_mib,point_mib,index_mib,map_mib,rss_mib,peak_rss_mib,"
              "elapsed_s,cpu_s,check_cpu_s\n");
}

/// One CSV row; `check_cpu_s` is the CPU time spent in checkInvariants() so far.
void printSample(std::size_t sent, const MapSize& s, double elapsed_s, double check_cpu_s = 0) {
  const auto [rss, peak] = residentMib();
  std::printf("%zu,%zu,%zu,%zu,%zu,%zu,%zu,%.2f,%.2f,%.2f,%.2f,%.2f,%.1f,%.1f,%.1f,%.2f,%.3f\n", sent, s.keyframes,
              s.points, s.inserted_points, s.cells, s.rays, s.ray_crossings, mib(s.triangulation_bytes),
              mib(s.ray_bytes), mib(s.point_bytes), mib(s.index_bytes), mib(s.totalBytes()), rss, peak,
              elapsed_s, cpuSeconds(), check_cpu_s);
  std::fflush(stdout);
}

bool parse(int argc, char** argv, Options& options) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) {
      std::cerr << "terramesh_soak: " << arg << " needs a value (or is unknown)\n";
      return false;
    }
    const std::string value = argv[++i];
    char* end = nullptr;
    const unsigned long long number = std::strtoull(value.c_str(), &end, 10);
    const bool numeric = end != value.c_str() && *end == '\0';
    if (arg == "--mode") {
      const auto mode = terramesh::mesher::parseMesherMode(value);
      if (!mode) {
        std::cerr << "terramesh_soak: --mode: expected proposed, litvinov13 or romanoni15\n";
        return false;
      }
      options.mode = *mode;
    } else if (arg == "--stream") {
      options.stream = value;
    } else if (arg == "--metres-per-unit") {
      options.metres_per_unit = std::strtod(value.c_str(), nullptr);
    } else if (!numeric) {
      std::cerr << "terramesh_soak: " << arg << ": expected a non-negative integer or unknown option\n";
      return false;
    } else if (arg == "--keyframes") {
      options.keyframes = number;
    } else if (arg == "--window") {
      options.window = number;
    } else if (arg == "--check-every") {
      options.check_every = number == 0 ? 1 : number;
    } else if (arg == "--sample-every") {
      options.sample_every = number == 0 ? 1 : number;
    } else if (arg == "--history-bytes") {
      options.history_bytes = number;
    } else if (arg == "--seed") {
      options.seed = number;
    } else {
      std::cerr << "terramesh_soak: unknown option " << arg << "\n";
      return false;
    }
  }
  return true;
}

int replayStream(const Options& options) {
  const terramesh::datasets::SlamStream stream = terramesh::datasets::readAnyStream(options.stream);
  MesherConfig config = MesherConfig::forMode(options.mode);
  config.metres_per_unit = options.metres_per_unit > 0 ? options.metres_per_unit : stream.metres_per_unit;
  if (options.history_bytes > 0) config.surface_history_max_bytes = options.history_bytes;
  if (!config.incremental_steiner_grid) {
    std::cerr << "terramesh_soak: --stream runs the proposed mode only\n";
    return 2;
  }
  Mesher mesher(config);
  const auto [rss_stream, peak_stream] = residentMib();
  std::fprintf(stderr, "stream read: %zu events, rss %.1f MiB\n", stream.events.size(), rss_stream);
  (void)peak_stream;
  printHeader();
  const auto start = std::chrono::steady_clock::now();
  std::size_t sent = 0;
  MapSize peak_size;
  for (const auto& event : stream.events) {
    if (const auto* keyframe = std::get_if<terramesh::mesher::Keyframe>(&event)) {
      mesher.integrateKeyframe(*keyframe);
      ++sent;
    } else if (const auto* removal = std::get_if<terramesh::datasets::PointRemoval>(&event)) {
      mesher.removePoints(removal->points);
    } else {
      mesher.removeKeyframe(std::get<terramesh::datasets::KeyframeRemoval>(event).keyframe);
    }
    if (sent % options.sample_every == 0 || &event == &stream.events.back()) {
      const MapSize size = mesher.size();
      if (size.totalBytes() > peak_size.totalBytes()) peak_size = size;
      printSample(sent, size, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
  }
  const MapSize end = mesher.size();
  const auto [rss, peak] = residentMib();
  std::fprintf(stderr,
               "end: %zu points inserted, %zu rays, %.1f MiB map (%.0f B/ray, %.0f B/point by the accounting); "
               "rss %.1f MiB, peak rss %.1f MiB (%.1f MiB above the stream in memory)\n",
               end.inserted_points, end.rays, mib(end.totalBytes()),
               end.rays ? static_cast<double>(end.ray_bytes) / static_cast<double>(end.rays) : 0.0,
               end.inserted_points ? static_cast<double>(end.totalBytes() - end.ray_bytes) /
                                         static_cast<double>(end.inserted_points)
                                   : 0.0,
               rss, peak, peak - rss_stream);
  return 0;
}

int soak(const Options& options) {
  terramesh::test::RandomStreamConfig stream_config;
  stream_config.seed = options.seed;
  stream_config.keyframes = options.keyframes;
  stream_config.window = options.window;
  terramesh::test::RandomStream stream(stream_config);
  MesherConfig config = MesherConfig::forMode(options.mode);
  config.steiner_step_m = 4.0;
  if (!config.incremental_steiner_grid) config.fixed_grid_bounds_W = terramesh::test::RandomStream::bounds();
  if (options.history_bytes > 0) config.surface_history_max_bytes = options.history_bytes;
  Mesher mesher(config);
  printHeader();
  const auto start = std::chrono::steady_clock::now();
  std::size_t updates = 0, checks = 0, failed_checks = 0;
  double check_cpu_s = 0;
  UpdateStats totals;
  terramesh::test::StreamEvent event;
  auto check = [&] {
    ++checks;
    const double check_start = cpuSeconds();
    const auto report = mesher.checkInvariants();
    check_cpu_s += cpuSeconds() - check_start;
    if (!report.ok()) {
      ++failed_checks;
      std::fprintf(stderr, "update %zu (keyframe %zu): %s\n", updates, stream.counts().keyframes,
                   report.summary().c_str());
    }
    printSample(stream.counts().keyframes, mesher.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), check_cpu_s);
  };
  while (stream.next(event)) {
    switch (event.kind) {
      case terramesh::test::StreamEvent::Kind::kKeyframe:
        totals += mesher.integrateKeyframe(event.keyframe);
        break;
      case terramesh::test::StreamEvent::Kind::kRemovePoints:
        totals += mesher.removePoints(event.points);
        break;
      case terramesh::test::StreamEvent::Kind::kRemoveKeyframe:
        totals += mesher.removeKeyframe(event.removed);
        break;
    }
    if (++updates % options.check_every == 0) check();
  }
  check();
  const auto topology = terramesh::mesher::analyzeTopology(mesher.extractMesh());
  const auto& c = stream.counts();
  const auto [rss, peak] = residentMib();
  std::fprintf(stderr,
               "mode %s: %zu keyframes, %zu corrections, %zu keyframe removals, %zu points culled, "
               "%zu observations (%zu moved, %zu outliers, %zu duplicates); %zu updates, "
               "%zu invariant checks, %zu failed; walk fallbacks %zu, walk failures %zu, walks cut "
               "by the step bound %zu; final surface %s (%zu faces); peak rss %.1f MiB; %.1f s wall, "
               "%.1f s CPU (%.1f s in checks)\n",
               terramesh::mesher::toString(options.mode), c.keyframes, c.corrections, c.keyframe_removals,
               c.point_removals, c.observations, c.moved_observations, c.outliers, c.duplicates, updates,
               checks, failed_checks, totals.walk_fallbacks, totals.walk_failures,
               totals.walk_step_limit_hits, topology.isClosedManifold() ? "closed manifold" : "NOT a closed manifold",
               topology.faces, peak,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), cpuSeconds(),
               check_cpu_s);
  (void)rss;
  return failed_checks == 0 && topology.isClosedManifold() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, options)) return 2;
  try {
    return options.stream.empty() ? soak(options) : replayStream(options);
  } catch (const std::exception& error) {
    std::cerr << "terramesh_soak: " << error.what() << "\n";
    return 2;
  }
}
