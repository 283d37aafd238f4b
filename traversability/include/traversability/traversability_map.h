#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "mesher/mesher.h"
#include "mesher/surface_delta.h"
#include "mesher/triangle_mesh.h"
#include "traversability/layered_mesh.h"
#include "traversability/robot_profile.h"

namespace terramesh::traversability {

/// How the map frame relates to the world: what "up" is and how large a map unit is.
struct MapFrame {
  /// Unit vector against gravity, in the map frame.
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  double metres_per_unit = 1.0;
  /// @throw std::invalid_argument if up_W is not finite and non-zero or the scale is not > 0.
  void validate() const;
};

/// Estimates "up" from sensor orientations: the mean of the sensors' up axes, normalised. `up_C` is
/// the axis of the sensor frame that points up when the sensor is level: -y for an OpenCV/KITTI
/// camera (x right, y down, z forward; the default), +z for a Velodyne (x forward, z up).
/// @throw std::invalid_argument if there are no rotations, `up_C` is zero or they cancel out.
Eigen::Vector3d estimateUpFromCameras(const std::vector<Eigen::Matrix3d>& rotations_W_C,
                                      const Eigen::Vector3d& up_C = -Eigen::Vector3d::UnitY());

/// What one TraversabilityMap update did (returned, never logged).
struct LayerUpdateStats {
  std::size_t faces_added = 0;
  std::size_t faces_removed = 0;
  std::size_t faces_recomputed = 0;  ///< faces whose layers (or only cost/class) were computed again
  std::size_t faces_reobserved = 0;  ///< faces whose observation count changed without re-adding
  /// Faces of the delta removed and re-added with identical vertices and positions (mesher churn,
  /// counted in faces_added and faces_removed too): only their observation count is re-read.
  std::size_t faces_readded_unchanged = 0;
  std::size_t faces_total = 0;       ///< faces in the map after the update
  /// Everything was recomputed: the delta was incomplete, or replaced at least half of the map's
  /// faces (update() then rebuilds, which costs less than an update reaching every footprint).
  bool full_rebuild = false;
  /// SLAM points the mesher holds but has not inserted (possible obstacles), after the update.
  std::size_t unconfirmed_points = 0;
  double seconds = 0;                ///< wall-clock time of the update
};

/// Where the robot stood when it put a driven-ground sample (mesher::PointKind::kDrivenGround)
/// down: its base frame's pose in the map frame (map units; x forward), or nullopt if the sample
/// is unknown (TrajectoryEvidence::baseOf).
using DrivePoseLookup = std::function<std::optional<Eigen::Isometry3d>(mesher::PointId)>;

/// Per-face traversability layers of a surface, for one robot, kept current incrementally.
///
/// Feed it the mesher's surface deltas (or a whole surface); it recomputes only the faces whose
/// footprint, clearance column or inflation radius reaches a changed face. Not thread-safe.
class TraversabilityMap {
 public:
  /// @throw std::invalid_argument if the profile or frame does not validate.
  TraversabilityMap(const RobotProfile& profile, const MapFrame& frame);
  ~TraversabilityMap();
  TraversabilityMap(TraversabilityMap&&) noexcept;
  TraversabilityMap& operator=(TraversabilityMap&&) noexcept;

  /// Brings the layers from the surface `mesher` had at `from_revision` (the revision this map was
  /// last brought to) to its current surface and unconfirmed points: setUnconfirmedPoints(
  /// unconfirmedPoints()) with apply(changesSince(from_revision), facesAround(touched_vertices)),
  /// or reset(surfaceFaces()) when that history is forgotten or the change replaces at least half
  /// of the map's faces.
  /// Afterwards every layer, `rays` included, equals reset(mesher.surfaceFaces()) exactly; the next
  /// call continues from mesher.revision(). Cost proportional to the change (except a reset).
  /// @throw std::invalid_argument if `from_revision` is newer than mesher.revision().
  LayerUpdateStats update(const mesher::Mesher& mesher, std::uint64_t from_revision);

  /// Applies one delta from mesher::Mesher::changesSince and updates the layers that it affects.
  /// `faces_around_touched` carries the fresh observation counts of the faces around
  /// `delta.touched_vertices` (mesher::Mesher::facesAround): a ray gained or lost by a vertex, or
  /// crossing the free cell in front of a face, changes the count of faces that are not re-added,
  /// and only this list tells. Faces whose count changed are re-judged (known / unknown) with the
  /// inflation around them; faces of the list that are not in the map are ignored. Pass an empty
  /// list only for a delta whose `added` faces carry every count that changed (hand-made deltas);
  /// update() does both steps for a Mesher. With the list, the map after any sequence of updates
  /// equals reset(mesher.surfaceFaces()) exactly. An incomplete delta must be followed by reset().
  /// @throw std::invalid_argument if `delta.complete` is false.
  LayerUpdateStats apply(const mesher::SurfaceDelta& delta,
                         const std::vector<mesher::SurfaceFace>& faces_around_touched);

  /// Replaces the whole surface and recomputes every layer (with the unconfirmed points last set).
  LayerUpdateStats reset(const std::vector<mesher::SurfaceFace>& faces);

  /// Replaces the SLAM points the mesher has not inserted (mesher::Mesher::unconfirmedPoints,
  /// which update() reads by itself) and re-judges the faces whose body they reach: inside it
  /// (between max_step_m and min_clearance_m above a face), such a point is a possible obstacle
  /// of radius EvidenceModel::unconfirmed_point_extension_m, making the face uncertain, never
  /// lethal. Faces on driven ground ignore them (the drive contradicts an unconfirmed point).
  LayerUpdateStats setUnconfirmedPoints(const std::vector<mesher::UnconfirmedPoint>& points);

  /// Sets where the robot stood on the driven-ground samples. A face on driven ground then knows the
  /// centre line and axis of the drive there (the mean of its vertices' bases): the drive
  /// contradicts obstacles only inside the strip its body swept (half the footprint's width, or
  /// its radius, on each side of that line), not beyond it; and a rectangle is also judged turned
  /// along the drive, besides the profile's contact_headings. Read when a face is added: set it
  /// before the first update (or reset() after). Without it, every obstacle over driven ground
  /// counts as swept. `sensor_height_m`, the drive's sensor above the ground contact plane (the
  /// height the samples use), bounds the body that interpolated geometry beside the strip can
  /// reach: no ray looks above the sensor there (LayerComputer::setDriveSensorHeight). Without it,
  /// that geometry counts up to min_clearance_m.
  void setDrivePoses(DrivePoseLookup lookup, std::optional<double> sensor_height_m = std::nullopt);

  /// Layers of a finished mesh (e.g. read from PLY). Faces touching a vertex flagged in
  /// `mesh.is_steiner` are unmeasured; without the flags every face counts as measured. Faces take
  /// the mesh's observation counts (`face_rays`, `face_front_crossings`: terramesh's own meshes);
  /// without them every other face is given `rays_if_unknown` rays, all counted as observed in
  /// front.
  static LayeredMesh computeForMesh(const mesher::TriangleMesh& mesh, const RobotProfile& profile,
                                    const MapFrame& frame, std::uint32_t rays_if_unknown);

  /// The current map as a mesh with its layers, faces sorted by key. O(F log F).
  LayeredMesh snapshot() const;

  std::size_t faceCount() const;
  const RobotProfile& profile() const;
  const MapFrame& frame() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terramesh::traversability
