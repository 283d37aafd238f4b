// Meshes a tiny stream (cameras 2 m above a 21 x 21 grid of ground points) through the installed
// libraries; exits 0 only if the mesh has faces.
#include <cstdio>

#include "datasets/slam_stream.h"
#include "mesher/mesher.h"

int main() {
  using namespace terramesh;
  datasets::SlamStream stream;
  for (int k = 0; k < 5; ++k) {
    mesher::Keyframe keyframe;
    keyframe.id.value = static_cast<std::uint64_t>(k);
    keyframe.position_W_C = Eigen::Vector3d(2.0 * k - 4.0, 0.5, 2.0);
    for (int i = 0; i < 21 * 21; ++i) {
      const Eigen::Vector3d ground(i % 21 - 10.0, i / 21 - 10.0, 0.1 * ((i * 7) % 5));
      keyframe.observations.push_back({mesher::PointId{static_cast<std::uint64_t>(i)}, ground});
    }
    stream.events.emplace_back(std::move(keyframe));
  }
  mesher::Mesher mesher(mesher::MesherConfig::forMode(mesher::MesherMode::kProposed));
  for (const datasets::StreamEvent& event : stream.events) datasets::applyEvent(mesher, event);
  const mesher::TriangleMesh mesh = mesher.extractMesh();
  std::printf("consumer: %zu vertices, %zu faces\n", mesh.vertexCount(), mesh.faceCount());
  return mesh.faceCount() > 0 ? 0 : 1;
}
