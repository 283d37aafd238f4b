#include <array>
#include <cmath>

#include "centre_line.h"
#include "datasets/synthetic_scene.h"
#include "mesh_builder.h"
#include "primitives.h"
#include "problem_list.h"

namespace terramesh::datasets {
namespace {

using synthetic::CentreLine;
using synthetic::Rng;

constexpr double kGridStepM = 0.5;
constexpr double kBankOffsetM = 12.0;   // left of the track
constexpr double kDitchOffsetM = -7.0;  // right of the track
constexpr double kDegToRad = M_PI / 180.0;

/// Terrain height above the centre line's plane as a function of world position and of the
/// lateral offset from the track: rolling hills + a bank (logistic step) + a ditch (Gaussian).
class Terrain {
 public:
  Terrain(const OffroadSceneConfig& config, Rng& rng) : config_(config) {
    // Each of the four waves contributes a quarter of the steepest hill slope.
    const double slope_share = std::tan(config.hill_slope_deg * kDegToRad) / kWaves;
    for (Wave& wave : waves_) {
      const double wavelength = rng.uniform(35.0, 90.0);
      const double angle = rng.uniform(0.0, 2 * M_PI);
      wave.k = 2 * M_PI / wavelength * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      wave.amplitude = slope_share * wavelength / (2 * M_PI);
      wave.phase = rng.uniform(0.0, 2 * M_PI);
    }
    bank_width_ = config.bank_height_m / (4.0 * std::tan(config.bank_slope_deg * kDegToRad));
    // A Gaussian -d exp(-(x/w)^2) is steepest at x = w / sqrt(2): slope d sqrt(2/e) / w.
    ditch_width_ = config.ditch_depth_m * std::sqrt(2.0 / std::exp(1.0)) /
                   std::tan(config.ditch_slope_deg * kDegToRad);
  }

  double height(const Eigen::Vector3d& position, double offset_m) const {
    double h = 0.0;
    for (const Wave& wave : waves_) h += wave.amplitude * std::sin(wave.k.dot(position.head<2>()) + wave.phase);
    h += config_.bank_height_m / (1.0 + std::exp(-(offset_m - kBankOffsetM) / bank_width_));
    const double x = (offset_m - kDitchOffsetM) / ditch_width_;
    h -= config_.ditch_depth_m * std::exp(-x * x);
    return h;
  }

 private:
  static constexpr int kWaves = 4;
  struct Wave {
    Eigen::Vector2d k;
    double amplitude = 0, phase = 0;
  };
  const OffroadSceneConfig& config_;
  std::array<Wave, kWaves> waves_;
  double bank_width_ = 1.0;
  double ditch_width_ = 1.0;
};

}  // namespace

void OffroadSceneConfig::validate() const {
  synthetic::ProblemList problems("OffroadSceneConfig");
  problems.require(length_m >= 20 && length_m <= 5000, "length_m must be in [20, 5000]");
  problems.require(object_density >= 0 && object_density <= 10, "object_density must be in [0, 10]");
  problems.require(half_width_m >= 16 && half_width_m <= 60, "half_width_m must be in [16, 60]");
  problems.require(track_width_m >= 1 && track_width_m <= 6, "track_width_m must be in [1, 6]");
  problems.require(hill_slope_deg >= 0 && hill_slope_deg <= 20, "hill_slope_deg must be in [0, 20]");
  problems.require(bank_slope_deg > 0 && bank_slope_deg <= 60, "bank_slope_deg must be in (0, 60]");
  problems.require(bank_height_m > 0 && bank_height_m <= 10, "bank_height_m must be in (0, 10]");
  problems.require(ditch_depth_m > 0 && ditch_depth_m <= 3, "ditch_depth_m must be in (0, 3]");
  problems.require(ditch_slope_deg > 0 && ditch_slope_deg <= 60, "ditch_slope_deg must be in (0, 60]");
  problems.require(camera_height_m > 0.2 && camera_height_m <= 5, "camera_height_m must be in (0.2, 5]");
  problems.require(speed_m_per_s > 0 && speed_m_per_s <= 20, "speed_m_per_s must be in (0, 20]");
  problems.throwIfAny();
}

SyntheticScene buildOffroadScene(const OffroadSceneConfig& config) {
  config.validate();
  SyntheticScene scene;
  scene.name = "offroad";
  scene.up_W = Eigen::Vector3d::UnitZ();
  scene.frame_description = "procedural off-road scene, z-up world frame, metres, track starts at the origin along +x";
  Rng path_rng(config.seed, 1);
  // Turns gentle enough that the terrain strip never folds: radius > 2 x its half width.
  const CentreLine line(synthetic::proceduralCentreline(config.length_m, 2.0 * config.half_width_m + 10.0,
                                                        0.0, path_rng),
                        scene.up_W, kGridStepM, 0.0);
  Rng terrain_rng(config.seed, 2);
  const Terrain terrain(config, terrain_rng);
  auto groundAt = [&](double s, double offset) {
    const synthetic::PathStation station = line.at(s);
    const Eigen::Vector3d flat = station.centre_W + offset * station.left_W;
    return Eigen::Vector3d(flat + terrain.height(flat, offset) * scene.up_W);
  };

  synthetic::LabeledMeshBuilder builder(scene.up_W);
  const auto& stations = line.stations();
  const auto columns = static_cast<std::size_t>(std::lround(2 * config.half_width_m / kGridStepM)) + 1;
  std::vector<Eigen::Vector3d> points;
  points.reserve(stations.size() * columns);
  for (const synthetic::PathStation& station : stations) {
    for (std::size_t c = 0; c < columns; ++c) {
      points.push_back(groundAt(station.s_m, -config.half_width_m + kGridStepM * static_cast<double>(c)));
    }
  }
  // Columns run right to left, so cells face up.
  builder.sheet(points, stations.size(), columns, [&](std::size_t, std::size_t c) {
    const double offset = -config.half_width_m + kGridStepM * (static_cast<double>(c) + 0.5);
    return std::abs(offset) <= config.track_width_m / 2 ? SurfaceLabel::kRoad : SurfaceLabel::kVegetation;
  });

  Rng rock_rng(config.seed, 3);
  const auto rocks = static_cast<int>(std::lround(config.object_density * config.length_m / 4.0));
  for (int r = 0; r < rocks; ++r) {
    const double s = rock_rng.uniform(0.0, line.length());
    const double side = rock_rng.chance(0.5) ? 1.0 : -1.0;
    const double offset = side * rock_rng.uniform(3.0, config.half_width_m - 2.0);
    const double radius = rock_rng.uniform(0.25, 1.1);
    // Sunk by a third of its size, as rocks rest in soil.
    synthetic::addBlob(builder, groundAt(s, offset) + 0.65 * radius * scene.up_W, radius, 0.3, rock_rng,
                       SurfaceLabel::kObstacle);
  }
  scene.ground_truth = builder.finish();
  scene.frames_T_W_C = synthetic::camerasAlong(line, config.speed_m_per_s / kSyntheticFrameRateHz, [&](double s) {
    return Eigen::Vector3d(groundAt(s, 0.0) + config.camera_height_m * scene.up_W);
  });
  return scene;
}

}  // namespace terramesh::datasets
