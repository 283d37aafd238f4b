#include "primitives.h"

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace terramesh::datasets::synthetic {

Eigen::Isometry3d uprightFrame(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& heading_W,
                               const Eigen::Vector3d& up_W) {
  const Eigen::Vector3d z = up_W.normalized();
  const Eigen::Vector3d x = (heading_W - heading_W.dot(z) * z).normalized();
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear().col(0) = x;
  frame.linear().col(1) = z.cross(x);
  frame.linear().col(2) = z;
  frame.translation() = origin_W;
  return frame;
}

void addRectangle(LabeledMeshBuilder& builder, const Eigen::Vector3d& centre,
                  const Eigen::Vector3d& half_u, const Eigen::Vector3d& half_v, SurfaceLabel label) {
  builder.quad(centre - half_u - half_v, centre + half_u - half_v, centre + half_u + half_v,
               centre - half_u + half_v, label);
}

void addBox(LabeledMeshBuilder& builder, const Eigen::Isometry3d& T_W_B, const Eigen::Vector3d& size,
            SurfaceLabel sides, SurfaceLabel top) {
  const Eigen::Matrix3d& R = T_W_B.linear();
  const Eigen::Vector3d hx = R.col(0) * size.x() / 2, hy = R.col(1) * size.y() / 2,
                        hz = R.col(2) * size.z() / 2;
  const Eigen::Vector3d centre = T_W_B.translation() + hz;
  addRectangle(builder, centre + hx, hy, hz, sides);
  addRectangle(builder, centre - hx, -hy, hz, sides);
  addRectangle(builder, centre + hy, -hx, hz, sides);
  addRectangle(builder, centre - hy, hx, hz, sides);
  addRectangle(builder, centre + hz, hx, hy, top);
}

void addCylinder(LabeledMeshBuilder& builder, const Eigen::Vector3d& base_W, double radius_m,
                 double height_m, int segments, SurfaceLabel label) {
  const Eigen::Isometry3d frame = uprightFrame(base_W, Eigen::Vector3d::UnitX() + 0.1 * Eigen::Vector3d::UnitY(),
                                               builder.up());
  std::vector<std::uint32_t> bottom, top;
  for (int i = 0; i < segments; ++i) {
    const double angle = 2.0 * M_PI * i / segments;
    const Eigen::Vector3d ring(radius_m * std::cos(angle), radius_m * std::sin(angle), 0.0);
    bottom.push_back(builder.vertex(frame * ring));
    top.push_back(builder.vertex(frame * Eigen::Vector3d(ring.x(), ring.y(), height_m)));
  }
  const std::uint32_t cap = builder.vertex(frame * Eigen::Vector3d(0, 0, height_m));
  for (int i = 0; i < segments; ++i) {
    const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>((i + 1) % segments);
    builder.quad(bottom[a], bottom[b], top[b], top[a], label);
    builder.triangle(cap, top[a], top[b], label);
  }
}

void addBlob(LabeledMeshBuilder& builder, const Eigen::Vector3d& centre_W, double radius_m,
             double roughness, Rng& rng, SurfaceLabel label) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> points = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0},
                                         {0, -1, t}, {0, 1, t},  {0, -1, -t}, {0, 1, -t},
                                         {t, 0, -1}, {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::uint32_t, 3>> faces = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Eigen::Vector3d& p : points) p.normalize();
  for (auto& face : faces) {  // wind every face outwards; subdivision keeps the winding
    const Eigen::Vector3d& a = points[face[0]];
    if ((points[face[1]] - a).cross(points[face[2]] - a).dot(a) < 0) std::swap(face[1], face[2]);
  }
  for (int level = 0; level < 2; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoints.emplace(key, static_cast<std::uint32_t>(points.size()));
      if (inserted) points.push_back((points[a] + points[b]).normalized());
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    for (const auto& [a, b, c] : faces) {
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  // Three random smooth undulations of the radius.
  std::array<Eigen::Vector3d, 3> directions;
  std::array<double, 3> phases{};
  for (std::size_t k = 0; k < 3; ++k) {
    directions[k] = Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal()).normalized() * (1.5 + k);
    phases[k] = rng.uniform(0.0, 2.0 * M_PI);
  }
  std::vector<std::uint32_t> index(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    double wobble = 0.0;
    for (std::size_t k = 0; k < 3; ++k) wobble += std::sin(directions[k].dot(points[i]) + phases[k]) / 3.0;
    index[i] = builder.vertex(centre_W + radius_m * (1.0 + roughness * wobble) * points[i]);
  }
  for (const auto& [a, b, c] : faces) {
    builder.triangle(index[a], index[b], index[c], label);
  }
}

void addWedge(LabeledMeshBuilder& builder, const Eigen::Isometry3d& T_W_B, double length_m,
              double width_m, double height_m, double skirt_m, SurfaceLabel top, SurfaceLabel sides) {
  const double w = width_m / 2;
  auto at = [&](double x, double y, double z) { return T_W_B * Eigen::Vector3d(x, y, z); };
  builder.quad(at(0, -w, 0), at(length_m, -w, height_m), at(length_m, w, height_m), at(0, w, 0), top);
  // Right side (y = -w) faces -y, left side faces +y, high end faces +x.
  builder.quad(at(0, -w, -skirt_m), at(length_m, -w, -skirt_m), at(length_m, -w, height_m),
               at(0, -w, 0), sides);
  builder.quad(at(length_m, w, -skirt_m), at(0, w, -skirt_m), at(0, w, 0), at(length_m, w, height_m),
               sides);
  builder.quad(at(length_m, -w, -skirt_m), at(length_m, w, -skirt_m), at(length_m, w, height_m),
               at(length_m, -w, height_m), sides);
}

void addCar(LabeledMeshBuilder& builder, const Eigen::Isometry3d& T_W_B) {
  auto box = [&](double x, double y, double z, const Eigen::Vector3d& size) {
    Eigen::Isometry3d frame = T_W_B;
    frame.translation() = T_W_B * Eigen::Vector3d(x, y, z);
    addBox(builder, frame, size, SurfaceLabel::kObstacle, SurfaceLabel::kObstacle);
  };
  const double wheel_x = kCarLengthM / 2 - 0.8, wheel_y = kCarWidthM / 2 - 0.15;
  for (const double x : {-wheel_x, wheel_x}) {
    for (const double y : {-wheel_y, wheel_y}) box(x, y, 0.0, {0.65, 0.25, 0.35});
  }
  box(0.0, 0.0, 0.35, {kCarLengthM, kCarWidthM, 0.7});
  box(-0.3, 0.0, 1.05, {2.3, 1.6, 0.45});
}

}  // namespace terramesh::datasets::synthetic
