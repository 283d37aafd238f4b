#include "spatial_backends.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <vector>

namespace terramesh::bench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 toCgal(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }
Eigen::Vector3d toEigen(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

struct CgalTriangleTree::Impl {
  Triangles triangles;
  Tree tree;
};

CgalTriangleTree::CgalTriangleTree(const mesher::TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(mesh.faces.size());
  for (const auto& face : mesh.faces) {
    impl_->triangles.emplace_back(toCgal(mesh.vertices[face[0]]), toCgal(mesh.vertices[face[1]]),
                                  toCgal(mesh.vertices[face[2]]));
  }
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

CgalTriangleTree::~CgalTriangleTree() = default;

std::optional<datasets::RayHit> CgalTriangleTree::firstHit(const Eigen::Vector3d& origin,
                                                           const Eigen::Vector3d& direction,
                                                           double max_distance) const {
  const Eigen::Vector3d unit = direction.normalized();
  const Kernel::Ray_3 ray(toCgal(origin), Kernel::Vector_3(unit.x(), unit.y(), unit.z()));
  const auto hit = impl_->tree.first_intersection(ray);
  if (!hit) return std::nullopt;
  Eigen::Vector3d point;
  if (const auto* p = boost::get<Kernel::Point_3>(&hit->first)) {
    point = toEigen(*p);
  } else {
    // The ray runs inside a face's plane: the hit is the segment's end nearer the origin.
    const auto& segment = boost::get<Kernel::Segment_3>(hit->first);
    const Eigen::Vector3d s = toEigen(segment.source()), t = toEigen(segment.target());
    point = (s - origin).norm() <= (t - origin).norm() ? s : t;
  }
  const double distance = (point - origin).norm();
  if (distance > max_distance) return std::nullopt;
  datasets::RayHit result;
  result.distance = distance;
  result.point = point;
  result.face = static_cast<std::uint32_t>(hit->second - impl_->triangles.begin());
  return result;
}

datasets::SurfacePoint CgalTriangleTree::closestPoint(const Eigen::Vector3d& query) const {
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(toCgal(query));
  datasets::SurfacePoint result;
  result.point = toEigen(point);
  result.distance = (result.point - query).norm();
  result.face = static_cast<std::uint32_t>(primitive - impl_->triangles.begin());
  return result;
}

}  // namespace terramesh::bench
