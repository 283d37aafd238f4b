#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <vector>

#include "evaluation/ground_truth_traversability.h"
#include "evaluation/traversability_score.h"
#include "traversability/layer_registry.h"
#include "traversability/layered_mesh.h"

namespace terramesh::evaluation {

/// Where the road under a driven camera path is looked for (real data with no labelled truth:
/// the road the camera's car drove on must be traversable).
struct RoadUnderPathConfig {
  /// Map surface within this horizontal distance of the camera path counts, in metres (strictly
  /// within: what stands on the strip's very edge covers none of its ground).
  double lateral_m = 1.5;
  /// The road lies this far below the camera (KITTI: 1.65 m).
  double camera_height_m = 1.65;
  /// ... give or take this much, in metres.
  double height_tolerance_m = 0.5;
  /// Map faces are split until no edge is longer than this (metres), each piece judged at its
  /// centroid; 0: whole faces.
  double sample_edge_m = 0.25;
  /// Spacing (metres) of the ground-plane grid of columns that judge the strip by what is
  /// underfoot (RoadUnderPath::underfoot).
  double column_spacing_m = 0.1;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// The map's classes on the road under the camera path.
struct RoadUnderPath {
  /// Area (m^2) of the map pieces under the path, per predicted class. Pieces facing down (a
  /// ceiling, a parking deck's underside: normal within 60 degrees of down) are not the road.
  ClassAreas areas;
  /// Area (m^2) of the pieces facing down in the band, left out of `areas`.
  double facing_down_m2 = 0;
  /// Each class's share of areas.total() (NaN if nothing lies under the path).
  double free_fraction = 0;
  double lethal_fraction = 0;
  double unknown_fraction = 0;
  double uncertain_fraction = 0;
  /// Per bit of traversability::reason (FaceLayers::reasons): the share of areas.total() whose
  /// face has it (why the road under the path is not free; NaN if nothing lies under the path).
  std::array<double, traversability::reason::kCount> reason_fraction{};
  /// With a truth surface: the distance (metres) from the free pieces under the path to it,
  /// median and 90th percentile, area-weighted; NaN without a truth or with no free piece.
  double free_truth_distance_median_m = std::numeric_limits<double>::quiet_NaN();
  double free_truth_distance_p90_m = std::numeric_limits<double>::quiet_NaN();
  /// With a labelled truth: the pieces the truth does not rule out for the robot, per predicted
  /// class, their share of areas.total(), and the free share of them (NaN without a truth or with
  /// nothing there). A piece is ruled out when its nearest truth face is ground that the truth
  /// calls not traversable for the robot (a step, a curb or a wall within the footprint, too steep,
  /// too low): a footprint centred off the path reaches beyond where the body swept. A piece
  /// nearest a non-ground truth face stays in: the robot drove there, so the map drew a wall or a
  /// ceiling where the road is.
  ClassAreas where_truth_fits;
  double truth_fits_fraction = std::numeric_limits<double>::quiet_NaN();
  double free_where_truth_fits_fraction = std::numeric_limits<double>::quiet_NaN();
  /// The strip as ground, by columns: a grid of `column_spacing_m` over the plane perpendicular to
  /// up, every node within lateral_m of the path; each column takes the highest map face within
  /// the height band that does not face down (what the robot's wheels meet) and weighs the node's
  /// ground-plane area (m^2). A steep face weighs what it covers of the ground, not its own area,
  /// and a face hidden under another within the band does not count. `underfoot_none_m2`: columns
  /// with no map surface in the band.
  ClassAreas underfoot;
  double underfoot_none_m2 = 0;
  /// Each class's share of the columns' area, holes included (NaN if no column).
  double underfoot_free_fraction = std::numeric_limits<double>::quiet_NaN();
  double underfoot_lethal_fraction = std::numeric_limits<double>::quiet_NaN();
  double underfoot_unknown_fraction = std::numeric_limits<double>::quiet_NaN();
  double underfoot_uncertain_fraction = std::numeric_limits<double>::quiet_NaN();
  double underfoot_none_fraction = std::numeric_limits<double>::quiet_NaN();
  /// With a labelled truth: the free share of the columns the truth does not rule out (a column's
  /// face judged as a piece is, at the truth face nearest its hit; a hole stays in).
  double underfoot_free_where_truth_fits_fraction = std::numeric_limits<double>::quiet_NaN();
  /// Length of the path, in metres.
  double path_length_m = 0;
};

/// The map against measured ground under the path (real data with a LiDAR): the ground points
/// within the path's band (RoadUnderPathConfig's lateral_m and camera_height_m +- tolerance), each
/// with the map surface straight above or below it (the nearer, within height_tolerance_m).
struct GroundUnderPath {
  /// Ground points in the band, and how many have a map face of each class over them; `missing`:
  /// no map surface within the tolerance.
  std::size_t points = 0;
  std::size_t free = 0, lethal = 0, unknown = 0, uncertain = 0, missing = 0;
  /// Shares of `points` (NaN without points).
  double free_fraction = std::numeric_limits<double>::quiet_NaN();
  double lethal_fraction = std::numeric_limits<double>::quiet_NaN();
  double unknown_fraction = std::numeric_limits<double>::quiet_NaN();
  double uncertain_fraction = std::numeric_limits<double>::quiet_NaN();
  double missing_fraction = std::numeric_limits<double>::quiet_NaN();
  /// Per bit of traversability::reason: the share of `points` under a face that has it.
  std::array<double, traversability::reason::kCount> reason_fraction{};
  /// Vertical distance (metres) from the ground points to the map surface over them: at the free
  /// ones (median, 90th percentile) and at all with a surface (median); NaN if none.
  double free_height_median_m = std::numeric_limits<double>::quiet_NaN();
  double free_height_p90_m = std::numeric_limits<double>::quiet_NaN();
  double height_median_m = std::numeric_limits<double>::quiet_NaN();
  /// Length (metres) of the path within lateral_m of some ground point of the band: the part the
  /// measurement covers.
  double covered_path_m = 0;
};

/// Checks the map under the polyline `path_W` against `ground_W`, measured points (e.g. LiDAR
/// returns; the band's height window keeps those on the road), both in the map's units and frame.
/// Metres via map.metres_per_unit; "up" is `up_W`. O(G P + G log F) for G ground points, P path
/// points and F faces.
/// @throw std::invalid_argument as roadUnderPath, or for a non-finite ground point.
GroundUnderPath groundUnderPath(const traversability::LayeredMesh& map, const std::vector<Eigen::Vector3d>& path_W,
                                const Eigen::Vector3d& up_W, const RoadUnderPathConfig& config,
                                const std::vector<Eigen::Vector3d>& ground_W);

/// "Up" from camera orientations (OpenCV/KITTI cameras: y points down in the image): the
/// normalised mean of the cameras' -y axes in the world frame.
/// @throw std::invalid_argument if there are no rotations or they cancel out.
Eigen::Vector3d upFromCameraRotations(const std::vector<Eigen::Quaterniond>& rotations_W_C);

/// Classes of the map surface under the polyline `path_W` (camera centres in driving order, in
/// the map's units and frame): pieces whose centroid is within lateral_m horizontally of the
/// polyline (strictly, by more than rounding: surface on the strip's very edge covers none of it)
/// and between camera_height_m -/+ height_tolerance_m below the nearest path point.
/// Distances are converted to metres with map.metres_per_unit; "up" is `up_W`. With `truth` (the
/// truth judged for the map's robot, in metres, in the map's frame), how far the free pieces lie
/// from its surface, and each piece judged by the truth at its nearest truth face.
/// @throw std::invalid_argument if the config does not validate, the path has fewer than 2
///        points, `up_W` is zero, or the map has not one layer per face.
RoadUnderPath roadUnderPath(const traversability::LayeredMesh& map, const std::vector<Eigen::Vector3d>& path_W,
                            const Eigen::Vector3d& up_W, const RoadUnderPathConfig& config,
                            const GroundTruthTraversability* truth = nullptr);

}  // namespace terramesh::evaluation
