#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

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

/// Ray casting, visibility and nearest-surface queries on the faces of a triangle mesh, on
/// Embree 3's bounding-volume hierarchy. All positions are in the frame of the mesh and in its
/// units; answers are in double precision.
///
/// Embree searches in single precision (robust mode, so a closed mesh stays closed); every face it
/// reports is then measured again in double: watertight ray-triangle tests (Woop, Benthin and
/// Wald, JCGT 2013) and exact point-triangle distances, with Embree's search widened by its float
/// rounding so that faces tied or nearly tied in double precision are all compared. The answers
/// are therefore those of an exact double-precision search except for rays that graze an edge or
/// a silhouette within float rounding (about 1e-7 of the scene's size), which may hit or miss.
/// Faces are hit from both sides (no back-face culling). Zero-area faces are never hit by rays
/// but can be the closest face.
///
/// Building is O(F log F); a query visits O(log F) nodes on typical scenes. The tree keeps its
/// own copy of the geometry: the mesh may be destroyed after construction. All const member
/// functions are thread-safe (Embree queries are; the per-query state lives on the stack).
class TriangleBvh {
 public:
  /// Builds the tree over every face of `mesh`. An empty mesh gives an empty tree.
  /// @throw std::invalid_argument if a face indexes a missing vertex or a vertex is not finite;
  /// std::runtime_error if Embree fails (no supported CPU, out of memory).
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

  /// Every face with a point within `radius` of `centre` (exact double-precision distances), in
  /// increasing face index. Empty for an empty tree or a negative radius.
  /// @throw std::invalid_argument if `centre` or `radius` is not finite.
  std::vector<std::uint32_t> facesWithin(const Eigen::Vector3d& centre, double radius) const;

  /// Number of faces in the tree.
  std::size_t faceCount() const;
  /// Axis-aligned box around every vertex used by a face (empty box for an empty tree).
  Eigen::AlignedBox3d bounds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terramesh::datasets
