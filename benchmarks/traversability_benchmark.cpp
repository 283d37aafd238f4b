// Google Benchmark of terramesh::traversability on a generated KITTI-like street stream: the
// per-keyframe layer update (TraversabilityMap::apply of Mesher::changesSince) while meshing, its
// ratio to a full recomputation of the same map, and the faces per second of a full computation.
// Meshing and stream generation are excluded from the timings. Streams: the built-in 200 m street,
// plus the stream files listed in TERRAMESH_TRAV_STREAMS (':'-separated, e.g. DIR/stream.tmstream
// of `terramesh generate`). Counters: update median/p99 (wall and thread CPU), ratio to a full
// recomputation, delta faces and real changes (churn netted out) per keyframe, full faces/s, and
// the CPU time of the mesher's two queries that TraversabilityMap::update adds to apply.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <variant>

#include "bench_streams.h"
#include "common/machine_info.h"
#include "datasets/stream_reader.h"
#include "mesher/mesher.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

const std::filesystem::path kRobots = std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

using bench::BenchStream;
using bench::builtinStreet;
using bench::fileStream;
using bench::percentile;
using bench::threadCpuSeconds;

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

/// Meshes the whole stream; after every keyframe applies the delta to the layers (timed); every
/// `full_every` keyframes also recomputes the whole map from the mesher's faces (timed).
void BM_LayersWhileMeshing(benchmark::State& state, const BenchStream* s, const std::string& robot) {
  const RobotProfile profile = loadRobotProfile(kRobots / (robot + ".yaml"));
  MapFrame frame;
  frame.up_W = s->up_W;
  const int full_every = 5;
  std::vector<double> delta_sizes, incremental_s, full_s, ratio, faces_per_s;
  std::vector<double> incremental_cpu_s, full_cpu_s, ratio_cpu, faces_per_cpu_s;
  std::vector<double> query_cpu_s;  // the mesher's changesSince + facesAround (TraversabilityMap::update)
  std::size_t recomputed = 0, updates = 0, faces_end = 0, delta_faces = 0, real_faces = 0;
  for (auto _ : state) {
    mesher::Mesher mesher{mesher::MesherConfig{}};
    TraversabilityMap map(profile, frame);
    int keyframes = 0;
    for (const datasets::StreamEvent& event : s->stream.events) {
      const std::uint64_t revision = mesher.revision();
      datasets::applyEvent(mesher, event);
      if (!std::holds_alternative<mesher::Keyframe>(event)) continue;
      const double query_cpu_start = threadCpuSeconds();
      const mesher::SurfaceDelta delta = mesher.changesSince(revision);
      const std::vector<mesher::SurfaceFace> around = mesher.facesAround(delta.touched_vertices);
      query_cpu_s.push_back(threadCpuSeconds() - query_cpu_start);
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = threadCpuSeconds();
      const LayerUpdateStats stats = map.apply(delta, around);
      const double t = seconds(start), cpu = threadCpuSeconds() - cpu_start;
      incremental_s.push_back(t);
      incremental_cpu_s.push_back(cpu);
      delta_faces += delta.added.size() + delta.removed.size();
      delta_sizes.push_back(static_cast<double>(delta.added.size() + delta.removed.size()));
      real_faces += stats.faces_added + stats.faces_removed - 2 * stats.faces_readded_unchanged;
      recomputed += stats.faces_recomputed;
      ++updates;
      if (++keyframes % full_every == 0) {
        const std::vector<mesher::SurfaceFace> faces = mesher.surfaceFaces();
        TraversabilityMap fresh(profile, frame);
        const auto full_start = std::chrono::steady_clock::now();
        const double full_cpu_start = threadCpuSeconds();
        fresh.reset(faces);
        const double full = seconds(full_start), full_cpu = threadCpuSeconds() - full_cpu_start;
        full_s.push_back(full);
        full_cpu_s.push_back(full_cpu);
        ratio.push_back(t / full);
        ratio_cpu.push_back(cpu / full_cpu);
        faces_per_s.push_back(static_cast<double>(faces.size()) / full);
        faces_per_cpu_s.push_back(static_cast<double>(faces.size()) / full_cpu);
      }
      faces_end = map.faceCount();
    }
  }
  state.counters["keyframes"] = static_cast<double>(updates) / static_cast<double>(state.iterations());
  state.counters["faces_end"] = static_cast<double>(faces_end);
  state.counters["update_median_ms"] = 1e3 * percentile(incremental_s, 0.5);
  state.counters["update_p99_ms"] = 1e3 * percentile(incremental_s, 0.99);
  state.counters["update_cpu_median_ms"] = 1e3 * percentile(incremental_cpu_s, 0.5);
  state.counters["update_cpu_p99_ms"] = 1e3 * percentile(incremental_cpu_s, 0.99);
  state.counters["mesher_queries_cpu_median_ms"] = 1e3 * percentile(query_cpu_s, 0.5);
  state.counters["mesher_queries_cpu_p99_ms"] = 1e3 * percentile(query_cpu_s, 0.99);
  state.counters["full_cpu_median_ms"] = 1e3 * percentile(full_cpu_s, 0.5);
  state.counters["update_over_full_cpu_median"] = percentile(ratio_cpu, 0.5);
  state.counters["delta_faces_per_update"] = static_cast<double>(delta_faces) / static_cast<double>(updates);
  state.counters["real_changed_faces_per_update"] = static_cast<double>(real_faces) / static_cast<double>(updates);
  state.counters["faces_recomputed_per_update"] = static_cast<double>(recomputed) / static_cast<double>(updates);
  state.counters["full_median_ms"] = 1e3 * percentile(full_s, 0.5);
  state.counters["update_over_full_median"] = percentile(ratio, 0.5);
  state.counters["full_faces_per_s"] = percentile(faces_per_s, 0.5);
  state.counters["full_faces_per_cpu_s"] = percentile(faces_per_cpu_s, 0.5);
  // Whether the slow updates are the big deltas: the delta of the slowest update (CPU time).
  if (!incremental_cpu_s.empty()) {
    const auto slowest =
        std::max_element(incremental_cpu_s.begin(), incremental_cpu_s.end()) - incremental_cpu_s.begin();
    state.counters["slowest_update_delta_faces"] = delta_sizes[static_cast<std::size_t>(slowest)];
    state.counters["delta_faces_median"] = percentile(delta_sizes, 0.5);
    state.counters["delta_faces_max"] = percentile(delta_sizes, 1.0);
  }
}

/// Full computation of the final street map (faces per second), setup excluded. With
/// `no_extension`, measured obstacles are not grown by their possible extension (the evidence
/// rule whose wider obstacle window costs most; the ratio of the two runs is its price).
void BM_FullComputation(benchmark::State& state, const BenchStream* s, const std::string& robot, bool no_extension) {
  RobotProfile profile = loadRobotProfile(kRobots / (robot + ".yaml"));
  if (no_extension) {
    profile.evidence.obstacle_extension = 0;
    profile.evidence.max_obstacle_extension_m = 0;
  }
  MapFrame frame;
  frame.up_W = s->up_W;
  mesher::Mesher mesher{mesher::MesherConfig{}};
  for (const datasets::StreamEvent& event : s->stream.events) datasets::applyEvent(mesher, event);
  const std::vector<mesher::SurfaceFace> faces = mesher.surfaceFaces();
  for (auto _ : state) {
    TraversabilityMap map(profile, frame);
    map.reset(faces);
    benchmark::DoNotOptimize(map.faceCount());
  }
  state.counters["faces"] = static_cast<double>(faces.size());
  state.counters["faces_per_s"] =
      benchmark::Counter(static_cast<double>(faces.size()) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
}

/// Registers the benchmarks of one stream.
void registerStream(const BenchStream* s, const std::vector<std::string>& robots) {
  for (const std::string& robot : robots) {
    benchmark::RegisterBenchmark(("BM_LayersWhileMeshing/" + s->name + "/" + robot).c_str(), BM_LayersWhileMeshing, s,
                                 robot)
        ->Iterations(1)
        ->Unit(benchmark::kSecond);
  }
  for (const std::string& robot : robots) {
    for (const bool no_extension : {false, true}) {
      const std::string name = "BM_FullComputation/" + s->name + "/" + robot + (no_extension ? "/no_extension" : "");
      benchmark::RegisterBenchmark(name.c_str(), BM_FullComputation, s, robot, no_extension)
          ->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace
}  // namespace terramesh::traversability

/// Streams: the built-in 200 m street (every shipped robot), plus every stream file listed in
/// the environment variable TERRAMESH_TRAV_STREAMS (separated by ':'; small_wheeled only).
int main(int argc, char** argv) {
  using terramesh::bench::BenchStream;
  benchmark::AddCustomContext("machine", terramesh::describeMachine());
  benchmark::Initialize(&argc, argv);
  std::vector<std::unique_ptr<BenchStream>> streams;
  streams.push_back(std::make_unique<BenchStream>(terramesh::bench::builtinStreet()));
  terramesh::traversability::registerStream(streams.back().get(), {"small_wheeled", "legged", "car"});
  if (const char* list = std::getenv("TERRAMESH_TRAV_STREAMS")) {
    std::istringstream in(list);
    for (std::string path; std::getline(in, path, ':');) {
      if (path.empty()) continue;
      streams.push_back(std::make_unique<BenchStream>(terramesh::bench::fileStream(path)));
      benchmark::AddCustomContext("stream " + streams.back()->name, path);
      terramesh::traversability::registerStream(streams.back().get(), {"small_wheeled"});
    }
  }
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
