#include "planning_fixtures.h"

#include <cmath>
#include <limits>
#include <map>
#include <tuple>

namespace terramesh::test {

using traversability::FaceClass;

std::uint32_t LayeredMeshBuilder::vertex(const Eigen::Vector3d& p) {
  auto& vertices = map_.mesh.vertices;
  for (std::uint32_t i = 0; i < vertices.size(); ++i) {
    if ((vertices[i] - p).norm() < 1e-9) return i;
  }
  vertices.push_back(p);
  return static_cast<std::uint32_t>(vertices.size() - 1);
}

void LayeredMeshBuilder::sheet(double x0, double x1, double y0, double y1, double cell_m,
                               const std::function<double(double, double)>& z,
                               const std::function<std::optional<FaceClass>(const Eigen::Vector3d&)>& class_of) {
  const int nx = static_cast<int>(std::lround((x1 - x0) / cell_m));
  const int ny = static_cast<int>(std::lround((y1 - y0) / cell_m));
  auto point = [&](int i, int j) {
    const double x = x0 + i * cell_m, y = y0 + j * cell_m;
    return Eigen::Vector3d(x, y, z(x, y));
  };
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const Eigen::Vector3d p00 = point(i, j), p10 = point(i + 1, j), p11 = point(i + 1, j + 1), p01 = point(i, j + 1);
      for (const auto& tri : {std::array<Eigen::Vector3d, 3>{p00, p10, p11}, std::array<Eigen::Vector3d, 3>{p00, p11, p01}}) {
        const std::optional<FaceClass> c = class_of((tri[0] + tri[1] + tri[2]) / 3.0);
        if (!c) continue;
        map_.mesh.faces.push_back({vertex(tri[0]), vertex(tri[1]), vertex(tri[2])});
        classes_.push_back(*c);
      }
    }
  }
}

void LayeredMeshBuilder::wall(double x0, double y0, double x1, double y1, double z0, double z1, double cell_m) {
  const Eigen::Vector3d a(x0, y0, 0), b(x1, y1, 0);
  const int n = static_cast<int>(std::lround((b - a).norm() / cell_m));
  const int m = static_cast<int>(std::lround((z1 - z0) / cell_m));
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < m; ++k) {
      auto p = [&](int di, int dk) {
        Eigen::Vector3d q = a + (b - a) * (static_cast<double>(i + di) / n);
        q.z() = z0 + (z1 - z0) * static_cast<double>(k + dk) / m;
        return vertex(q);
      };
      map_.mesh.faces.push_back({p(0, 0), p(1, 0), p(1, 1)});
      map_.mesh.faces.push_back({p(0, 0), p(1, 1), p(0, 1)});
      classes_.push_back(FaceClass::kLethal);
      classes_.push_back(FaceClass::kLethal);
    }
  }
}

traversability::LayeredMesh LayeredMeshBuilder::finish() const {
  traversability::LayeredMesh map = map_;
  const auto& v = map.mesh.vertices;
  std::vector<Eigen::Vector3d> centroids;
  for (const auto& f : map.mesh.faces) centroids.push_back((v[f[0]] + v[f[1]] + v[f[2]]) / 3.0);
  map.layers.resize(map.mesh.faces.size());
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    traversability::FaceLayers& layer = map.layers[f];
    layer.face_class = classes_[f];
    layer.cost = classes_[f] == FaceClass::kFree ? 0.2f
                 : classes_[f] == FaceClass::kLethal ? 1.0f
                                                     : std::numeric_limits<float>::quiet_NaN();
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t g = 0; g < map.mesh.faces.size(); ++g) {
      if (classes_[g] == FaceClass::kLethal) nearest = std::min(nearest, (centroids[f] - centroids[g]).norm());
    }
    layer.lethal_distance_m = static_cast<float>(nearest);
  }
  return map;
}

traversability::LayeredMesh wallWithGapMap() {
  LayeredMeshBuilder builder;
  builder.sheet(0, 20, 0, 10, 0.5, [](double, double) { return 0.0; }, [](const Eigen::Vector3d& c) {
    const bool in_strip = c.x() > 9.5 && c.x() < 10.5 && c.y() < 7;
    return std::optional<FaceClass>(in_strip ? FaceClass::kLethal : FaceClass::kFree);
  });
  return builder.finish();
}

traversability::LayeredMesh unknownGapMap(bool all_lethal) {
  LayeredMeshBuilder builder;
  builder.sheet(0, 20, 0, 10, 0.5, [](double, double) { return 0.0; }, [all_lethal](const Eigen::Vector3d& c) {
    if (c.x() < 9.5 || c.x() > 10.5) return std::optional<FaceClass>(FaceClass::kFree);
    return std::optional<FaceClass>(c.y() < 6 || all_lethal ? FaceClass::kLethal : FaceClass::kUnknown);
  });
  return builder.finish();
}

traversability::LayeredMesh twoLevelMap() {
  LayeredMeshBuilder builder;
  auto flat = [](double h) { return [h](double, double) { return h; }; };
  builder.sheet(0, 20, 0, 10, 0.5, flat(0), [](const Eigen::Vector3d& c) -> std::optional<FaceClass> {
    if (c.x() > 10 && c.x() < 12 && c.y() > 1 && c.y() < 3) return std::nullopt;  // under the box
    if (c.x() > 2 && c.x() < 4 && c.y() > 1 && c.y() < 3) return FaceClass::kUnknown;
    return FaceClass::kFree;
  });
  // The box: a free top 1 m up, lethal sides down to the floor.
  builder.sheet(10, 12, 1, 3, 0.5, flat(1), [](const Eigen::Vector3d&) { return std::optional<FaceClass>(FaceClass::kFree); });
  builder.wall(10, 1, 12, 1, 0, 1, 0.5);
  builder.wall(12, 1, 12, 3, 0, 1, 0.5);
  builder.wall(12, 3, 10, 3, 0, 1, 0.5);
  builder.wall(10, 3, 10, 1, 0, 1, 0.5);
  builder.sheet(20, 40, 0, 4, 0.5, [](double x, double) { return 3.0 * (x - 20) / 20.0; },
                [](const Eigen::Vector3d&) { return std::optional<FaceClass>(FaceClass::kFree); });
  builder.sheet(40, 44, 0, 10, 0.5, flat(3), [](const Eigen::Vector3d&) { return std::optional<FaceClass>(FaceClass::kFree); });
  builder.sheet(0, 40, 4, 10, 0.5, flat(3), [](const Eigen::Vector3d&) { return std::optional<FaceClass>(FaceClass::kFree); });
  return builder.finish();
}

}  // namespace terramesh::test
