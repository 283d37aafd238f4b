#include "bench_report.h"

#include <algorithm>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "common/atomic_file.h"

namespace terramesh::cli {
namespace {

struct StepColumn {
  const char* column;
  const char* title;
};

constexpr StepColumn kSteps[] = {{"time_steiner_s", "Steiner"},        {"time_shrink_s", "Shrink"},
                                 {"time_insertion_s", "Insertion"},   {"time_ray_tracing_s", "Ray tracing"},
                                 {"time_grow_s", "Grow"},              {"time_total_s", "Total"}};

double sum(const BenchRun& run, const char* column) {
  double total = 0;
  for (const CsvRow& row : run.keyframes) total += row.at(column);
  return total;
}

double mean(const BenchRun& run, const char* column) {
  return run.keyframes.empty() ? 0.0 : sum(run, column) / static_cast<double>(run.keyframes.size());
}

std::vector<double> column(const BenchRun& run, const char* name) {
  std::vector<double> values;
  values.reserve(run.keyframes.size());
  for (const CsvRow& row : run.keyframes) values.push_back(row.at(name));
  return values;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = p / 100.0 * static_cast<double>(values.size() - 1);
  const auto low = static_cast<std::size_t>(std::floor(rank));
  const auto high = std::min(low + 1, values.size() - 1);
  return values[low] + (rank - static_cast<double>(low)) * (values[high] - values[low]);
}

/// Mean of the last 10% of keyframes over the mean of the first 10%.
double growthRatio(const std::vector<double>& values) {
  const std::size_t tenth = std::max<std::size_t>(1, values.size() / 10);
  if (values.size() < 2 * tenth) return 0.0;
  const double first = std::accumulate(values.begin(), values.begin() + static_cast<long>(tenth), 0.0);
  const double last = std::accumulate(values.end() - static_cast<long>(tenth), values.end(), 0.0);
  return first > 0 ? last / first : 0.0;
}

/// A CSV field, quoted (RFC 4180) if it holds a comma, a quote or a line break.
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + '"';
}

/// Quotes `text` for a POSIX shell if it holds anything but safe characters.
std::string shellWord(const std::string& text) {
  const bool safe = !text.empty() && text.find_first_not_of(
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                         "0123456789_-./+:=@%,") == std::string::npos;
  if (safe) return text;
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + '\'';
}

void line(std::ostream& out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void line(std::ostream& out, const char* format, ...) {
  char buffer[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  out << buffer << '\n';
}

}  // namespace

void printBenchReport(std::ostream& out, const BenchContext& context,
                      const std::vector<BenchRun>& runs) {
  line(out, "stream: %s", context.stream_name.c_str());
  line(out, "machine: %s; one thread, Release build", context.machine.c_str());
  if (runs.empty()) return;
  const std::size_t keyframes = runs.front().keyframes.size();
  line(out, "keyframes: %zu%s", keyframes,
       context.camera_frames ? (", camera frames: " + std::to_string(context.camera_frames)).c_str() : "");

  out << "\nTable II: time per step summed over the run (s)\n";
  line(out, "%-12s %9s %9s %9s %11s %9s %9s %10s %10s", "mode", "Steiner", "Shrink", "Insertion",
       "Ray tracing", "Grow", "Total", "kf/s", context.camera_frames ? "frames/s" : "");
  for (const BenchRun& run : runs) {
    const double total = sum(run, "time_total_s");
    char frames[32] = "";
    if (context.camera_frames && total > 0) {
      std::snprintf(frames, sizeof(frames), "%.1f", static_cast<double>(context.camera_frames) / total);
    }
    line(out, "%-12s %9.3f %9.3f %9.3f %11.3f %9.3f %9.3f %10.1f %10s", run.mode.c_str(),
         sum(run, "time_steiner_s"), sum(run, "time_shrink_s"), sum(run, "time_insertion_s"),
         sum(run, "time_ray_tracing_s"), sum(run, "time_grow_s"), total,
         total > 0 ? static_cast<double>(run.keyframes.size()) / total : 0.0, frames);
  }
  const BenchRun& first = runs.front();
  for (std::size_t i = 1; i < runs.size(); ++i) {
    out << "speed-up of " << first.mode << " over " << runs[i].mode << ":";
    for (const StepColumn& step : kSteps) {
      const double mine = sum(first, step.column);
      char cell[64];
      std::snprintf(cell, sizeof(cell), " %s %.1fx", step.title, mine > 0 ? sum(runs[i], step.column) / mine : 0.0);
      out << cell;
    }
    out << '\n';
  }
  if (context.camera_frames) {
    for (const BenchRun& run : runs) {
      const double total = sum(run, "time_total_s");
      const double stream_seconds = static_cast<double>(context.camera_frames) / context.camera_rate_hz;
      line(out, "%s runs at %.1fx real time (camera at %.0f Hz)", run.mode.c_str(),
           total > 0 ? stream_seconds / total : 0.0, context.camera_rate_hz);
    }
  }

  out << "\nPer-keyframe update time (ms)\n";
  line(out, "%-12s %8s %8s %8s %8s %8s %14s", "mode", "mean", "median", "p90", "p99", "max",
       "last/first 10%");
  for (const BenchRun& run : runs) {
    const std::vector<double> totals = column(run, "time_total_s");
    line(out, "%-12s %8.2f %8.2f %8.2f %8.2f %8.2f %14.2f", run.mode.c_str(),
         1e3 * mean(run, "time_total_s"), 1e3 * percentile(totals, 50), 1e3 * percentile(totals, 90),
         1e3 * percentile(totals, 99), 1e3 * percentile(totals, 100), growthRatio(totals));
  }

  out << "\nTable IV: per-keyframe averages\n";
  line(out, "%-12s %7s %7s %9s %9s %8s %8s %8s %8s %8s", "mode", "moved", "new", "shrunk",
       "Steiner", "dropped", "traced", "retraced", "untraced", "cache");
  for (const BenchRun& run : runs) {
    const double lookups = sum(run, "cache_lookups");
    char cache[16] = "-";
    if (lookups > 0) std::snprintf(cache, sizeof(cache), "%.1f%%", 100.0 * sum(run, "cache_hits") / lookups);
    line(out, "%-12s %7.1f %7.1f %9.1f %9.1f %8.2f %8.1f %8.1f %8.1f %8s", run.mode.c_str(),
         mean(run, "moved_points"), mean(run, "new_points"), mean(run, "cells_shrunk"),
         mean(run, "steiner_cells_shrunk"), mean(run, "dropped_points"), mean(run, "rays_traced"),
         mean(run, "rays_retraced"), mean(run, "rays_untraced"), cache);
  }

  out << "\nMemory at the end of the run\n";
  line(out, "%-12s %12s %12s %12s %12s %12s %14s", "mode", "points", "rays", "map MiB", "B/ray",
       "B/point", "peak RSS MiB");
  for (const BenchRun& run : runs) {
    const auto get = [&run](const char* key) {
      const auto it = run.summary.find(key);
      return it == run.summary.end() ? 0.0 : it->second;
    };
    const double points = get("points");
    const double rays = get("rays");
    const double point_side = get("triangulation_bytes") + get("point_bytes") + get("index_bytes");
    line(out, "%-12s %12.0f %12.0f %12.1f %12.0f %12.0f %14.1f", run.mode.c_str(), points, rays,
         get("total_bytes") / (1024.0 * 1024.0), rays > 0 ? get("ray_bytes") / rays : 0.0,
         points > 0 ? point_side / points : 0.0, (get("peak_rss_kib") - get("rss_before_kib")) / 1024.0);
  }
  out << "(B/ray: ray records, cell paths and per-cell ray lists; B/point: triangulation, point "
         "records and indices; peak RSS: growth of the process while meshing)\n";
}

std::filesystem::path writeBenchIndex(const std::filesystem::path& dir, const BenchContext& context,
                                      const std::vector<BenchRun>& runs) {
  std::ostringstream csv;
  csv << "mode,stream,keyframes_csv,summary\n";
  for (const BenchRun& run : runs) {
    csv << csvField(run.mode) << ',' << csvField(context.stream_name) << ','
        << csvField(run.mode + "/keyframes.csv") << ',' << csvField(run.mode + "/summary.txt") << '\n';
  }
  const std::filesystem::path path = dir / "runs.csv";
  writeFileAtomically(path, csv.str());
  return path;
}

std::string benchFiguresCommand(const std::filesystem::path& dir) {
  return "scripts/figures/bench_figures.py " + shellWord(dir.string());
}

}  // namespace terramesh::cli
