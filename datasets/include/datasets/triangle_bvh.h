#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>

#include "mesher/triangle_mesh.h"

namespace terramesh::datasets {

/// Where a ray first meets a surface.
struct RayHit {
  /// Distance from the ray origin along the unit direction, in mesh units.
  double distance = 0.0;
  /// Index of the face hit in the mesh the tree was built from.
  std::uint32_t face = 0;
  /// The hit point, in the mesh's frame.
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

/// The point of a surface nearest to a query point.
struct SurfacePoint {
  /// The closest surface point, in the mesh's frame.
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  /// Euclidean distance from the query to `point`, in mesh units.
  double distance = 0.0;
  /// Index of the face `point` lies on.
  std::uint32_t face = 0;
};

/// A bounding-volume hierarchy over the faces of a triangle mesh, for ray casting, visibility and
/// nearest-surface queries. All positions are in the frame of the mesh and in its units.
///
/// Faces are hit from both sides (no back-face culling). Ray-triangle tests are watertight
/// (Woop, Benthin and Wald, JCGT 2013): a ray through an edge or vertex shared by several faces
/// hits at least one of them, so rays never leak through the seams of a closed mesh. Zero-area
/// faces are never hit by rays but can be the closest face.
///
/// Building is O(F log F) (binned surface-area heuristic); a query visits O(log F) nodes on
/// typical scenes. The tree keeps its own copy of the geometry: the mesh may be destroyed after
/// construction. All const member functions are thread-safe (they use no shared mutable state).
class TriangleBvh {
 public:
  /// Builds the tree over every face of `mesh`. An empty mesh gives an empty tree.
  /// @throw std::invalid_argument if a face indexes a missing vertex or a vertex is not finite.
  explicit TriangleBvh(const mesher::TriangleMesh& mesh);
  ~TriangleBvh();
  TriangleBvh(TriangleBvh&&) noexcept;
  TriangleBvh& operator=(TriangleBvh&&) noexcept;
  TriangleBvh(const TriangleBvh&) = delete;
  TriangleBvh& operator=(const TriangleBvh&) = delete;

  /// The first surface met by the ray `origin + t * direction / |direction|` for 0 <= t <=
  /// `max_distance` (mesh units), or nothing. Ties between faces at the same distance go to the
  /// lowest face index, so results do not depend on the tree's layout.
  /// @throw std::invalid_argument if `direction` is zero or not finite, or `origin` not finite.
  std::optional<RayHit> firstHit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                 double max_distance = std::numeric_limits<double>::infinity()) const;

  /// Whether a surface crosses the segment from `a` to `b` strictly between `tolerance` of
  /// either end (mesh units): the visibility test between a camera centre `a` and a point `b` on
  /// a surface, where the surface at `b` itself must not count. Stops at the first such hit.
  /// A segment shorter than 2 * `tolerance` is never occluded.
  /// @throw std::invalid_argument if an end is not finite or `tolerance` is negative.
  bool segmentOccluded(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tolerance) const;

  /// The surface point nearest to `query`. Ties go to the lowest face index.
  /// @throw std::logic_error if the tree is empty; std::invalid_argument if `query` is not finite.
  SurfacePoint closestPoint(const Eigen::Vector3d& query) const;

  /// Number of faces in the tree.
  std::size_t faceCount() const;
  /// Axis-aligned box around every vertex used by a face (empty box for an empty tree).
  Eigen::AlignedBox3d bounds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terramesh::datasets
