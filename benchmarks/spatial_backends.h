#pragma once

// Library-backed spatial queries with the same contracts as datasets::TriangleBvh (firstHit,
// closestPoint) and datasets::PointCloudIndex (nearest within a radius), for the comparison in
// spatial_queries_benchmark.cpp and its agreement test. Benchmark-only code: the evaluation uses
// the datasets classes (docs/benchmarks.md, "Spatial queries", says why).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "datasets/point_cloud_index.h"
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

#ifdef TERRAMESH_HAVE_EMBREE
/// Embree 3 (single precision, no back-face culling) over the mesh's triangles: rtcIntersect1 for
/// rays, rtcPointQuery with an exact closest-point-on-triangle callback (in double) for distances.
class EmbreeTriangleScene {
 public:
  explicit EmbreeTriangleScene(const mesher::TriangleMesh& mesh);
  ~EmbreeTriangleScene();
  std::optional<datasets::RayHit> firstHit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                           double max_distance) const;
  datasets::SurfacePoint closestPoint(const Eigen::Vector3d& query) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
#endif

/// nanoflann's k-d tree (leaf size 10) over a point cloud: the nearest point, kept when within
/// `max_distance_m` (nanoflann 1.4 has no bounded 1-NN search).
class NanoflannCloud {
 public:
  explicit NanoflannCloud(std::vector<Eigen::Vector3d> points);
  ~NanoflannCloud();
  std::optional<datasets::PointCloudIndex::Nearest> nearest(const Eigen::Vector3d& query,
                                                            double max_distance_m) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

}  // namespace terramesh::bench
