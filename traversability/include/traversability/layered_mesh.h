#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "mesher/surface_delta.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::traversability {

/// Class of a face for a given robot. The numeric values are written to files: never renumber.
enum class FaceClass : std::uint8_t {
  kFree = 0,     ///< known and drivable, with a cost in [0, 1]
  kLethal = 1,   ///< known and not drivable
  kUnknown = 2,  ///< not measured (touches a Steiner vertex) or seen by too few rays
  /// Measured, but the evidence cannot decide: the robot fits on the surface as reconstructed,
  /// not in the worst case within the surface's height uncertainty (a possible step, unsupported
  /// footprint, a possible obstacle or the possible extension of a sparsely measured one); or
  /// only interpolated geometry makes it lethal. Never silently free, never lethal by invention.
  kUncertain = 3,
};

/// Where a face's geometry comes from. The numeric values are written to files: never renumber.
enum class Evidence : std::uint8_t {
  kMeasured = 0,      ///< SLAM points, with rays through the free space in front of the face
  kDriven = 1,        ///< every vertex a driven-ground sample: under the robot's own trajectory
  kInterpolated = 2,  ///< closing (Steiner) geometry, or a span no ray observed
};

/// Every layer of one face, in metres and degrees (map units times metres_per_unit).
///
/// A layer that cannot be computed is NaN (e.g. step on a wall, clearance with no measured face
/// above within the search height, which is reported as +infinity instead).
struct FaceLayers {
  float slope_deg = 0;     ///< angle between the face normal and "up"
  /// Largest height jump within the footprint centred on the face (a rectangle: at its best
  /// heading, one where it fits if any; see docs/traversability.md "Headings").
  float step_m = 0;
  float roughness_m = 0;   ///< RMS deviation from the plane fitted over the footprint (best heading)
  float contact = 1;       ///< supported fraction of the footprint, worst heading, [0, 1]
  float contact_best = 1;  ///< ... best heading
  /// Free height above the face along "up" against measured faces; +inf if none above within
  /// the search height; NaN if the first face above is a Steiner (closing) face: unknown.
  float clearance_m = std::numeric_limits<float>::infinity();
  /// Geodesic distance over the surface to the nearest lethal face; +inf if none within the
  /// inflation radius.
  float lethal_distance_m = std::numeric_limits<float>::infinity();
  std::uint32_t rays = 0;  ///< observation count (see mesher::SurfaceFace::rays)
  bool steiner = false;    ///< touches a Steiner vertex
  Evidence evidence = Evidence::kInterpolated;
  /// Bound on how far the true surface may lie from the face, along up (metres): the points'
  /// noise plus the relief an unobserved span can hide (docs/traversability.md "Evidence");
  /// +inf for closing geometry.
  float height_uncertainty_m = std::numeric_limits<float>::infinity();
  FaceClass face_class = FaceClass::kUnknown;
  /// Combined cost in [0, 1] for free faces; 1 for lethal; the profile's uncertain cost for
  /// uncertain faces; NaN for unknown.
  float cost = std::numeric_limits<float>::quiet_NaN();
  /// Why the face is not free: the bits of `reason::` in traversability/layer_registry.h of its
  /// class's rules that hold (0 for a free face).
  std::uint16_t reasons = 0;
  /// The headings of travel at which the footprint fits in the worst case, as a free face needs:
  /// bit k for heading k x 180 / contact_headings degrees about up from the first axis of the
  /// map's plan frame (geometry::planFrame(up_W), default rule); a disc has bit 0 only. 0 where no
  /// judged heading fits (a driven face may still be free: it fits along its drive). Planners
  /// keep a rectangle's heading of travel to these (docs/planning.md, "Headings").
  std::uint32_t heading_fits = 0;
};

/// A snapshot of a traversability map: the mesh (map units) with every layer per face. What the
/// exporters and the planner consume.
struct LayeredMesh {
  mesher::TriangleMesh mesh;
  /// One per face of `mesh`.
  std::vector<FaceLayers> layers;
  /// Stable keys of the faces (empty when the mesh came from a file without vertex keys).
  std::vector<mesher::FaceKey> face_keys;
  /// Unit vector pointing up (against gravity), in the map frame.
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  /// Metres per map unit.
  double metres_per_unit = 1.0;

  /// Which end of a per-face quantity is worse for the robot; for a set of bits, every bit any
  /// face has (FaceLayers::reasons) or only the bits every face has (FaceLayers::heading_fits).
  enum class Worst : std::uint8_t { kHighest, kLowest, kBitwiseOr, kBitwiseAnd };
  /// The per-vertex rule of every export: a vertex takes the worst value of its faces (`worst`
  /// says which end is worse); NaN face values are no data and skipped; NaN where no face of the
  /// vertex has a value (or the vertex has no face). O(faces).
  /// @param value the quantity of one face
  std::vector<float> vertexWorst(const std::function<float(const FaceLayers&)>& value,
                                 Worst worst = Worst::kHighest) const;
  /// Per-vertex cost: the max over the vertex's known faces (NaN if all are unknown; 1 if any is
  /// lethal). vertexWorst of the face cost, unknown faces skipped.
  std::vector<float> vertexCost() const;
  /// Per-vertex class: lethal if any face is lethal, else uncertain if any face is uncertain, else
  /// free if any face is free, else unknown.
  std::vector<FaceClass> vertexClass() const;
};

}  // namespace terramesh::traversability
