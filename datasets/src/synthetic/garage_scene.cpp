#include <cmath>
#include <optional>
#include <vector>

#include "centre_line.h"
#include "datasets/synthetic_scene.h"
#include "mesh_builder.h"
#include "primitives.h"
#include "problem_list.h"

namespace terramesh::datasets {
namespace {

using synthetic::LabeledMeshBuilder;

constexpr double kTileM = 0.5;
constexpr double kPillarSpacingM = 8.0;
constexpr double kRampStartXM = 12.0;
constexpr double kRampWidthM = 4.0;   // against the far wall, y in [W - 4, W]
constexpr double kLaneM = 4.0;        // driving lanes run this far from the walls
constexpr double kWallPanelM = 2.0;

/// The garage's fixed plan: pillar positions, the ramp and the opening above it.
class GaragePlan {
 public:
  explicit GaragePlan(const GarageSceneConfig& config) : config_(config) {
    for (double x = kPillarSpacingM; x <= config.length_m - 2 * kLaneM + 1e-9; x += kPillarSpacingM) {
      for (double y = kPillarSpacingM; y < kGarageWidthM - kRampWidthM - 1e-9; y += kPillarSpacingM) {
        pillars_.emplace_back(x, y);
      }
    }
  }

  double level(int index) const { return index * (config_.clear_height_m + config_.slab_thickness_m); }
  double rampEndX() const { return kRampStartXM + kGarageRampLengthM; }
  const std::vector<Eigen::Vector2d>& pillars() const { return pillars_; }

  bool inPillar(const Eigen::Vector2d& p) const {
    for (const Eigen::Vector2d& pillar : pillars_) {
      if ((p - pillar).cwiseAbs().maxCoeff() < config_.pillar_size_m / 2) return true;
    }
    return false;
  }
  bool inRampFootprint(const Eigen::Vector2d& p) const {
    return p.x() > kRampStartXM && p.x() < rampEndX() && p.y() > kGarageWidthM - kRampWidthM;
  }

 private:
  const GarageSceneConfig& config_;
  std::vector<Eigen::Vector2d> pillars_;
};

/// A tiled horizontal surface over the whole plan at height z, facing up or down, without the
/// tiles for which `hole(centre)` holds.
template <class Hole>
void addTiledLevel(LabeledMeshBuilder& builder, double length, double z, bool facing_up, SurfaceLabel label,
                   Hole&& hole) {
  const auto nx = static_cast<std::size_t>(std::lround(length / kTileM));
  const auto ny = static_cast<std::size_t>(std::lround(kGarageWidthM / kTileM));
  // Rows along x and columns along y face up (x cross y = +z); swapped, they face down.
  const std::size_t rows = facing_up ? nx + 1 : ny + 1;
  const std::size_t cols = facing_up ? ny + 1 : nx + 1;
  std::vector<Eigen::Vector3d> points;
  points.reserve(rows * cols);
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols; ++j) {
      const double x = kTileM * static_cast<double>(facing_up ? i : j);
      const double y = kTileM * static_cast<double>(facing_up ? j : i);
      points.emplace_back(x, y, z);
    }
  }
  builder.sheet(points, rows, cols, [&](std::size_t i, std::size_t j) -> std::optional<SurfaceLabel> {
    const Eigen::Vector2d centre = kTileM * Eigen::Vector2d(facing_up ? i + 0.5 : j + 0.5, facing_up ? j + 0.5 : i + 0.5);
    if (hole(centre)) return std::nullopt;
    return label;
  });
}

/// Inward-facing perimeter walls of one level, in panels.
void addPerimeter(LabeledMeshBuilder& builder, double length, double z0, double height) {
  const Eigen::Vector3d half_v(0, 0, height / 2);
  for (double x = 0; x < length - 1e-9; x += kWallPanelM) {
    const double w = std::min(kWallPanelM, length - x);
    const Eigen::Vector3d half_u(w / 2, 0, 0);
    synthetic::addRectangle(builder, {x + w / 2, 0, z0 + height / 2}, -half_u, half_v, SurfaceLabel::kWall);
    synthetic::addRectangle(builder, {x + w / 2, kGarageWidthM, z0 + height / 2}, half_u, half_v, SurfaceLabel::kWall);
  }
  for (double y = 0; y < kGarageWidthM - 1e-9; y += kWallPanelM) {
    const double w = std::min(kWallPanelM, kGarageWidthM - y);
    const Eigen::Vector3d half_u(0, w / 2, 0);
    synthetic::addRectangle(builder, {0, y + w / 2, z0 + height / 2}, half_u, half_v, SurfaceLabel::kWall);
    synthetic::addRectangle(builder, {length, y + w / 2, z0 + height / 2}, -half_u, half_v, SurfaceLabel::kWall);
  }
}

void addPillars(LabeledMeshBuilder& builder, const GaragePlan& plan, const GarageSceneConfig& config, double z0) {
  const double h = config.pillar_size_m / 2;
  const Eigen::Vector3d half_v(0, 0, config.clear_height_m / 2);
  for (const Eigen::Vector2d& p : plan.pillars()) {
    const Eigen::Vector3d centre(p.x(), p.y(), z0 + config.clear_height_m / 2);
    synthetic::addRectangle(builder, centre + Eigen::Vector3d(h, 0, 0), {0, h, 0}, half_v, SurfaceLabel::kWall);
    synthetic::addRectangle(builder, centre - Eigen::Vector3d(h, 0, 0), {0, -h, 0}, half_v, SurfaceLabel::kWall);
    synthetic::addRectangle(builder, centre + Eigen::Vector3d(0, h, 0), {-h, 0, 0}, half_v, SurfaceLabel::kWall);
    synthetic::addRectangle(builder, centre - Eigen::Vector3d(0, h, 0), {h, 0, 0}, half_v, SurfaceLabel::kWall);
  }
}

/// The ramp (a solid wedge against the far wall) and the rim of the opening above it.
void addRamp(LabeledMeshBuilder& builder, const GaragePlan& plan, const GarageSceneConfig& config) {
  const double y0 = kGarageWidthM - kRampWidthM, y1 = kGarageWidthM;
  const double x0 = kRampStartXM, x1 = plan.rampEndX();
  const double top = plan.level(1);
  builder.quad({x0, y0, 0}, {x1, y0, top}, {x1, y1, top}, {x0, y1, 0}, SurfaceLabel::kRamp);
  builder.triangle(builder.vertex({x0, y0, 0}), builder.vertex({x1, y0, 0}), builder.vertex({x1, y0, top}),
                   SurfaceLabel::kWall);
  const double c = config.clear_height_m;
  synthetic::addRectangle(builder, {x1, (y0 + y1) / 2, c / 2}, {0, kRampWidthM / 2, 0}, {0, 0, c / 2},
                          SurfaceLabel::kWall);
  const Eigen::Vector3d rim_half(0, 0, config.slab_thickness_m / 2);
  const double rim_z = c + config.slab_thickness_m / 2;
  synthetic::addRectangle(builder, {x0, (y0 + y1) / 2, rim_z}, {0, kRampWidthM / 2, 0}, rim_half, SurfaceLabel::kWall);
  synthetic::addRectangle(builder, {(x0 + x1) / 2, y0, rim_z}, {-(x1 - x0) / 2, 0, 0}, rim_half, SurfaceLabel::kWall);
}

void addParkedCars(LabeledMeshBuilder& builder, const GaragePlan& plan, const GarageSceneConfig& config) {
  synthetic::Rng rng(config.seed, 2);
  const double occupancy = std::min(1.0, 0.5 * config.object_density);
  for (int level = 0; level < 2; ++level) {
    for (double bay = kPillarSpacingM; bay + kPillarSpacingM <= config.length_m - 2 * kLaneM + 1e-9;
         bay += kPillarSpacingM) {
      for (const double x : {bay + 2.5, bay + 5.5}) {
        if (!rng.chance(occupancy)) continue;
        synthetic::addCar(builder, synthetic::uprightFrame({x, 1.5 * kPillarSpacingM, plan.level(level)},
                                                           Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()));
      }
    }
  }
}

}  // namespace

void GarageSceneConfig::validate() const {
  synthetic::ProblemList problems("GarageSceneConfig");
  problems.require(length_m >= 40 && length_m <= 400, "length_m must be in [40, 400]");
  problems.require(object_density >= 0 && object_density <= 10, "object_density must be in [0, 10]");
  problems.require(clear_height_m >= 2.2 && clear_height_m <= 6, "clear_height_m must be in [2.2, 6]");
  problems.require(slab_thickness_m >= 0.1 && slab_thickness_m <= 1, "slab_thickness_m must be in [0.1, 1]");
  problems.require(pillar_size_m >= 0.3 && pillar_size_m <= 2, "pillar_size_m must be in [0.3, 2]");
  problems.require(camera_height_m > 0.2 && camera_height_m < clear_height_m - 0.2,
                   "camera_height_m must be in (0.2, clear_height_m - 0.2)");
  problems.require(speed_m_per_s > 0 && speed_m_per_s <= 10, "speed_m_per_s must be in (0, 10]");
  problems.throwIfAny();
}

SyntheticScene buildGarageScene(const GarageSceneConfig& config) {
  config.validate();
  SyntheticScene scene;
  scene.name = "garage";
  scene.up_W = Eigen::Vector3d::UnitZ();
  scene.frame_description = "garage, z-up world frame, metres, origin at a ground-floor corner, ramp along +x";
  const GaragePlan plan(config);
  const double length = config.length_m;
  LabeledMeshBuilder builder(scene.up_W);
  for (int level = 0; level < 2; ++level) {
    const double floor = plan.level(level);
    const double ceiling = floor + config.clear_height_m;
    addTiledLevel(builder, length, floor, true, SurfaceLabel::kRoad, [&](const Eigen::Vector2d& p) {
      // Under the ramp on the ground floor, the opening above it upstairs.
      return plan.inPillar(p) || plan.inRampFootprint(p);
    });
    addTiledLevel(builder, length, ceiling, false, SurfaceLabel::kCeiling, [&](const Eigen::Vector2d& p) {
      return plan.inPillar(p) || (level == 0 && plan.inRampFootprint(p));
    });
    // Ground-floor walls reach through the slab: seen through the ramp opening, no gap shows.
    addPerimeter(builder, length, floor, config.clear_height_m + (level == 0 ? config.slab_thickness_m : 0.0));
    addPillars(builder, plan, config, floor);
  }
  addRamp(builder, plan, config);
  addParkedCars(builder, plan, config);
  scene.ground_truth = builder.finish();

  // Loops round the pillars of the ground floor, up the ramp, loops round those of the upper floor.
  const double z1 = plan.level(1);
  const double far_x = length - kLaneM, lane_y = kGarageWidthM - kRampWidthM / 2;
  const std::vector<Eigen::Vector3d> waypoints = {
      {kLaneM, kLaneM, 0},  {far_x, kLaneM, 0},  {far_x, 20, 0},           {kLaneM, 20, 0},
      {kLaneM, lane_y, 0},  {kRampStartXM, lane_y, 0}, {plan.rampEndX(), lane_y, z1}, {far_x, lane_y, z1},
      {far_x, kLaneM, z1},  {kLaneM, kLaneM, z1}, {kLaneM, 20, z1},        {28, 20, z1}};
  const synthetic::CentreLine line(waypoints, scene.up_W, 0.25, 3.0);
  scene.frames_T_W_C = synthetic::camerasAlong(line, config.speed_m_per_s / kSyntheticFrameRateHz, [&](double s) {
    return Eigen::Vector3d(line.at(s).centre_W + config.camera_height_m * scene.up_W);
  });
  return scene;
}

}  // namespace terramesh::datasets
