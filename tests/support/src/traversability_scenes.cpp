#include "test_support/traversability_scenes.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace terramesh::test {
namespace {

struct Patch {
  Eigen::Vector3d origin, u, v;  ///< origin + s u + t v, s, t in [0, 1]
};

struct Box {
  Eigen::Vector3d lo, hi;
};

/// Whether the open segment (a, b) passes through the interior of the box.
bool crossesBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Box& box) {
  double t0 = 1e-6, t1 = 1.0 - 1e-6;
  const Eigen::Vector3d d = b - a;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) < 1e-15) {
      if (a[axis] <= box.lo[axis] || a[axis] >= box.hi[axis]) return false;
      continue;
    }
    double near = (box.lo[axis] - a[axis]) / d[axis], far = (box.hi[axis] - a[axis]) / d[axis];
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
    if (t0 >= t1) return false;
  }
  return true;
}

/// Camera-to-world rotation of an OpenCV camera (y down) looking along `forward`, z-up world.
Eigen::Quaterniond lookAlong(const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();
  x.normalize();
  Eigen::Matrix3d rotation;
  rotation << x, z.cross(x), z;
  return Eigen::Quaterniond(rotation);
}

/// Samples points on the patches, then lets each camera observe those in range and field of
/// view whose sight line no occluder crosses.
std::vector<mesher::Keyframe> observeScene(const std::vector<Patch>& patches, const std::vector<Box>& occluders,
                                           const std::vector<Eigen::Vector3d>& positions,
                                           const Eigen::Vector3d& forward, const SceneOptions& options) {
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (const Patch& p : patches) {
    const long count = std::lround(p.u.cross(p.v).norm() * options.density_per_m2);
    for (long i = 0; i < count; ++i) points.push_back(p.origin + unit(rng) * p.u + unit(rng) * p.v);
  }
  const double cos_half_fov = std::cos(options.half_fov_deg * M_PI / 180.0);
  const Eigen::Vector3d f = forward.normalized();
  std::vector<mesher::Keyframe> keyframes;
  for (std::size_t k = 0; k < positions.size(); ++k) {
    mesher::Keyframe keyframe;
    keyframe.id.value = k;
    keyframe.position_W_C = positions[k];
    keyframe.rotation_W_C = lookAlong(f);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d offset = points[i] - positions[k];
      const double distance = offset.norm();
      if (distance > options.max_range_m || distance == 0.0 || offset.dot(f) < cos_half_fov * distance) continue;
      bool hidden = false;
      for (const Box& box : occluders) hidden = hidden || crossesBox(positions[k], points[i], box);
      if (!hidden) keyframe.observations.push_back({{i}, points[i]});
    }
    keyframes.push_back(std::move(keyframe));
  }
  return keyframes;
}

std::vector<Eigen::Vector3d> line(const Eigen::Vector3d& from, const Eigen::Vector3d& to, int count) {
  std::vector<Eigen::Vector3d> positions;
  for (int k = 0; k < count; ++k) {
    const double s = count > 1 ? static_cast<double>(k) / (count - 1) : 0.5;
    // A small sideways wobble keeps the cameras off one plane (degenerate for the mesher).
    positions.push_back(from + s * (to - from) + Eigen::Vector3d(0, 0.3 * std::sin(7.0 * s), 0.05 * std::cos(5.0 * s)));
  }
  return positions;
}

}  // namespace

AnalyticScene rampScene(double slope_deg, const SceneOptions& options) {
  const double t = std::tan(slope_deg * M_PI / 180.0);
  const std::vector<Patch> patches = {{{-12, -8, -12 * t}, {24, 0, 24 * t}, {0, 16, 0}}};
  std::vector<Eigen::Vector3d> positions = line({-11, 0, 0}, {7, 0, 0}, options.keyframes);
  for (Eigen::Vector3d& p : positions) p.z() += p.x() * t + 2.5;
  AnalyticScene scene;
  scene.keyframes = observeScene(patches, {}, positions, {1, 0, -std::tan(35 * M_PI / 180)}, options);
  scene.in_free_space = [t](const Eigen::Vector3d& p) { return p.z() > p.x() * t; };
  scene.free_probe_min = {-4, -1, 0.8};
  scene.free_probe_max = {4, 1, 1.8};
  scene.matter_probe_min = {-4, -4, -4};
  scene.matter_probe_max = {4, 4, -2.5};
  return scene;
}

AnalyticScene stepScene(double height_m, const SceneOptions& options) {
  const std::vector<Patch> patches = {{{-12, -8, 0}, {24, 0, 0}, {0, 8, 0}},
                                      {{-12, 0, height_m}, {24, 0, 0}, {0, 8, 0}},
                                      {{-12, 0, 0}, {24, 0, 0}, {0, 0, height_m}}};
  const std::vector<Box> occluders = {{{-12, 0, -1}, {12, 8, height_m}}};
  AnalyticScene scene;
  scene.keyframes = observeScene(patches, occluders, line({-11, -3, 2.5}, {7, -3, 2.5}, options.keyframes),
                                 {1, 0.6, -0.9}, options);
  scene.in_free_space = [height_m](const Eigen::Vector3d& p) { return p.z() > (p.y() < 0 ? 0 : height_m); };
  scene.free_probe_min = {-4, -4, 0.8 + height_m};
  scene.free_probe_max = {4, -2, 2.0 + height_m};
  scene.matter_probe_min = {-4, -4, -4};
  scene.matter_probe_max = {4, 4, -2.5};
  return scene;
}

AnalyticScene lowCeilingScene(double ceiling_m, const SceneOptions& options) {
  const double top = ceiling_m + 0.3;
  const std::vector<Patch> patches = {
      {{-12, -8, 0}, {28, 0, 0}, {0, 16, 0}},         // floor
      {{0, -3, ceiling_m}, {6, 0, 0}, {0, 6, 0}},     // underside
      {{0, -3, ceiling_m}, {0, 6, 0}, {0, 0, 0.3}},   // front face (x = 0)
      {{0, -3, ceiling_m}, {6, 0, 0}, {0, 0, 0.3}},   // side y = -3
      {{0, 3, ceiling_m}, {6, 0, 0}, {0, 0, 0.3}},    // side y = 3
      {{6, -3, ceiling_m}, {0, 6, 0}, {0, 0, 0.3}}};  // back face (x = 6)
  const std::vector<Box> occluders = {{{0, -3, ceiling_m}, {6, 3, top}}};
  AnalyticScene scene;
  scene.keyframes = observeScene(patches, occluders,
                                 line({-11, 0, 0.5 * ceiling_m}, {14, 0, 0.5 * ceiling_m}, options.keyframes),
                                 {1, 0, -0.25}, options);
  scene.in_free_space = [ceiling_m, top](const Eigen::Vector3d& p) {
    const bool in_slab = p.x() > 0 && p.x() < 6 && std::abs(p.y()) < 3 && p.z() > ceiling_m && p.z() < top;
    return p.z() > 0 && !in_slab;
  };
  scene.free_probe_min = {1, -2, 0.2 * ceiling_m};
  scene.free_probe_max = {5, 2, 0.8 * ceiling_m};
  scene.matter_probe_min = {-4, -4, -4};
  scene.matter_probe_max = {4, 4, -2.5};
  return scene;
}

mesher::TriangleMesh heightFieldMesh(double x0, double x1, double y0, double y1, double spacing_m,
                                     const std::function<double(double, double)>& height) {
  const int nx = static_cast<int>(std::lround((x1 - x0) / spacing_m));
  const int ny = static_cast<int>(std::lround((y1 - y0) / spacing_m));
  mesher::TriangleMesh mesh;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + (x1 - x0) * i / nx, y = y0 + (y1 - y0) * j / ny;
      mesh.vertices.emplace_back(x, y, height(x, y));
    }
  }
  const auto at = [nx](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      mesh.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

void appendMesh(mesher::TriangleMesh& a, const mesher::TriangleMesh& b) {
  const auto offset = static_cast<std::uint32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& f : b.faces) a.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
}

mesher::TriangleMesh horizontalQuad(double x0, double x1, double y0, double y1, double z, bool facing_down) {
  mesher::TriangleMesh mesh;
  mesh.vertices = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  if (facing_down) {
    mesh.faces = {{0, 2, 1}, {0, 3, 2}};
  } else {
    mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  }
  return mesh;
}

mesher::TriangleMesh verticalQuad(double x0, double y0, double x1, double y1, double z0, double z1) {
  mesher::TriangleMesh mesh;
  mesh.vertices = {{x0, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y0, z1}};
  mesh.faces = {{0, 2, 1}, {0, 3, 2}};
  return mesh;
}

mesher::TriangleMesh thinWall(double x0, double y0, double x1, double y1, double z0, double z1) {
  mesher::TriangleMesh mesh = verticalQuad(x0, y0, x1, y1, z0, z1);
  appendMesh(mesh, verticalQuad(x1, y1, x0, y0, z0, z1));
  return mesh;
}

}  // namespace terramesh::test
