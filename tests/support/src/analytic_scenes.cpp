#include "test_support/analytic_scenes.h"

#include <cmath>
#include <Eigen/Geometry>
#include <random>
#include <unordered_map>

namespace terramesh::test {
namespace {

/// An axis-aligned rectangle origin + s*u + t*v, s,t in [0,1].
struct Rectangle {
  Eigen::Vector3d origin;
  Eigen::Vector3d u;
  Eigen::Vector3d v;
};

struct SurfacePoint {
  std::uint64_t id;
  Eigen::Vector3d position;
};

std::vector<SurfacePoint> samplePoints(const std::vector<Rectangle>& rectangles, double density,
                                       std::mt19937& rng,
                                       const std::function<bool(const Eigen::Vector3d&)>& keep) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<SurfacePoint> points;
  for (const Rectangle& r : rectangles) {
    const double area = r.u.cross(r.v).norm();
    const int count = static_cast<int>(std::lround(area * density));
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector3d p = r.origin + unit(rng) * r.u + unit(rng) * r.v;
      if (keep && !keep(p)) continue;
      points.push_back({points.size(), p});
    }
  }
  return points;
}

struct Camera {
  Eigen::Vector3d position;
  Eigen::Vector3d forward;  ///< unit viewing direction
};

/// Camera-to-world rotation of a camera looking along `forward` (z forward, y down-ish).
Eigen::Quaterniond lookAlong(const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d rotation;
  rotation.col(0) = x;
  rotation.col(1) = y;
  rotation.col(2) = z;
  return Eigen::Quaterniond(rotation);
}

/// Builds keyframes: each camera observes the points in range, inside its field of view, for
/// which `visible` holds.
std::vector<mesher::Keyframe> observe(
    const std::vector<Camera>& cameras, const std::vector<SurfacePoint>& points,
    const SceneOptions& options,
    const std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)>& visible) {
  const double cos_half_fov = std::cos(options.half_fov_deg * M_PI / 180.0);
  std::vector<mesher::Keyframe> keyframes;
  for (std::size_t k = 0; k < cameras.size(); ++k) {
    const Camera& camera = cameras[k];
    mesher::Keyframe keyframe;
    keyframe.id.value = k;
    keyframe.position_W_C = camera.position;
    keyframe.rotation_W_C = lookAlong(camera.forward);
    for (const SurfacePoint& point : points) {
      const Eigen::Vector3d offset = point.position - camera.position;
      const double distance = offset.norm();
      if (distance > options.max_range_m || distance == 0.0) continue;
      if (offset.dot(camera.forward) < cos_half_fov * distance) continue;
      if (visible && !visible(camera.position, point.position)) continue;
      keyframe.observations.push_back({{point.id}, point.position});
    }
    keyframes.push_back(std::move(keyframe));
  }
  return keyframes;
}

/// Cameras on a closed loop x(angle), looking along the direction of travel.
std::vector<Camera> loopCameras(int count, double phase,
                                const std::function<Eigen::Vector3d(double)>& path) {
  std::vector<Camera> cameras;
  for (int k = 0; k < count; ++k) {
    const double angle = 2.0 * M_PI * k / count + phase;
    const Eigen::Vector3d here = path(angle);
    cameras.push_back({here, (path(angle + 1e-3) - here).normalized()});
  }
  return cameras;
}

/// Whether the open segment (a, b) passes through the interior of the box [lo, hi].
bool segmentCrossesBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& lo,
                       const Eigen::Vector3d& hi) {
  double t0 = 0.0;
  double t1 = 1.0;
  const Eigen::Vector3d d = b - a;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) < 1e-15) {
      if (a[axis] <= lo[axis] || a[axis] >= hi[axis]) return false;
      continue;
    }
    double near = (lo[axis] - a[axis]) / d[axis];
    double far = (hi[axis] - a[axis]) / d[axis];
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
    if (t0 >= t1) return false;
  }
  return true;
}

Rectangle rect(const Eigen::Vector3d& origin, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return {origin, u, v};
}

}  // namespace

AnalyticScene planeScene(const SceneOptions& options) {
  std::mt19937 rng(options.seed);
  const auto points =
      samplePoints({rect({-12, -12, 0}, {24, 0, 0}, {0, 24, 0})}, options.density_per_m2, rng, {});
  std::vector<Camera> cameras;
  const Eigen::Vector3d forward = Eigen::Vector3d(1.0, 0.0, -std::tan(35.0 * M_PI / 180.0)).normalized();
  for (int k = 0; k < options.keyframes; ++k) {
    const double s = options.keyframes > 1 ? static_cast<double>(k) / (options.keyframes - 1) : 0.5;
    cameras.push_back({{-10.0 + 14.0 * s, 0.4 * std::sin(6.0 * s), 3.0}, forward});
  }
  AnalyticScene scene;
  scene.keyframes = observe(cameras, points, options, {});
  scene.in_free_space = [](const Eigen::Vector3d& p) { return p.z() > 0; };
  scene.free_probe_min = {-4, -1.5, 0.8};
  scene.free_probe_max = {4, 1.5, 2.4};
  scene.matter_probe_min = {-4, -4, -4};
  scene.matter_probe_max = {6, 4, -0.5};
  scene.expected_genus = 0;
  return scene;
}

AnalyticScene boxRoomScene(const SceneOptions& options) {
  std::mt19937 rng(options.seed);
  const double X = 12, Y = 9, Z = 3.5;
  const auto points = samplePoints(
      {rect({0, 0, 0}, {X, 0, 0}, {0, Y, 0}), rect({0, 0, Z}, {X, 0, 0}, {0, Y, 0}),
       rect({0, 0, 0}, {X, 0, 0}, {0, 0, Z}), rect({0, Y, 0}, {X, 0, 0}, {0, 0, Z}),
       rect({0, 0, 0}, {0, Y, 0}, {0, 0, Z}), rect({X, 0, 0}, {0, Y, 0}, {0, 0, Z})},
      options.density_per_m2, rng, {});
  const auto cameras = loopCameras(options.keyframes, 0.0, [](double angle) {
    return Eigen::Vector3d(6.0 + 4.0 * std::cos(angle), 4.5 + 3.0 * std::sin(angle), 1.5);
  });
  AnalyticScene scene;
  scene.keyframes = observe(cameras, points, options, {});
  scene.in_free_space = [=](const Eigen::Vector3d& p) {
    return p.x() > 0 && p.x() < X && p.y() > 0 && p.y() < Y && p.z() > 0 && p.z() < Z;
  };
  scene.free_probe_min = {2, 1.5, 0.6};
  scene.free_probe_max = {10, 7.5, 2.9};
  scene.matter_probe_min = {13, 0, 0};
  scene.matter_probe_max = {18, 9, 3.5};
  scene.expected_genus = 0;
  return scene;
}

AnalyticScene corridorScene(const SceneOptions& options) {
  std::mt19937 rng(options.seed);
  const double R = 10, P = 4, Z = 3;
  const auto outside_pillar = [=](const Eigen::Vector3d& p) {
    return std::abs(p.x()) > P || std::abs(p.y()) > P;
  };
  std::vector<Rectangle> surfaces = {
      rect({-R, -R, 0}, {2 * R, 0, 0}, {0, 2 * R, 0}), rect({-R, -R, Z}, {2 * R, 0, 0}, {0, 2 * R, 0}),
      rect({-R, -R, 0}, {2 * R, 0, 0}, {0, 0, Z}),     rect({-R, R, 0}, {2 * R, 0, 0}, {0, 0, Z}),
      rect({-R, -R, 0}, {0, 2 * R, 0}, {0, 0, Z}),     rect({R, -R, 0}, {0, 2 * R, 0}, {0, 0, Z}),
      rect({-P, -P, 0}, {2 * P, 0, 0}, {0, 0, Z}),     rect({-P, P, 0}, {2 * P, 0, 0}, {0, 0, Z}),
      rect({-P, -P, 0}, {0, 2 * P, 0}, {0, 0, Z}),     rect({P, -P, 0}, {0, 2 * P, 0}, {0, 0, Z})};
  const auto points = samplePoints(surfaces, options.density_per_m2, rng, [&](const Eigen::Vector3d& p) {
    // Floor and ceiling only around the pillar; pillar faces are kept (they lie on its border).
    const bool horizontal = p.z() == 0 || p.z() == Z;
    return !horizontal || outside_pillar(p);
  });
  const auto cameras = loopCameras(options.keyframes, 0.1, [](double angle) {
    return Eigen::Vector3d(7.0 * std::cos(angle), 7.0 * std::sin(angle), 1.5);
  });
  const Eigen::Vector3d pillar_lo(-P + 1e-6, -P + 1e-6, 0);
  const Eigen::Vector3d pillar_hi(P - 1e-6, P - 1e-6, Z);
  AnalyticScene scene;
  scene.keyframes = observe(cameras, points, options,
                            [&](const Eigen::Vector3d& camera, const Eigen::Vector3d& point) {
                              return !segmentCrossesBox(camera, point, pillar_lo, pillar_hi);
                            });
  scene.in_free_space = [=](const Eigen::Vector3d& p) {
    return std::abs(p.x()) < R && std::abs(p.y()) < R && p.z() > 0 && p.z() < Z && outside_pillar(p);
  };
  scene.free_probe_min = {5.5, -2.5, 0.6};
  scene.free_probe_max = {8.5, 2.5, 2.4};
  scene.matter_probe_min = {-3, -3, 0.5};
  scene.matter_probe_max = {3, 3, 2.5};
  scene.expected_genus = 1;
  return scene;
}

std::vector<mesher::Keyframe> withMovingEstimates(const std::vector<mesher::Keyframe>& keyframes,
                                                  double magnitude, std::uint32_t seed) {
  std::vector<mesher::Keyframe> result = keyframes;
  std::unordered_map<std::uint64_t, int> seen;
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (mesher::Keyframe& keyframe : result) {
    for (mesher::PointObservation& observation : keyframe.observations) {
      const int n = ++seen[observation.point.value];
      const Eigen::Vector3d direction(normal(rng), normal(rng), normal(rng));
      observation.position_W += direction.normalized() * (magnitude / n);
    }
  }
  return result;
}

std::vector<mesher::Keyframe> withFinalEstimates(const std::vector<mesher::Keyframe>& keyframes) {
  std::unordered_map<std::uint64_t, Eigen::Vector3d> final_position;
  for (const mesher::Keyframe& keyframe : keyframes) {
    for (const auto& observation : keyframe.observations) {
      final_position[observation.point.value] = observation.position_W;
    }
  }
  std::vector<mesher::Keyframe> result = keyframes;
  for (mesher::Keyframe& keyframe : result) {
    for (auto& observation : keyframe.observations) {
      observation.position_W = final_position.at(observation.point.value);
    }
  }
  return result;
}

mesher::AxisAlignedBox keyframeBounds(const std::vector<mesher::Keyframe>& keyframes) {
  mesher::AxisAlignedBox box{Eigen::Vector3d::Constant(1e300), Eigen::Vector3d::Constant(-1e300)};
  for (const mesher::Keyframe& keyframe : keyframes) {
    box.min_W = box.min_W.cwiseMin(keyframe.position_W_C);
    box.max_W = box.max_W.cwiseMax(keyframe.position_W_C);
    for (const auto& o : keyframe.observations) {
      box.min_W = box.min_W.cwiseMin(o.position_W);
      box.max_W = box.max_W.cwiseMax(o.position_W);
    }
  }
  return box;
}

}  // namespace terramesh::test
