// Google Benchmark micro-benchmarks of the mesher's stages: the ray walk with and without the
// next-tetrahedron cache, the manifold test, point insertion, and whole keyframe updates (with the
// per-step split) in every mode. Setup is excluded from the timings.
#include <benchmark/benchmark.h>

#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <random>

#include "cgal_types.h"
#include "manifold_test.h"
#include "map_state.h"
#include "mesher/mesher.h"
#include "outside_set.h"
#include "ray_walk.h"
#include "test_support/analytic_scenes.h"
#include "triangulation_editor.h"
#include "visibility_tracer.h"

namespace terramesh::mesher::internal {
namespace {

/// Points on a street-like layout: a ground plane and two facades, 12 m apart, 200 m long.
std::vector<Point> streetPoints(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> along(0.0, 200.0), across(-6.0, 6.0), up(0.0, 8.0);
  std::vector<Point> points;
  for (std::size_t i = 0; i < count; ++i) {
    switch (rng() % 3) {
      case 0: points.emplace_back(along(rng), across(rng), 0.01 * across(rng)); break;
      case 1: points.emplace_back(along(rng), -6.0 + 0.02 * across(rng), up(rng)); break;
      default: points.emplace_back(along(rng), 6.0 + 0.02 * across(rng), up(rng)); break;
    }
  }
  return points;
}

void BM_RayWalk(benchmark::State& state) {
  const bool cache = state.range(0) != 0;
  Delaunay tri;
  std::vector<VertexHandle> vertices;
  for (const Point& p : streetPoints(30000, 1)) vertices.push_back(tri.insert(p));
  for (int i = -1; i <= 21; ++i) {
    for (int j = -2; j <= 2; ++j) {
      for (int k = -2; k <= 3; ++k) tri.insert(Point(10.0 * i + 0.37, 10.0 * j + 0.21, 10.0 * k + 0.13));
    }
  }
  // Cameras along the street, each seeing the points within 40 m ahead: similar directions.
  std::vector<std::pair<CameraLocation, std::vector<VertexHandle>>> views;
  for (double x = 5.0; x < 160.0; x += 4.0) {
    CameraLocation camera;
    camera.position = Point(x, 0.3, 1.6);
    camera.cell = tri.locate(camera.position, camera.type, camera.li, camera.lj);
    std::vector<VertexHandle> seen;
    for (const VertexHandle& v : vertices) {
      const double dx = v->point().x() - x;
      if (dx > 2.0 && dx < 40.0 && seen.size() < 500) seen.push_back(v);
    }
    views.emplace_back(camera, seen);
  }
  RayWalker walker(tri, cache);
  WalkCounters counters;
  std::vector<CellHandle> path;
  std::size_t rays = 0;
  for (auto _ : state) {
    for (const auto& [camera, seen] : views) {
      for (const VertexHandle& target : seen) {
        walker.walk(camera, target, path, counters);
        benchmark::DoNotOptimize(path.data());
        ++rays;
      }
    }
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
  state.counters["cells/ray"] = static_cast<double>(counters.steps) / static_cast<double>(rays) + 1.0;
  state.counters["cache_hit_rate"] =
      counters.cache_lookups ? static_cast<double>(counters.cache_hits) / counters.cache_lookups : 0.0;
}
BENCHMARK(BM_RayWalk)->Arg(0)->Arg(1)->ArgName("cache")->Unit(benchmark::kMillisecond);

void BM_ManifoldTest(benchmark::State& state) {
  Delaunay tri;
  MarkEpochs epochs(tri);
  SteinerGrid grid(10.0);
  grid.coverPoint(Eigen::Vector3d::Zero(), 1);
  BoundaryHash hash(true);
  OutsideSet outside(tri, grid, hash, epochs);
  for (const Point& p : streetPoints(20000, 2)) tri.insert(p);
  for (auto cell = tri.all_cells_begin(); cell != tri.all_cells_end(); ++cell) {
    for (int i = 0; i < 4; ++i) ++cell->vertex(i)->info().degree;
  }
  // Grow a large O, then time canAdd on its frontier.
  std::mt19937 rng(3);
  std::vector<CellHandle> members{tri.finite_cells_begin()};
  outside.add(members.front());
  for (int i = 0; i < 60000; ++i) {
    const CellHandle next = members[rng() % members.size()]->neighbor(static_cast<int>(rng() % 4));
    if (!next->info().outside() && !tri.is_infinite(next) && outside.canAdd(next)) {
      outside.add(next);
      members.push_back(next);
    }
  }
  std::vector<CellHandle> frontier;
  for (const CellHandle& member : members) {
    for (int i = 0; i < 4; ++i) {
      const CellHandle n = member->neighbor(i);
      if (!n->info().outside() && !tri.is_infinite(n)) frontier.push_back(n);
    }
  }
  std::size_t tests = 0, accepted = 0;
  for (auto _ : state) {
    for (const CellHandle& cell : frontier) {
      accepted += outside.canAdd(cell);
      ++tests;
    }
  }
  state.counters["tests/s"] = benchmark::Counter(static_cast<double>(tests), benchmark::Counter::kIsRate);
  state.counters["accepted"] = static_cast<double>(accepted) / static_cast<double>(tests);
  state.counters["O_cells"] = static_cast<double>(outside.size());
}
BENCHMARK(BM_ManifoldTest)->Unit(benchmark::kMillisecond);

void BM_PointInsertion(benchmark::State& state) {
  MesherConfig config;
  MapState map(config);
  VisibilityTracer tracer(map);
  TriangulationEditor editor(map, tracer);
  std::vector<Eigen::Vector3d> nodes = map.grid.coverBox({0, -6, 0}, {200, 6, 8}, 2);
  editor.bootstrap(nodes);
  // Keyframe-sized batches, each local and spatially sorted as the pipeline inserts them.
  std::vector<Point> points = streetPoints(200000, 4);
  std::sort(points.begin(), points.end(), [](const Point& a, const Point& b) { return a.x() < b.x(); });
  for (std::size_t begin = 0; begin < points.size(); begin += 1000) {
    const auto end = points.begin() + static_cast<long>(std::min(begin + 1000, points.size()));
    CGAL::spatial_sort(points.begin() + static_cast<long>(begin), end);
  }
  std::vector<RayId> retrace;
  std::size_t next = 0, inserted = 0;
  for (auto _ : state) {
    for (int i = 0; i < 1000 && next < points.size(); ++i, ++next) {
      VertexHandle vertex;
      inserted += editor.insert(toEigen(points[next]), static_cast<std::uint32_t>(next), retrace, vertex) ==
                  TriangulationEditor::InsertResult::kInserted;
    }
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(inserted), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PointInsertion)->Unit(benchmark::kMillisecond)->Iterations(100);

/// One keyframe update after 20 keyframes of the corridor scene, with the time split by step.
void BM_KeyframeUpdate(benchmark::State& state) {
  const auto mode = static_cast<MesherMode>(state.range(0));
  test::SceneOptions options;
  options.keyframes = 40;
  options.density_per_m2 = 4.0;
  const auto scene = test::corridorScene(options);
  MesherConfig config = MesherConfig::forMode(mode);
  config.steiner_step_m = 4.0;
  if (!config.incremental_steiner_grid) {
    config.fixed_grid_bounds_W = AxisAlignedBox{Eigen::Vector3d(-11, -11, -1), Eigen::Vector3d(11, 11, 4)};
  }
  StepTimes steps;
  std::size_t updates = 0;
  for (auto _ : state) {
    state.PauseTiming();
    Mesher mesher(config);
    for (int k = 0; k < 20; ++k) mesher.integrateKeyframe(scene.keyframes[static_cast<std::size_t>(k)]);
    state.ResumeTiming();
    const UpdateStats stats = mesher.integrateKeyframe(scene.keyframes[20]);
    steps += stats.time;
    ++updates;
  }
  const double n = static_cast<double>(updates);
  state.counters["shrink_ms"] = 1e3 * steps.shrink_s / n;
  state.counters["insert_ms"] = 1e3 * steps.insertion_s / n;
  state.counters["rays_ms"] = 1e3 * steps.ray_tracing_s / n;
  state.counters["grow_ms"] = 1e3 * steps.grow_s / n;
  state.SetLabel(toString(mode));
}
BENCHMARK(BM_KeyframeUpdate)
    ->Arg(static_cast<int>(MesherMode::kProposed))
    ->Arg(static_cast<int>(MesherMode::kRomanoni15))
    ->Arg(static_cast<int>(MesherMode::kLitvinov13))
    ->ArgName("mode")
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace terramesh::mesher::internal

BENCHMARK_MAIN();
