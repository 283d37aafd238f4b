// Per-keyframe latency of the proposed mode on a SLAM stream, in thread CPU time, so that runs on
// a shared, loaded machine can be compared (`terramesh bench` reports wall-clock time). Prints the
// distribution of the update time, the work per keyframe (cells shrunk and grown, Steiner nodes),
// the share of each step (from the mesher's own step clock), and optionally writes the final mesh
// and checks the invariants, so a change of the pipeline can be judged on the map it ends with.
//
//   terramesh_latency_bench STREAM [--max-keyframes N] [--mesh-out FILE.ply]
//                           [--check-invariants-every K] [--slowest N] [--enclosing-radius-cells R]
//                           [--handle-min-rays N] [--floor]
//
// --floor: also the floor of an update on the same keyframes (update_floor.h), and the ratio of
// the medians.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <numeric>
#include <string>
#include <vector>

#include "bench_streams.h"
#include "datasets/slam_stream.h"
#include "datasets/stream_reader.h"
#include "mesher/mesh_io.h"
#include "mesher/mesher.h"
#include "update_floor.h"

namespace {

using namespace terramesh;

using bench::threadCpuSeconds;

double quantile(const std::vector<double>& values, double q) { return bench::percentile(values, q); }

double mean(const std::vector<double>& values, std::size_t from, std::size_t to) {
  if (to <= from) return 0.0;
  return std::accumulate(values.begin() + static_cast<std::ptrdiff_t>(from),
                         values.begin() + static_cast<std::ptrdiff_t>(to), 0.0) /
         static_cast<double>(to - from);
}

struct Options {
  std::string stream;
  std::size_t max_keyframes = 0;
  std::string mesh_out;
  std::size_t check_every = 0;
  std::size_t slowest = 5;
  int enclosing_radius_cells = 0;  ///< 0: the config's default
  int handle_min_rays = -1;  ///< -1: the mode's default
  bool floor = false;
};

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--max-keyframes") {
      options.max_keyframes = std::stoul(value());
    } else if (arg == "--mesh-out") {
      options.mesh_out = value();
    } else if (arg == "--check-invariants-every") {
      options.check_every = std::stoul(value());
    } else if (arg == "--enclosing-radius-cells") {
      options.enclosing_radius_cells = std::stoi(value());
    } else if (arg == "--handle-min-rays") {
      options.handle_min_rays = std::stoi(value());
    } else if (arg == "--floor") {
      options.floor = true;
    } else if (arg == "--slowest") {
      options.slowest = std::stoul(value());
    } else if (!arg.empty() && arg[0] != '-' && options.stream.empty()) {
      options.stream = arg;
    } else {
      throw std::invalid_argument("unknown argument " + arg);
    }
  }
  if (options.stream.empty()) throw std::invalid_argument("usage: terramesh_latency_bench STREAM [options]");
  return options;
}

struct KeyframeRow {
  std::size_t event = 0;
  double cpu_ms = 0;
  mesher::UpdateStats stats;
};

/// The floor on the same keyframes, its distribution and the ratio of the update's median to its.
void printFloor(const datasets::SlamStream& stream, const mesher::MesherConfig& config, std::size_t keyframes,
                double update_median_ms) {
  const bench::FloorRun floor = bench::measureFloor(stream, config, keyframes);
  const std::vector<double>& ms = floor.keyframe_ms;
  const double median = quantile(ms, 0.5);
  std::printf("floor CPU time per keyframe (ms): mean %.2f median %.2f p99 %.2f (points %zu, rays %zu, "
              "unresolved walks %zu)\n",
              mean(ms, 0, ms.size()), median, quantile(ms, 0.99), floor.points_inserted, floor.rays_walked,
              floor.walk_failures);
  std::printf("update / floor, medians: %.2f\n", median > 0 ? update_median_ms / median : 0.0);
}

int run(const Options& options) {
  const datasets::SlamStream stream = datasets::readAnyStream(options.stream);
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  config.metres_per_unit = stream.metres_per_unit;
  datasets::applyMeshingAdvice(stream, config);
  if (options.enclosing_radius_cells > 0) config.enclosing_radius_cells = options.enclosing_radius_cells;
  if (options.handle_min_rays >= 0) config.handle_min_rays = options.handle_min_rays;
  mesher::Mesher mesher(config);

  std::vector<KeyframeRow> rows;
  std::size_t invariant_failures = 0;
  for (std::size_t e = 0; e < stream.events.size(); ++e) {
    const bool keyframe = std::holds_alternative<mesher::Keyframe>(stream.events[e]);
    if (keyframe && options.max_keyframes > 0 && rows.size() == options.max_keyframes) break;
    const double start = threadCpuSeconds();
    const mesher::UpdateStats stats = datasets::applyEvent(mesher, stream.events[e]);
    const double cpu_ms = 1e3 * (threadCpuSeconds() - start);
    if (keyframe) rows.push_back({e, cpu_ms, stats});
    if (options.check_every > 0 && keyframe && rows.size() % options.check_every == 0) {
      const mesher::InvariantReport report = mesher.checkInvariants();
      if (!report.ok()) {
        ++invariant_failures;
        std::fprintf(stderr, "event %zu: invariants broken: %s\n", e, report.summary().c_str());
      }
    }
  }
  if (rows.empty()) throw std::invalid_argument("the stream has no keyframe");

  std::vector<double> ms;
  double shrunk = 0, grown = 0, steiner = 0, dropped = 0, deferred = 0, traced = 0, retraced = 0;
  mesher::StepTimes steps;
  for (const KeyframeRow& row : rows) {
    ms.push_back(row.cpu_ms);
    shrunk += static_cast<double>(row.stats.cells_shrunk);
    grown += static_cast<double>(row.stats.cells_grown);
    steiner += static_cast<double>(row.stats.steiner_points);
    dropped += static_cast<double>(row.stats.dropped_points);
    deferred += static_cast<double>(row.stats.deferred_points);
    traced += static_cast<double>(row.stats.rays_traced);
    retraced += static_cast<double>(row.stats.rays_retraced);
    steps.steiner_s += row.stats.time.steiner_s;
    steps.shrink_s += row.stats.time.shrink_s;
    steps.insertion_s += row.stats.time.insertion_s;
    steps.ray_tracing_s += row.stats.time.ray_tracing_s;
    steps.grow_s += row.stats.time.grow_s;
    steps.total_s += row.stats.time.total_s;
  }
  const double n = static_cast<double>(rows.size());
  const std::size_t decile = std::max<std::size_t>(1, rows.size() / 10);
  const double growth = mean(ms, rows.size() - decile, rows.size()) / mean(ms, 0, decile);
  std::printf("stream: %s\nkeyframes: %zu\n", options.stream.c_str(), rows.size());
  std::printf("update CPU time per keyframe (ms): mean %.2f median %.2f p90 %.2f p99 %.2f max %.2f "
              "last/first 10%% %.2f total %.2f s\n",
              mean(ms, 0, ms.size()), quantile(ms, 0.5), quantile(ms, 0.9), quantile(ms, 0.99),
              *std::max_element(ms.begin(), ms.end()), growth,
              1e-3 * std::accumulate(ms.begin(), ms.end(), 0.0));
  const double total = steps.total_s > 0 ? steps.total_s : 1.0;
  std::printf("share of the update (step clock): Steiner %.1f%% shrink %.1f%% insertion %.1f%% "
              "ray tracing %.1f%% grow %.1f%%\n",
              100 * steps.steiner_s / total, 100 * steps.shrink_s / total,
              100 * steps.insertion_s / total, 100 * steps.ray_tracing_s / total,
              100 * steps.grow_s / total);
  std::printf("per keyframe: cells shrunk %.1f grown %.1f Steiner nodes %.1f traced %.1f retraced "
              "%.1f dropped %.2f deferred %.2f\n",
              shrunk / n, grown / n, steiner / n, traced / n, retraced / n, dropped / n, deferred / n);
  std::vector<std::size_t> order(rows.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ms[a] > ms[b]; });
  for (std::size_t i = 0; i < std::min(options.slowest, order.size()); ++i) {
    const KeyframeRow& row = rows[order[i]];
    std::printf("slow: event %zu %.2f ms shrunk %zu grown %zu Steiner %zu new %zu moved %zu "
                "retraced %zu\n",
                row.event, row.cpu_ms, row.stats.cells_shrunk, row.stats.cells_grown,
                row.stats.steiner_points, row.stats.new_points, row.stats.moved_points,
                row.stats.rays_retraced);
  }
  if (options.floor) printFloor(stream, config, rows.size(), quantile(ms, 0.5));
  if (options.check_every > 0) std::printf("invariant checks failed: %zu\n", invariant_failures);
  if (!options.mesh_out.empty()) mesher::writePly(options.mesh_out, mesher.extractMesh());
  return invariant_failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "terramesh_latency_bench: %s\n", error.what());
    return 2;
  }
}
