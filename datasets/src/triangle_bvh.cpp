#include "datasets/triangle_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace terramesh::datasets {
namespace {

constexpr int kMaxLeafFaces = 4;
constexpr int kSahBins = 16;
// Past this depth the builder splits at the object median, which bounds the total depth by
// kMedianSplitDepth + log2(F) and so the fixed traversal stacks below.
constexpr int kMedianSplitDepth = 40;
constexpr int kStackSize = 128;

struct Triangle {
  Eigen::Vector3d v0, v1, v2;
  std::uint32_t face;
};

/// Internal node: children are at index + 1 and `right`. Leaf: faces [first, first + count).
struct Node {
  Eigen::AlignedBox3d box;
  std::uint32_t first_or_right = 0;
  std::uint32_t count = 0;
};

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

/// Per-ray constants of the watertight test: the dominant axis kz and the shear that maps the
/// direction onto +z.
struct PreparedRay {
  Eigen::Vector3d origin;
  Eigen::Vector3d inverse_direction;
  int kx = 0, ky = 1, kz = 2;
  double shear_x = 0, shear_y = 0, shear_z = 1;

  PreparedRay(const Eigen::Vector3d& o, const Eigen::Vector3d& unit_direction) : origin(o) {
    Eigen::Index axis = 0;
    unit_direction.cwiseAbs().maxCoeff(&axis);
    kz = static_cast<int>(axis);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (unit_direction[kz] < 0) std::swap(kx, ky);  // keeps the winding of the sheared triangle
    shear_x = unit_direction[kx] / unit_direction[kz];
    shear_y = unit_direction[ky] / unit_direction[kz];
    shear_z = 1.0 / unit_direction[kz];
    for (int i = 0; i < 3; ++i) {
      // A tiny stand-in for zero keeps the slab test free of 0 * inf.
      const double d = unit_direction[i];
      const double safe = std::abs(d) < 1e-300 ? std::copysign(1e-300, d) : d;
      inverse_direction[i] = 1.0 / safe;
    }
  }

  /// Parameter interval [near, far] of the ray inside `box`, intersected with [t_min, t_max].
  bool hitsBox(const Eigen::AlignedBox3d& box, double t_min, double t_max) const {
    double near = t_min;
    double far = t_max;
    for (int i = 0; i < 3; ++i) {
      double t0 = (box.min()[i] - origin[i]) * inverse_direction[i];
      double t1 = (box.max()[i] - origin[i]) * inverse_direction[i];
      if (t0 > t1) std::swap(t0, t1);
      near = std::max(near, t0);
      far = std::min(far, t1 * (1.0 + 4.0 * std::numeric_limits<double>::epsilon()));
    }
    return near <= far;
  }

  /// Watertight ray-triangle test; returns the ray parameter of the hit in [t_min, t_max].
  std::optional<double> hitTriangle(const Triangle& tri, double t_min, double t_max) const {
    const Eigen::Vector3d a = tri.v0 - origin;
    const Eigen::Vector3d b = tri.v1 - origin;
    const Eigen::Vector3d c = tri.v2 - origin;
    const double ax = a[kx] - shear_x * a[kz], ay = a[ky] - shear_y * a[kz];
    const double bx = b[kx] - shear_x * b[kz], by = b[ky] - shear_y * b[kz];
    const double cx = c[kx] - shear_x * c[kz], cy = c[ky] - shear_y * c[kz];
    double u = cx * by - cy * bx;
    double v = ax * cy - ay * cx;
    double w = bx * ay - by * ax;
    if (u == 0.0 || v == 0.0 || w == 0.0) {
      // On an edge in double precision: decide it in extended precision, as the paper does.
      using Long = long double;
      u = static_cast<double>(Long(cx) * Long(by) - Long(cy) * Long(bx));
      v = static_cast<double>(Long(ax) * Long(cy) - Long(ay) * Long(cx));
      w = static_cast<double>(Long(bx) * Long(ay) - Long(by) * Long(ax));
    }
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return std::nullopt;
    const double det = u + v + w;
    if (det == 0.0) return std::nullopt;
    const double t = (u * shear_z * a[kz] + v * shear_z * b[kz] + w * shear_z * c[kz]) / det;
    if (!(t >= t_min && t <= t_max)) return std::nullopt;
    return t;
  }
};

/// Closest point to `p` on the segment [a, b].
Eigen::Vector3d closestOnSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 == 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
  return a + t * ab;
}

/// Closest point to `p` on a triangle (Ericson, Real-Time Collision Detection, 5.1.5); degenerate
/// triangles fall back to their edges.
Eigen::Vector3d closestOnTriangle(const Eigen::Vector3d& p, const Triangle& tri) {
  const Eigen::Vector3d& a = tri.v0;
  const Eigen::Vector3d& b = tri.v1;
  const Eigen::Vector3d& c = tri.v2;
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double scale = std::max(ab.squaredNorm(), ac.squaredNorm());
  if (ab.cross(ac).squaredNorm() <= 1e-24 * scale * scale) {
    const Eigen::Vector3d candidates[3] = {closestOnSegment(p, a, b), closestOnSegment(p, b, c),
                                           closestOnSegment(p, c, a)};
    const Eigen::Vector3d* best = &candidates[0];
    for (const Eigen::Vector3d& q : candidates) {
      if ((q - p).squaredNorm() < (*best - p).squaredNorm()) best = &q;
    }
    return *best;
  }
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

Eigen::AlignedBox3d triangleBox(const Triangle& tri) {
  Eigen::AlignedBox3d box(tri.v0);
  box.extend(tri.v1);
  box.extend(tri.v2);
  return box;
}

/// Grows a box by a relative margin so that rounding in the slab test never culls a face the
/// exact triangle test would hit.
Eigen::AlignedBox3d padded(const Eigen::AlignedBox3d& box) {
  const double magnitude = std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff());
  const double pad = 1e-9 * magnitude + 1e-12;
  return Eigen::AlignedBox3d(box.min().array() - pad, box.max().array() + pad);
}

}  // namespace

struct TriangleBvh::Impl {
  std::vector<Node> nodes;
  std::vector<Triangle> triangles;  // in leaf order
  Eigen::AlignedBox3d bounds;

  struct BuildItem {
    Eigen::AlignedBox3d box;
    Eigen::Vector3d centroid;
    std::uint32_t face;
  };

  void build(std::vector<BuildItem>& items, const std::vector<Triangle>& by_face) {
    if (items.empty()) return;
    nodes.reserve(2 * items.size() / kMaxLeafFaces + 1);
    buildNode(items, 0, items.size(), 0);
    triangles.reserve(items.size());
    for (const BuildItem& item : items) triangles.push_back(by_face[item.face]);
  }

  /// Builds the subtree over items [begin, end) and returns its node index.
  std::uint32_t buildNode(std::vector<BuildItem>& items, std::size_t begin, std::size_t end, int depth) {
    const auto index = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    Eigen::AlignedBox3d box;
    Eigen::AlignedBox3d centroid_box;
    for (std::size_t i = begin; i < end; ++i) {
      box.extend(items[i].box);
      centroid_box.extend(items[i].centroid);
    }
    nodes[index].box = padded(box);
    const std::size_t count = end - begin;
    Eigen::Index axis = 0;
    const double extent = centroid_box.sizes().maxCoeff(&axis);
    if (count <= static_cast<std::size_t>(kMaxLeafFaces) || extent <= 0.0) {
      makeLeaf(index, begin, count);
      return index;
    }
    std::size_t middle = begin;
    if (depth < kMedianSplitDepth) middle = sahSplit(items, begin, end, centroid_box, static_cast<int>(axis));
    if (middle == begin || middle == end) {
      middle = begin + count / 2;
      std::nth_element(items.begin() + static_cast<std::ptrdiff_t>(begin),
                       items.begin() + static_cast<std::ptrdiff_t>(middle),
                       items.begin() + static_cast<std::ptrdiff_t>(end),
                       [axis](const BuildItem& x, const BuildItem& y) {
                         return x.centroid[axis] < y.centroid[axis];
                       });
    }
    buildNode(items, begin, middle, depth + 1);
    const std::uint32_t right = buildNode(items, middle, end, depth + 1);
    nodes[index].first_or_right = right;
    return index;
  }

  void makeLeaf(std::uint32_t index, std::size_t begin, std::size_t count) {
    nodes[index].first_or_right = static_cast<std::uint32_t>(begin);
    nodes[index].count = static_cast<std::uint32_t>(count);
  }

  /// Binned surface-area heuristic along `axis`; partitions the items and returns the split
  /// position, or `begin` when keeping a leaf is cheaper (only for small counts).
  static std::size_t sahSplit(std::vector<BuildItem>& items, std::size_t begin, std::size_t end,
                              const Eigen::AlignedBox3d& centroid_box, int axis) {
    struct Bin {
      Eigen::AlignedBox3d box;
      std::size_t count = 0;
    };
    std::array<Bin, kSahBins> bins;
    const double lo = centroid_box.min()[axis];
    const double scale = kSahBins / (centroid_box.max()[axis] - lo);
    auto binOf = [&](const BuildItem& item) {
      const int bin = static_cast<int>((item.centroid[axis] - lo) * scale);
      return std::clamp(bin, 0, kSahBins - 1);
    };
    for (std::size_t i = begin; i < end; ++i) {
      Bin& bin = bins[static_cast<std::size_t>(binOf(items[i]))];
      bin.box.extend(items[i].box);
      ++bin.count;
    }
    auto area = [](const Eigen::AlignedBox3d& box) {
      if (box.isEmpty()) return 0.0;
      const Eigen::Vector3d s = box.sizes();
      return s.x() * s.y() + s.y() * s.z() + s.z() * s.x();
    };
    std::array<double, kSahBins - 1> right_cost{};
    Eigen::AlignedBox3d accumulated;
    std::size_t accumulated_count = 0;
    for (int i = kSahBins - 1; i > 0; --i) {
      accumulated.extend(bins[static_cast<std::size_t>(i)].box);
      accumulated_count += bins[static_cast<std::size_t>(i)].count;
      right_cost[static_cast<std::size_t>(i - 1)] = area(accumulated) * static_cast<double>(accumulated_count);
    }
    accumulated.setEmpty();
    accumulated_count = 0;
    double best_cost = std::numeric_limits<double>::infinity();
    int best_split = -1;
    for (int i = 0; i < kSahBins - 1; ++i) {
      accumulated.extend(bins[static_cast<std::size_t>(i)].box);
      accumulated_count += bins[static_cast<std::size_t>(i)].count;
      const double cost = area(accumulated) * static_cast<double>(accumulated_count) +
                          right_cost[static_cast<std::size_t>(i)];
      if (cost < best_cost) {
        best_cost = cost;
        best_split = i;
      }
    }
    if (best_split < 0) return begin;
    const auto middle = std::partition(items.begin() + static_cast<std::ptrdiff_t>(begin),
                                       items.begin() + static_cast<std::ptrdiff_t>(end),
                                       [&](const BuildItem& item) { return binOf(item) <= best_split; });
    return static_cast<std::size_t>(middle - items.begin());
  }

  /// Visits the leaves whose boxes the ray meets, near child first. `visit(triangle, t_max)`
  /// returns the new t_max (shrinking it prunes the traversal) or a negative number to stop.
  template <class Visit>
  void traverseRay(const PreparedRay& ray, double t_min, double t_max, Visit&& visit) const {
    if (nodes.empty()) return;
    std::uint32_t stack[kStackSize];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes[stack[--top]];
      if (!ray.hitsBox(node.box, t_min, t_max)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first_or_right; i < node.first_or_right + node.count; ++i) {
          t_max = visit(triangles[i], t_max);
          if (t_max < 0) return;
        }
        continue;
      }
      const std::uint32_t left = static_cast<std::uint32_t>(&node - nodes.data()) + 1;
      const std::uint32_t right = node.first_or_right;
      // Push the far child first so the near one (along the dominant axis) is visited first.
      const bool left_nearer = nodes[left].box.center()[ray.kz] <= nodes[right].box.center()[ray.kz];
      const bool left_first = left_nearer == (ray.inverse_direction[ray.kz] > 0);
      stack[top++] = left_first ? right : left;
      stack[top++] = left_first ? left : right;
    }
  }
};

TriangleBvh::TriangleBvh(const mesher::TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  std::vector<Triangle> by_face;
  by_face.reserve(mesh.faces.size());
  std::vector<Impl::BuildItem> items;
  items.reserve(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    Triangle tri;
    Eigen::Vector3d* corners[3] = {&tri.v0, &tri.v1, &tri.v2};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t vertex = mesh.faces[f][static_cast<std::size_t>(k)];
      if (vertex >= mesh.vertices.size()) {
        throw std::invalid_argument("TriangleBvh: face " + std::to_string(f) + " uses vertex " +
                                    std::to_string(vertex) + " of " +
                                    std::to_string(mesh.vertices.size()));
      }
      if (!finite(mesh.vertices[vertex])) {
        throw std::invalid_argument("TriangleBvh: vertex " + std::to_string(vertex) + " is not finite");
      }
      *corners[k] = mesh.vertices[vertex];
    }
    tri.face = static_cast<std::uint32_t>(f);
    const Eigen::AlignedBox3d box = triangleBox(tri);
    impl_->bounds.extend(box);
    items.push_back({box, (tri.v0 + tri.v1 + tri.v2) / 3.0, tri.face});
    by_face.push_back(tri);
  }
  impl_->build(items, by_face);
}

TriangleBvh::~TriangleBvh() = default;
TriangleBvh::TriangleBvh(TriangleBvh&&) noexcept = default;
TriangleBvh& TriangleBvh::operator=(TriangleBvh&&) noexcept = default;

std::size_t TriangleBvh::faceCount() const { return impl_->triangles.size(); }

Eigen::AlignedBox3d TriangleBvh::bounds() const { return impl_->bounds; }

std::optional<RayHit> TriangleBvh::firstHit(const Eigen::Vector3d& origin,
                                            const Eigen::Vector3d& direction,
                                            double max_distance) const {
  const double length = direction.norm();
  if (!origin.allFinite() || !direction.allFinite() || length == 0.0) {
    throw std::invalid_argument("TriangleBvh::firstHit: origin and direction must be finite, "
                                "direction non-zero");
  }
  const Eigen::Vector3d unit = direction / length;
  const PreparedRay ray(origin, unit);
  double best_t = std::numeric_limits<double>::infinity();
  std::uint32_t best_face = 0;
  impl_->traverseRay(ray, 0.0, max_distance, [&](const Triangle& tri, double t_max) {
    const std::optional<double> t = ray.hitTriangle(tri, 0.0, t_max);
    if (t && (*t < best_t || (*t == best_t && tri.face < best_face))) {
      best_t = *t;
      best_face = tri.face;
    }
    return std::min(t_max, best_t);
  });
  if (!std::isfinite(best_t)) return std::nullopt;
  return RayHit{best_t, best_face, origin + best_t * unit};
}

bool TriangleBvh::segmentOccluded(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  double tolerance) const {
  if (!a.allFinite() || !b.allFinite() || !(tolerance >= 0.0)) {
    throw std::invalid_argument("TriangleBvh::segmentOccluded: ends must be finite and tolerance >= 0");
  }
  const double length = (b - a).norm();
  if (length <= 2.0 * tolerance) return false;
  const PreparedRay ray(a, (b - a) / length);
  const double t_min = tolerance;
  const double t_max = length - tolerance;
  bool occluded = false;
  impl_->traverseRay(ray, t_min, t_max, [&](const Triangle& tri, double current_max) {
    const std::optional<double> t = ray.hitTriangle(tri, t_min, current_max);
    if (t && *t > t_min && *t < t_max) {
      occluded = true;
      return -1.0;
    }
    return current_max;
  });
  return occluded;
}

SurfacePoint TriangleBvh::closestPoint(const Eigen::Vector3d& query) const {
  if (impl_->nodes.empty()) throw std::logic_error("TriangleBvh::closestPoint: the tree is empty");
  if (!query.allFinite()) throw std::invalid_argument("TriangleBvh::closestPoint: query not finite");
  const std::vector<Node>& nodes = impl_->nodes;
  double best_d2 = std::numeric_limits<double>::infinity();
  SurfacePoint best;
  std::uint32_t stack[kStackSize];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t index = stack[--top];
    const Node& node = nodes[index];
    if (node.box.squaredExteriorDistance(query) > best_d2) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first_or_right; i < node.first_or_right + node.count; ++i) {
        const Triangle& tri = impl_->triangles[i];
        const Eigen::Vector3d point = closestOnTriangle(query, tri);
        const double d2 = (point - query).squaredNorm();
        if (d2 < best_d2 || (d2 == best_d2 && tri.face < best.face)) {
          best_d2 = d2;
          best.point = point;
          best.face = tri.face;
        }
      }
      continue;
    }
    const std::uint32_t left = index + 1;
    const std::uint32_t right = node.first_or_right;
    const double d_left = nodes[left].box.squaredExteriorDistance(query);
    const double d_right = nodes[right].box.squaredExteriorDistance(query);
    // Nearer child on top of the stack: it tightens best_d2 before the other is examined.
    stack[top++] = d_left <= d_right ? right : left;
    stack[top++] = d_left <= d_right ? left : right;
  }
  best.distance = std::sqrt(best_d2);
  return best;
}

}  // namespace terramesh::datasets
