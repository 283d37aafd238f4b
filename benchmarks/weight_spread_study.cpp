// How far free-space votes leak behind surfaces as a function of the neighbour-vote cap
// (MesherConfig::spread_cap), on the analytic plane scene: cameras move above the plane z = 0, so
// every cell entirely below it is matter. Prints, per cap, how many such cells end up free and in O,
// and how much of the probes above/below the plane the mesh encloses.
//
// Usage: terramesh_weight_study   (no arguments; deterministic)
#include <cstdio>

#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"
#include "test_support/mesh_queries.h"

namespace {

using namespace terramesh;

void study(mesher::MesherMode mode, int cap) {
  const test::AnalyticScene scene = test::planeScene(test::SceneOptions{});
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mode);
  config.steiner_step_m = 4.0;
  config.spread_cap = cap;
  config.incremental_steiner_grid = false;
  config.fixed_grid_bounds_W = mesher::AxisAlignedBox{Eigen::Vector3d(-15, -15, -1), Eigen::Vector3d(15, 15, 4)};
  mesher::Mesher mesher(config);
  for (const mesher::Keyframe& keyframe : scene.keyframes) mesher.integrateKeyframe(keyframe);
  std::size_t below = 0, below_free = 0, below_outside = 0;
  for (const mesher::CellVisibility& cell : mesher.cellVisibility()) {
    bool all_below = true, strictly = false;
    for (const Eigen::Vector3d& v : cell.vertices_W) {
      all_below = all_below && v.z() <= 1e-9;
      strictly = strictly || v.z() < -1e-9;
    }
    if (!all_below || !strictly) continue;
    ++below;
    below_free += cell.weight > config.free_threshold;
    below_outside += cell.outside;
  }
  const mesher::TriangleMesh mesh = mesher.extractMesh();
  std::printf("%-11s %4d %10zu %10zu %10zu %13.3f %13.3f\n", mesher::toString(mode), cap, below,
              below_free, below_outside,
              test::fractionInside(mesh, scene.free_probe_min, scene.free_probe_max, 400),
              test::fractionInside(mesh, scene.matter_probe_min, scene.matter_probe_max, 400));
}

}  // namespace

int main() {
  std::printf("plane scene, cells entirely below the plane (matter)\n");
  std::printf("%-11s %4s %10s %10s %10s %13s %13s\n", "mode", "cap", "below", "free", "in O",
              "above carved", "below carved");
  for (int cap : {0, 1, 2, 4, 8}) study(mesher::MesherMode::kRomanoni15, cap);
  for (int cap : {0, 1}) study(mesher::MesherMode::kProposed, cap);
  return 0;
}
