#include "bench_run.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "mesher/mesher.h"
#include "stats_table.h"

namespace terramesh::cli {
namespace {

/// Resident and peak resident memory of this process, KiB (VmRSS, VmHWM of /proc/self/status).
std::pair<long, long> residentKib() {
  std::ifstream status("/proc/self/status");
  long rss = 0;
  long peak = 0;
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) rss = std::strtol(line.c_str() + 6, nullptr, 10);
    if (line.rfind("VmHWM:", 0) == 0) peak = std::strtol(line.c_str() + 6, nullptr, 10);
  }
  return {rss, peak};
}

/// The child's work: run the stream, write the CSV and the end-of-run sizes.
void runInChild(const datasets::SlamStream& stream, const mesher::MesherConfig& config,
                const std::filesystem::path& dir, std::size_t max_keyframes) {
  const long rss_before = residentKib().first;
  mesher::Mesher mesher(config);
  std::ostringstream csv;
  csv << updateCsvHeader() << '\n';
  std::size_t keyframes = 0;
  std::size_t peak_bytes = 0;
  for (std::size_t i = 0; i < stream.events.size(); ++i) {
    const auto& event = stream.events[i];
    const bool is_keyframe = std::holds_alternative<mesher::Keyframe>(event);
    if (is_keyframe && keyframes == max_keyframes) break;
    const mesher::UpdateStats stats = datasets::applyEvent(mesher, event);
    const mesher::MapSize size = mesher.size();
    peak_bytes = std::max(peak_bytes, size.totalBytes());
    std::uint64_t id = 0;
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) id = keyframe->id.value;
    csv << updateCsvRow(i, is_keyframe ? "keyframe" : "removal", id, stats, size) << '\n';
    keyframes += is_keyframe;
  }
  const mesher::MapSize size = mesher.size();
  std::ostringstream summary;
  summary << "keyframes " << keyframes << "\npoints " << size.inserted_points << "\nrays "
          << size.rays << "\nray_crossings " << size.ray_crossings << "\ncells " << size.cells
          << "\noutside_cells " << size.outside_cells << "\nsteiner_vertices "
          << size.steiner_vertices << "\ntriangulation_bytes " << size.triangulation_bytes
          << "\nray_bytes " << size.ray_bytes << "\npoint_bytes " << size.point_bytes
          << "\nindex_bytes " << size.index_bytes << "\ntotal_bytes " << size.totalBytes()
          << "\npeak_map_bytes " << peak_bytes << "\nrss_before_kib " << rss_before
          << "\npeak_rss_kib " << residentKib().second << '\n';
  writeFileAtomically(dir / "keyframes.csv", csv.str());
  writeFileAtomically(dir / "summary.txt", summary.str());
}

std::vector<CsvRow> readKeyframeRows(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path.string() + ": empty");
  std::vector<std::string> columns;
  for (std::stringstream header(line); std::getline(header, line, ',');) columns.push_back(line);
  std::vector<CsvRow> rows;
  std::string text;
  while (std::getline(in, text)) {
    std::stringstream fields(text);
    CsvRow row;
    bool keyframe = false;
    std::string field;
    for (std::size_t c = 0; c < columns.size() && std::getline(fields, field, ','); ++c) {
      if (columns[c] == "kind") {
        keyframe = field == "keyframe";
        continue;
      }
      row[columns[c]] = std::strtod(field.c_str(), nullptr);
    }
    if (keyframe) rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

BenchRun runModeIsolated(const datasets::SlamStream& stream, const mesher::MesherConfig& config,
                         const std::filesystem::path& dir, std::size_t max_keyframes) {
  std::filesystem::create_directories(dir);
  std::fflush(nullptr);
  const pid_t child = ::fork();
  if (child < 0) throw std::runtime_error("bench: fork failed");
  if (child == 0) {
    int code = 0;
    try {
      runInChild(stream, config, dir, max_keyframes);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "terramesh: bench (%s): %s\n", mesher::toString(config.mode()), error.what());
      code = 1;
    }
    std::fflush(nullptr);
    ::_exit(code);
  }
  int status = 0;
  struct rusage usage {};
  if (::wait4(child, &status, 0, &usage) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error(std::string("bench: the run of mode ") + mesher::toString(config.mode()) +
                             " failed");
  }
  BenchRun run;
  run.mode = mesher::toString(config.mode());
  run.peak_rss_kib = usage.ru_maxrss;
  run.keyframes = readKeyframeRows(dir / "keyframes.csv");
  std::ifstream summary(dir / "summary.txt");
  std::string key;
  double value = 0;
  while (summary >> key >> value) run.summary[key] = value;
  return run;
}

}  // namespace terramesh::cli
