#pragma once

// CGAL's AABB_tree with the contracts of datasets::TriangleBvh (firstHit, closestPoint), for the
// comparison in spatial_queries_benchmark.cpp and its agreement test. Benchmark-only code: the
// project's queries run on Embree and nanoflann (docs/benchmarks.md, "Spatial queries").
#include <Eigen/Core>
#include <memory>
#include <optional>

#include "datasets/triangle_bvh.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::bench {

/// CGAL's AABB_tree over the mesh's triangles (Epick kernel, doubles). Rays are cast with
/// first_intersection (a ray, cut at `max_distance` afterwards: the tree has no bounded query);
/// closest points with closest_point_and_primitive after accelerate_distance_queries().
class CgalTriangleTree {
 public:
  explicit CgalTriangleTree(const mesher::TriangleMesh& mesh);
  ~CgalTriangleTree();
  std::optional<datasets::RayHit> firstHit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                           double max_distance) const;
  datasets::SurfacePoint closestPoint(const Eigen::Vector3d& query) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terramesh::bench
