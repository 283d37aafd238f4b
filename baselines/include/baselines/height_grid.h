#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace terramesh::baselines {

/// What a robot can drive on, for the 2.5D grid (same meaning as traversability::RobotProfile).
struct GridRobotConfig {
  double max_step_m = 0.2;
  double max_slope_deg = 20.0;
  double min_clearance_m = 1.0;
  /// Disc footprint: a pose is valid if its cell is traversable and no known non-traversable
  /// cell lies within this radius (unknown cells inside the footprint are tolerated).
  double footprint_radius_m = 0.3;
  /// Per-metre cost multiplier 1 + w * cost, as WalkabilityConfig::cost_weight.
  double cost_weight = 4.0;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// A 2.5D traversability grid in a gravity-aligned frame G (z up): per column the ground height,
/// the step to the neighbours, the slope, the clearance and whether a robot may stand there.
/// See docs/planning.md for the definitions. Cell (i, j) covers
/// [origin_x + i r, origin_x + (i + 1) r) x [origin_y + j r, ...).
struct HeightGrid {
  double resolution_m = 0.2;
  double origin_x_m = 0, origin_y_m = 0;
  int width = 0, height = 0;
  /// Rotation from the map frame W into G (G's z is up) and metres per map unit of W.
  Eigen::Matrix3d R_G_W = Eigen::Matrix3d::Identity();
  double metres_per_unit = 1.0;
  std::vector<float> ground_z_m;   ///< NaN: unknown (no observed ground in the column)
  std::vector<float> clearance_m;  ///< +inf when nothing occupied was seen above the ground
  std::vector<float> step_m;       ///< largest height difference to a known 8-neighbour
  std::vector<float> slope_deg;    ///< from central differences over known neighbours (0 if none)
  std::vector<float> cost;         ///< in [0, 1] for traversable cells, NaN otherwise
  std::vector<std::uint8_t> traversable;
  /// Valid robot centre: traversable and no known non-traversable cell within the footprint.
  std::vector<std::uint8_t> valid_pose;

  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * static_cast<std::size_t>(width) + static_cast<std::size_t>(i); }
  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < width && j < height; }
  /// Cell of a point of G (metres); may be outside.
  Eigen::Vector2i cellOf(double x_m, double y_m) const;
  /// Fills step, slope, cost, traversable and valid_pose from ground and clearance.
  void classify(const GridRobotConfig& robot);
  std::size_t knownCells() const;
  std::size_t traversableCells() const;
  std::size_t memoryBytes() const;
};

}  // namespace terramesh::baselines
