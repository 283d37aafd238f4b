#include "bench_streams.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <sstream>
#include <variant>

#include "datasets/slam_simulation.h"
#include "datasets/stream_reader.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"
#include "traversability/traversability_map.h"

namespace terramesh::bench {

BenchStream builtinStreet(double length_m) {
  datasets::StreetSceneConfig config;
  config.length_m = length_m;
  const datasets::SyntheticScene scene = datasets::buildStreetScene(config);
  const datasets::TriangleBvh bvh(scene.ground_truth.mesh);
  BenchStream s;
  s.name = "street" + std::to_string(static_cast<int>(std::lround(length_m)));
  s.stream = datasets::simulateSlam(scene, bvh, datasets::kittiLikeSlamConfig()).stream;
  s.up_W = scene.up_W;
  return s;
}

BenchStream fileStream(const std::filesystem::path& path) {
  BenchStream s;
  s.name = path.parent_path().filename().string();
  if (s.name.empty()) s.name = path.stem().string();
  s.stream = datasets::readAnyStream(path);
  std::ifstream generation(path.parent_path() / "generation.txt");
  for (std::string line; std::getline(generation, line);) {
    std::istringstream in(line);
    std::string key;
    double x = 0, y = 0, z = 0;
    if (in >> key && key == "up_W" && in >> x >> y >> z) {
      s.up_W = Eigen::Vector3d(x, y, z).normalized();
      return s;
    }
  }
  std::vector<Eigen::Matrix3d> rotations;
  for (const datasets::StreamEvent& event : s.stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      rotations.push_back(keyframe->rotation_W_C.toRotationMatrix());
    }
  }
  s.up_W = traversability::estimateUpFromCameras(rotations, s.stream.sensor_up_S);
  return s;
}

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto i = static_cast<std::size_t>(std::lround(q * static_cast<double>(values.size() - 1)));
  return values[std::min(i, values.size() - 1)];
}

}  // namespace terramesh::bench
