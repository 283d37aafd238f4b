#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::traversability {
struct RobotProfile;
}

namespace terramesh::evaluation {

/// The robot and the tolerances a path is judged with. Lengths in metres, angles in degrees.
struct TruthCheckConfig {
  /// The body's footprint: a disc of `footprint_radius_m`, or, when `footprint_length_m` and
  /// `footprint_width_m` are both > 0, that rectangle (length along the heading), turned to the
  /// heading of travel (TruthChecker::check). A rectangle's `footprint_radius_m` is its
  /// circumscribed radius, the disc a path without any heading (all on one vertical) is tested as.
  double footprint_radius_m = 0.3;
  double footprint_length_m = 0.0;
  double footprint_width_m = 0.0;
  /// Anything lower than this above the local true ground is a step the robot crosses.
  double max_step_m = 0.2;
  /// Robot height: the body spans max_step_m to min_clearance_m above the local true ground.
  double min_clearance_m = 1.0;
  /// Steepest true slope under the path.
  double max_slope_deg = 20.0;
  /// Largest vertical distance, above or below, between a path sample and the true ground under
  /// it. The path lies on our reconstructed surface, so this also bounds the reconstruction error.
  double vertical_tolerance_m = 0.3;
  /// Distance between samples along the path.
  double spacing_m = 0.1;
  /// Height above the path of the segments that must not cross the true surface.
  double crossing_lift_m = 0.3;
  /// Vertical spacing of the horizontal slices the body is tested in.
  double body_slice_m = 0.05;
  /// How far up and down to look for the true surface when a sample is out of tolerance (only
  /// for the failure reason).
  double ground_search_m = 5.0;
  /// A rectangle that keeps its own heading (traversability::MotionModel::kOmni): its paths are
  /// checked at the body's heading the planner gave each point (the yaw), which the callers pass
  /// to TruthChecker::check, instead of the heading of travel.
  bool own_heading = false;

  /// @throw std::invalid_argument listing every problem, each as "field: value (expected ...)".
  void validate() const;
  /// Whether the footprint is a rectangle.
  bool rectangle() const { return footprint_length_m > 0.0 && footprint_width_m > 0.0; }
};

/// The check of a robot profile's robot: its footprint (disc, or rectangle with its circumscribed
/// radius), step, height and slope; the tolerances at their defaults.
TruthCheckConfig truthCheckConfigFrom(const traversability::RobotProfile& profile);

/// Whether a path is drivable on the true scene.
struct TruthCheck {
  bool valid = true;
  /// First problem found, naming what failed, where and by how much, e.g. "the path is 0.52 m
  /// above the true ground at (x, y, z) (tolerance 0.3 m) ...", "true wall face 0.20 m from the
  /// path at (x, y, z), inside the 0.34 m footprint by 0.14 m, 0.40 m above the true ground".
  std::string reason;
  std::size_t samples = 0;
  /// Largest vertical distance (metres) between a checked sample and the true ground under it.
  double max_ground_offset_m = 0.0;
};

/// Checks paths against one truth. Holds a tree over the truth's non-drivable faces, built once
/// (O(F log F)), so checking many paths costs only the queries. Keeps references to `truth` and
/// `bvh`: both must outlive the checker.
class TruthChecker {
 public:
  /// `bvh` is built over `truth.mesh`.
  /// @throw std::invalid_argument if the truth has no label per face.
  TruthChecker(const datasets::LabeledMesh& truth, const datasets::TriangleBvh& bvh);

  /// Samples the polyline every `config.spacing_m` and checks, at each sample p, in this order:
  /// 1. ground: the true surface nearest to p along the vertical (rays up and down from p) lies
  ///    within `vertical_tolerance_m` of p;
  /// 2. label: that face is drivable (road, sidewalk, curb, vegetation or ramp; not wall, obstacle
  ///    or ceiling);
  /// 3. slope: its true slope is <= `max_slope_deg`;
  /// 4. body: no non-drivable true face (wall, obstacle, ceiling) enters the robot's body between
  ///    `max_step_m` and `min_clearance_m` above that true ground point g.
  ///    A rectangle's body is the upright box over the footprint centred on g, turned to the
  ///    heading of travel at p: the horizontal direction of the chord between the path points half
  ///    the footprint's length behind and ahead of p along the path (clamped to its ends), the
  ///    heading of a body whose two ends follow the path; or, given `body_headings_W` (one per
  ///    path point: a body that keeps its own heading, traversability::MotionModel::kOmni), the
  ///    heading of the path point before p turned towards the next one's in proportion to the
  ///    distance along the segment. Where that heading turns between
  ///    samples, the body is also tested at p at intermediate headings, close enough that its
  ///    corners move at most `spacing_m` from one to the next. Each face within the box's
  ///    circumscribed ball (TriangleBvh::facesWithin) is clipped to the box, exactly; a face that
  ///    only touches the box's boundary does not enter it.
  ///    A disc's body is the vertical cylinder of radius `footprint_radius_m` around p. Tested in
  ///    slices `body_slice_m` apart: for each slice centre c on the
  ///    axis, the non-drivable surface point q nearest to c (TriangleBvh::closestPoint on those
  ///    faces only) fails the path if it lies in the cylinder. Any non-drivable point in a slice
  ///    is within hypot(r, slice / 2) of c, so a face in the body is missed only when another
  ///    non-drivable point outside the body is nearer to every slice centre: in the rim between r
  ///    and hypot(r, slice / 2) (0.9 mm for r = 0.34 m), or below the step height / above the
  ///    clearance;
  /// 5. crossing: the segment from the previous sample to p, lifted by `crossing_lift_m`, does not
  ///    cross the true surface (driving through a wall, a car, a rock).
  /// Stops at the first failure. `path_W` and the truth share a frame and its units;
  /// `metres_per_unit` converts. An empty path is valid.
  /// @throw std::invalid_argument if `config` is invalid, `metres_per_unit` <= 0, `up_W` is zero,
  ///        or `body_headings_W` is neither empty nor one horizontal direction per path point.
  TruthCheck check(const std::vector<Eigen::Vector3d>& path_W, const Eigen::Vector3d& up_W, double metres_per_unit,
                   const TruthCheckConfig& config, const std::vector<Eigen::Vector3d>& body_headings_W = {}) const;

 private:
  /// The failure of rule 4 for a disc body on true ground `g` under sample `p`, or "".
  std::string discFailure(const Eigen::Vector3d& p, const Eigen::Vector3d& g, const Eigen::Vector3d& up,
                          double metres_per_unit, const TruthCheckConfig& config) const;
  /// The failure of rule 4 for a rectangle's body turning from heading `from` to `to` at `p`, or "";
  /// `own_heading`: the headings are the body's own, not those of travel (for the message).
  std::string boxFailure(const Eigen::Vector3d& p, const Eigen::Vector3d& g, const Eigen::Vector3d& up,
                         const Eigen::Vector3d& from, const Eigen::Vector3d& to, double metres_per_unit,
                         const TruthCheckConfig& config, bool own_heading) const;

  const datasets::LabeledMesh& truth_;
  const datasets::TriangleBvh& bvh_;
  /// Index in the truth of each face of `obstacle_bvh_`.
  std::vector<std::uint32_t> obstacle_truth_face_;
  datasets::TriangleBvh obstacle_bvh_;
};

/// One path against the truth: TruthChecker(truth, bvh).check(...), which builds the tree over
/// the non-drivable faces again on each call; use a TruthChecker for many paths.
/// @throw std::invalid_argument as TruthChecker's constructor and check().
TruthCheck checkAgainstTruth(const datasets::LabeledMesh& truth, const datasets::TriangleBvh& bvh,
                             const std::vector<Eigen::Vector3d>& path_W, const Eigen::Vector3d& up_W,
                             double metres_per_unit, const TruthCheckConfig& config);

}  // namespace terramesh::evaluation
