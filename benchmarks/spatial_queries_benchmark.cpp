// Ray casts and nearest-point queries per second on the evaluation's workloads, for the project's
// spatial queries (datasets::TriangleBvh on Embree with double-precision refinement,
// datasets::PointCloudIndex on nanoflann) and, for the triangle queries, CGAL's AABB_tree.
//   rays:    the depth-comparison rays of `terramesh eval --gt-mesh` (renderTruthRays): every 8th
//            pixel of the KITTI camera from 20 views along a synthetic street, max depth 40 m;
//   closest: the surface-distance queries (distancesToSurface): surface samples of the street's
//            ground truth moved 0.2 m (sd) off it, to that ground truth;
//   nearest: the LiDAR accuracy queries (distancesToPoints): KITTI 00 scan returns moved 0.2 m
//            (sd), to the cloud of returns, within 2 m (the `eval --gt-lidar` match radius).
// Setup (scene, trees) is built once and not timed. Results: docs/benchmarks.md, "Spatial queries".
#include <benchmark/benchmark.h>

#include <random>

#include "evaluation/lidar_truth.h"
#include "evaluation/mesh_evaluation.h"
#include "datasets/synthetic_scene.h"
#include "spatial_backends.h"

namespace terramesh::bench {
namespace {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
  double max_distance;
};

struct Workloads {
  mesher::TriangleMesh street;
  std::vector<Ray> rays;
  std::vector<Eigen::Vector3d> surface_queries;
  std::vector<Eigen::Vector3d> lidar_cloud;
  std::vector<Eigen::Vector3d> lidar_queries;
};

std::vector<Eigen::Vector3d> jitter(const std::vector<Eigen::Vector3d>& points, std::size_t count, double sd_m,
                                    std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sd_m);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::vector<Eigen::Vector3d> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) out.push_back(points[pick(rng)] + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  return out;
}

const Workloads& workloads() {
  static const Workloads data = [] {
    Workloads w;
    const datasets::SyntheticScene scene = datasets::buildStreetScene(datasets::StreetSceneConfig{});
    w.street = scene.ground_truth.mesh;
    const evaluation::PinholeCamera camera;
    const evaluation::DepthComparisonConfig config;  // max depth 40 m
    const std::size_t views = 20, step = std::max<std::size_t>(1, scene.frames_T_W_C.size() / views);
    for (std::size_t f = 0; f < scene.frames_T_W_C.size(); f += step) {
      const Eigen::Isometry3d& pose = scene.frames_T_W_C[f];
      for (int v = 4; v < camera.height_px; v += 8) {
        for (int u = 4; u < camera.width_px; u += 8) {
          w.rays.push_back({pose.translation(), pose.linear() * camera.rayDirection_C(u + 0.5, v + 0.5), config.max_depth_m});
        }
      }
    }
    w.surface_queries = jitter(evaluation::sampleSurface(w.street, 100000, 7, false), 100000, 0.2, 8);
    evaluation::LidarTruthOptions lidar;
    lidar.poses_path = TERRAMESH_SHARED_DIR "/data/kitti_poses/00.txt";
    lidar.first_frame = 1;
    lidar.last_frame = 1;
    w.lidar_cloud = evaluation::readLidarTruth(TERRAMESH_SHARED_DIR "/data/kitti00_lidar", lidar, camera, config).returns_W;
    w.lidar_queries = jitter(w.lidar_cloud, 100000, 0.2, 9);
    return w;
  }();
  return data;
}

template <class Tree>
void castRays(benchmark::State& state) {
  const Workloads& w = workloads();
  const Tree tree(w.street);
  std::size_t hits = 0;
  for (auto _ : state) {
    for (const Ray& ray : w.rays) hits += tree.firstHit(ray.origin, ray.direction, ray.max_distance).has_value();
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * w.rays.size()));
  state.counters["rays"] = static_cast<double>(w.rays.size());
  state.counters["faces"] = static_cast<double>(w.street.faces.size());
}

template <class Tree>
void closestPoints(benchmark::State& state) {
  const Workloads& w = workloads();
  const Tree tree(w.street);
  double sum = 0;
  for (auto _ : state) {
    for (const Eigen::Vector3d& q : w.surface_queries) sum += tree.closestPoint(q).distance;
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * w.surface_queries.size()));
}

template <class Tree>
void buildTree(benchmark::State& state) {
  const Workloads& w = workloads();
  for (auto _ : state) {
    const Tree tree(w.street);
    benchmark::DoNotOptimize(&tree);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * w.street.faces.size()));
}

template <class Cloud>
void nearestPoints(benchmark::State& state) {
  const Workloads& w = workloads();
  const Cloud cloud(w.lidar_cloud);
  std::size_t found = 0;
  for (auto _ : state) {
    for (const Eigen::Vector3d& q : w.lidar_queries) found += cloud.nearest(q, 2.0).has_value();
  }
  benchmark::DoNotOptimize(found);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * w.lidar_queries.size()));
  state.counters["cloud_points"] = static_cast<double>(w.lidar_cloud.size());
}

template <class Cloud>
void buildCloud(benchmark::State& state) {
  const Workloads& w = workloads();
  for (auto _ : state) {
    const Cloud cloud(w.lidar_cloud);
    benchmark::DoNotOptimize(&cloud);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * w.lidar_cloud.size()));
}

/// The index `terramesh eval --gt-lidar` uses.
struct Cloud {
  explicit Cloud(const std::vector<Eigen::Vector3d>& points) : index(points) {}
  datasets::PointCloudIndex index;
  auto nearest(const Eigen::Vector3d& q, double max_distance_m) const { return index.nearest(q, max_distance_m); }
};

BENCHMARK_TEMPLATE(castRays, datasets::TriangleBvh)->Name("rays/triangle_bvh_embree")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(castRays, CgalTriangleTree)->Name("rays/cgal_aabb_tree")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(closestPoints, datasets::TriangleBvh)->Name("closest/triangle_bvh_embree")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(closestPoints, CgalTriangleTree)->Name("closest/cgal_aabb_tree")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(buildTree, datasets::TriangleBvh)->Name("build_mesh/triangle_bvh_embree")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(buildTree, CgalTriangleTree)->Name("build_mesh/cgal_aabb_tree")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(nearestPoints, Cloud)->Name("nearest/point_cloud_index_nanoflann")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(buildCloud, Cloud)->Name("build_cloud/point_cloud_index_nanoflann")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace terramesh::bench

BENCHMARK_MAIN();
