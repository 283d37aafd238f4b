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
using synthetic::Rng;

constexpr double kTileM = 0.25;
constexpr double kDegToRad = M_PI / 180.0;
/// The serpentine lane's three legs run along x at these y; hazards stand in the two bands
/// between them, within a few metres of a leg on either side.
constexpr double kLaneY[] = {4.0, 18.0, 32.0};
constexpr double kLaneEndXM[] = {4.0, 68.0};
/// The ramp's footprint along x is fixed (a whole number of tiles); its slope sets the plateau's
/// height.
constexpr double kRampLengthM = 3.0;
constexpr double kRampWidthM = 2.5;
/// Start points stand this far from a slab's, pit's or ramp's edge (beyond a robot's footprint).
constexpr double kApproachM = 2.0;
/// ... and this far to each side of a wall or rock.
constexpr double kSideStepM = 1.5;

/// A multiple of the tile size near `value`, so that footprints cut whole tiles out of the ground.
double onTiles(double value) { return kTileM * std::round(value / kTileM); }

/// Axis-aligned footprint [x0, x1] x [y0, y1] at ground level.
struct Footprint {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool contains(const Eigen::Vector2d& p) const { return p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1; }
};

Footprint footprintOf(const SceneHazard& hazard) {
  const Eigen::Vector2d half = hazard.size_m / 2;
  return {hazard.centre_W.x() - half.x(), hazard.centre_W.x() + half.x(), hazard.centre_W.y() - half.y(),
          hazard.centre_W.y() + half.y()};
}

/// The plateau's ramp footprint: kRampLengthM before its -x edge, centred on it along y.
Footprint rampOf(const SceneHazard& plateau) {
  const Footprint top = footprintOf(plateau);
  return {top.x0 - plateau.ramp_length_m, top.x0, plateau.centre_W.y() - plateau.ramp_width_m / 2,
          plateau.centre_W.y() + plateau.ramp_width_m / 2};
}

/// A slab, plateau or pit: centre and size jittered on whole tiles, height drawn in [lo, hi).
SceneHazard boxHazard(const std::string& name, HazardKind kind, Eigen::Vector2d centre, Eigen::Vector2d size,
                      double lo, double hi, Rng& rng) {
  SceneHazard hazard;
  hazard.name = name;
  hazard.kind = kind;
  centre += Eigen::Vector2d(rng.uniform(-0.75, 0.75), rng.uniform(-0.5, 0.5));
  size += Eigen::Vector2d(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
  // Size in whole tiles of two, so that the centre +- half the size stays on the tiles.
  hazard.size_m = {2 * onTiles(size.x() / 2), 2 * onTiles(size.y() / 2)};
  hazard.centre_W = {onTiles(centre.x()), onTiles(centre.y()), 0.0};
  hazard.height_m = rng.uniform(lo, hi);
  const Footprint box = footprintOf(hazard);
  hazard.start_W = {box.x0 - kApproachM, hazard.centre_W.y(), 0.0};
  hazard.goal_W = hazard.centre_W + hazard.height_m * Eigen::Vector3d::UnitZ();
  return hazard;
}

/// Every hazard of the scene, placed and sized from the seed.
std::vector<SceneHazard> layoutHazards(const HazardsSceneConfig& config) {
  Rng rng(config.seed, 1);
  std::vector<SceneHazard> hazards;
  hazards.push_back(boxHazard("slab_1", HazardKind::kSlab, {10, 11}, {4, 3}, 0.30, 0.40, rng));
  hazards.push_back(boxHazard("slab_2", HazardKind::kSlab, {12, 25}, {3, 3}, 0.40, 0.50, rng));
  SceneHazard plateau = boxHazard("plateau", HazardKind::kPlateau, {28, 11}, {6, 5}, 0.0, 0.0, rng);
  plateau.ramp_slope_deg = rng.uniform(15.0, 18.0);
  plateau.ramp_length_m = kRampLengthM;
  plateau.ramp_width_m = kRampWidthM;
  plateau.height_m = kRampLengthM * std::tan(plateau.ramp_slope_deg * kDegToRad);
  plateau.start_W = {rampOf(plateau).x0 - kApproachM, plateau.centre_W.y(), 0.0};
  plateau.goal_W = plateau.centre_W + plateau.height_m * Eigen::Vector3d::UnitZ();
  hazards.push_back(plateau);
  hazards.push_back(boxHazard("pit", HazardKind::kPit, {44, 11}, {4, 3}, -0.60, -0.30, rng));

  // Walls: one across band A (along y), one along band B (along x); a path goes round an end.
  const struct { const char* name; Eigen::Vector2d centre; bool along_x; } walls[] = {
      {"wall_1", {30, 25}, true}, {"wall_2", {58, 11}, false}};
  for (const auto& spec : walls) {
    SceneHazard wall;
    wall.name = spec.name;
    wall.kind = HazardKind::kThinWall;
    const Eigen::Vector2d centre = spec.centre + Eigen::Vector2d(rng.uniform(-1, 1), rng.uniform(-0.5, 0.5));
    wall.centre_W = {centre.x(), centre.y(), 0.0};
    const double length = rng.uniform(3.5, 4.5), thickness = rng.uniform(0.1, 0.2);
    wall.size_m = spec.along_x ? Eigen::Vector2d(length, thickness) : Eigen::Vector2d(thickness, length);
    wall.height_m = rng.uniform(1.0, 2.0);
    const Eigen::Vector3d across = spec.along_x ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
    wall.start_W = wall.centre_W - kSideStepM * across;
    wall.goal_W = wall.centre_W + kSideStepM * across;
    hazards.push_back(wall);
  }

  const Eigen::Vector2d rock_sites[] = {{40, 23}, {46, 27}, {52, 24}, {58, 26}, {52, 8}, {64, 13}};
  const auto rocks = static_cast<int>(std::lround(config.object_density * kHazardsRockCount));
  for (int r = 0; r < rocks; ++r) {
    SceneHazard rock;
    rock.name = "rock_" + std::to_string(r + 1);
    rock.kind = HazardKind::kRock;
    // Beyond kHazardsRockCount, a second round 2.5 m west of the first (still clear of the rest).
    const double west = r < kHazardsRockCount ? 0.0 : 2.5;
    const Eigen::Vector2d site = rock_sites[r % kHazardsRockCount] - Eigen::Vector2d(west, 0);
    const Eigen::Vector2d centre = site + Eigen::Vector2d(rng.uniform(-1, 1), rng.uniform(-0.5, 0.5));
    rock.centre_W = {centre.x(), centre.y(), 0.0};
    // addBlob's radius; the ball is sunk so that 80 % of its diameter stands above the ground.
    const double radius = rng.uniform(0.18, 0.45);
    rock.size_m = Eigen::Vector2d::Constant(2 * radius);
    rock.height_m = 1.6 * radius;
    rock.start_W = rock.centre_W - kSideStepM * Eigen::Vector3d::UnitX();
    rock.goal_W = rock.centre_W + kSideStepM * Eigen::Vector3d::UnitX();
    hazards.push_back(rock);
  }
  return hazards;
}

/// The flat ground in tiles, without the tiles under slabs, the plateau, its ramp and the pit.
void addGround(LabeledMeshBuilder& builder, const std::vector<Footprint>& holes) {
  const auto nx = static_cast<std::size_t>(std::lround(kHazardsLengthM / kTileM));
  const auto ny = static_cast<std::size_t>(std::lround(kHazardsWidthM / kTileM));
  std::vector<Eigen::Vector3d> points;
  points.reserve((nx + 1) * (ny + 1));
  // Rows along x, columns along y: cells face up.
  for (std::size_t i = 0; i <= nx; ++i) {
    for (std::size_t j = 0; j <= ny; ++j) points.emplace_back(kTileM * i, kTileM * j, 0.0);
  }
  builder.sheet(points, nx + 1, ny + 1, [&](std::size_t i, std::size_t j) -> std::optional<SurfaceLabel> {
    const Eigen::Vector2d centre(kTileM * (i + 0.5), kTileM * (j + 0.5));
    for (const Footprint& hole : holes) {
      if (hole.contains(centre)) return std::nullopt;
    }
    return SurfaceLabel::kRoad;
  });
}

/// The plateau's walls (the -x one beside the ramp only), its top, the ramp and the ramp's sides.
void addPlateau(LabeledMeshBuilder& builder, const SceneHazard& plateau) {
  const Footprint top = footprintOf(plateau), ramp = rampOf(plateau);
  const double h = plateau.height_m;
  const Eigen::Vector3d half_v(0, 0, h / 2);
  const double cx = plateau.centre_W.x(), cy = plateau.centre_W.y();
  const double half_x = (top.x1 - top.x0) / 2, half_y = (top.y1 - top.y0) / 2;
  synthetic::addRectangle(builder, {cx, top.y1, h / 2}, {-half_x, 0, 0}, half_v, SurfaceLabel::kWall);  // +y
  synthetic::addRectangle(builder, {cx, top.y0, h / 2}, {half_x, 0, 0}, half_v, SurfaceLabel::kWall);   // -y
  synthetic::addRectangle(builder, {top.x1, cy, h / 2}, {0, half_y, 0}, half_v, SurfaceLabel::kWall);   // +x
  for (const auto& [y0, y1] : {std::make_pair(top.y0, ramp.y0), std::make_pair(ramp.y1, top.y1)}) {
    synthetic::addRectangle(builder, {top.x0, (y0 + y1) / 2, h / 2}, {0, -(y1 - y0) / 2, 0}, half_v,
                            SurfaceLabel::kWall);  // -x, beside the ramp
  }
  builder.quad({top.x0, top.y0, h}, {top.x1, top.y0, h}, {top.x1, top.y1, h}, {top.x0, top.y1, h},
               SurfaceLabel::kRoad);
  builder.quad({ramp.x0, ramp.y0, 0}, {ramp.x1, ramp.y0, h}, {ramp.x1, ramp.y1, h}, {ramp.x0, ramp.y1, 0},
               SurfaceLabel::kRamp);
  builder.triangle(builder.vertex({ramp.x0, ramp.y0, 0}), builder.vertex({ramp.x1, ramp.y0, 0}),
                   builder.vertex({ramp.x1, ramp.y0, h}), SurfaceLabel::kWall);
  builder.triangle(builder.vertex({ramp.x0, ramp.y1, 0}), builder.vertex({ramp.x1, ramp.y1, h}),
                   builder.vertex({ramp.x1, ramp.y1, 0}), SurfaceLabel::kWall);
}

/// The pit's floor and its four walls, facing into it.
void addPit(LabeledMeshBuilder& builder, const SceneHazard& pit) {
  const Footprint box = footprintOf(pit);
  const double d = -pit.height_m;
  const Eigen::Vector3d half_v(0, 0, d / 2);
  const double cx = pit.centre_W.x(), cy = pit.centre_W.y();
  const double half_x = (box.x1 - box.x0) / 2, half_y = (box.y1 - box.y0) / 2;
  builder.quad({box.x0, box.y0, -d}, {box.x1, box.y0, -d}, {box.x1, box.y1, -d}, {box.x0, box.y1, -d},
               SurfaceLabel::kRoad);
  synthetic::addRectangle(builder, {box.x0, cy, -d / 2}, {0, half_y, 0}, half_v, SurfaceLabel::kWall);   // +x
  synthetic::addRectangle(builder, {box.x1, cy, -d / 2}, {0, -half_y, 0}, half_v, SurfaceLabel::kWall);  // -x
  synthetic::addRectangle(builder, {cx, box.y0, -d / 2}, {-half_x, 0, 0}, half_v, SurfaceLabel::kWall);  // +y
  synthetic::addRectangle(builder, {cx, box.y1, -d / 2}, {half_x, 0, 0}, half_v, SurfaceLabel::kWall);   // -y
}

void addHazard(LabeledMeshBuilder& builder, const SceneHazard& hazard, Rng& rock_rng) {
  Eigen::Isometry3d on_ground = Eigen::Isometry3d::Identity();
  on_ground.translation() = hazard.centre_W;
  switch (hazard.kind) {
    case HazardKind::kSlab:
      synthetic::addBox(builder, on_ground, {hazard.size_m.x(), hazard.size_m.y(), hazard.height_m},
                        SurfaceLabel::kWall, SurfaceLabel::kRoad);
      break;
    case HazardKind::kPlateau: addPlateau(builder, hazard); break;
    case HazardKind::kPit: addPit(builder, hazard); break;
    case HazardKind::kThinWall:
      synthetic::addBox(builder, on_ground, {hazard.size_m.x(), hazard.size_m.y(), hazard.height_m},
                        SurfaceLabel::kWall, SurfaceLabel::kWall);
      break;
    case HazardKind::kRock: {
      const double radius = hazard.size_m.x() / 2;
      synthetic::addBlob(builder, hazard.centre_W + 0.6 * radius * Eigen::Vector3d::UnitZ(), radius, 0.15, rock_rng,
                         SurfaceLabel::kObstacle);
      break;
    }
  }
}

}  // namespace

std::string_view toString(HazardKind kind) {
  switch (kind) {
    case HazardKind::kSlab: return "slab";
    case HazardKind::kPlateau: return "plateau";
    case HazardKind::kPit: return "pit";
    case HazardKind::kThinWall: return "thin_wall";
    case HazardKind::kRock: return "rock";
  }
  return "?";
}

void HazardsSceneConfig::validate() const {
  synthetic::ProblemList problems("HazardsSceneConfig");
  problems.require(object_density >= 0 && object_density <= 2, "object_density must be in [0, 2]");
  problems.require(camera_height_m >= 0.3 && camera_height_m <= 3, "camera_height_m must be in [0.3, 3]");
  problems.require(speed_m_per_s > 0 && speed_m_per_s <= 10, "speed_m_per_s must be in (0, 10]");
  problems.throwIfAny();
}

SyntheticScene buildHazardsScene(const HazardsSceneConfig& config) {
  config.validate();
  SyntheticScene scene;
  scene.name = "hazards";
  scene.up_W = Eigen::Vector3d::UnitZ();
  scene.frame_description =
      "hazards scene, z-up world frame, metres, ground plane z = 0, origin at a ground corner, lane legs along x";
  scene.hazards = layoutHazards(config);
  std::vector<Footprint> holes;
  for (const SceneHazard& hazard : scene.hazards) {
    if (hazard.kind == HazardKind::kSlab || hazard.kind == HazardKind::kPit) holes.push_back(footprintOf(hazard));
    if (hazard.kind == HazardKind::kPlateau) {
      holes.push_back(footprintOf(hazard));
      holes.push_back(rampOf(hazard));
    }
  }
  LabeledMeshBuilder builder(scene.up_W);
  addGround(builder, holes);
  Rng rock_rng(config.seed, 2);
  for (const SceneHazard& hazard : scene.hazards) addHazard(builder, hazard, rock_rng);
  scene.ground_truth = builder.finish();

  // A serpentine lane: east along the first leg, west along the second, east along the third.
  const double x0 = kLaneEndXM[0], x1 = kLaneEndXM[1];
  const std::vector<Eigen::Vector3d> waypoints = {{x0, kLaneY[0], 0}, {x1, kLaneY[0], 0}, {x1, kLaneY[1], 0},
                                                  {x0, kLaneY[1], 0}, {x0, kLaneY[2], 0}, {x1, kLaneY[2], 0}};
  const synthetic::CentreLine line(waypoints, scene.up_W, kTileM, 3.0);
  scene.frames_T_W_C = synthetic::camerasAlong(line, config.speed_m_per_s / kSyntheticFrameRateHz, [&](double s) {
    return Eigen::Vector3d(line.at(s).centre_W + config.camera_height_m * scene.up_W);
  });
  return scene;
}

}  // namespace terramesh::datasets
