#pragma once

// Closest points on segments and triangles, in double precision.
#include <Eigen/Core>

namespace terramesh::geometry {

/// What `closestPointOnTriangle` does with a (nearly) zero-area triangle.
enum class DegenerateTriangles {
  /// |ab x ac|^2 <= 1e-24 max(|ab|^2, |ac|^2)^2: the triangle is its three edges (the nearest of
  /// the three segment answers, the first on ties).
  kAsEdges,
  /// No test: Ericson's region tests as they are, for callers whose triangles have a non-zero
  /// normal (on a sliver the interior answer may be far off, or not finite).
  kUnchecked,
};

/// The point of the segment [a, b] nearest to p; a if the segment has zero length.
Eigen::Vector3d closestPointOnSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection, 5.1.5),
/// either winding, any units. O(1), thread-safe.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c,
                                       DegenerateTriangles degenerate = DegenerateTriangles::kAsEdges);

}  // namespace terramesh::geometry
