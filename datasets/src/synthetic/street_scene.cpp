#include <cmath>
#include <stdexcept>

#include "centre_line.h"
#include "datasets/synthetic_scene.h"
#include "mesh_builder.h"
#include "problem_list.h"
#include "street_layout.h"
#include "street_objects.h"

namespace terramesh::datasets::synthetic {
namespace {

constexpr double kStationSpacingM = 1.0;
/// Smooths the camera path into a road centre line (removes steering jitter).
constexpr double kTrajectorySmoothingM = 8.0;

/// Sweeps the cross-sections of each run of consecutive built stations into one sheet, from the
/// right verge to the left verge (so the sheet faces up).
void addGround(const StreetLayout& layout, LabeledMeshBuilder& builder) {
  const std::size_t n = layout.line().stations().size();
  constexpr std::size_t kColumns = 2 * kProfilePoints + 1;
  std::size_t run_start = 0;
  while (run_start < n) {
    if (!layout.built(run_start)) {
      ++run_start;
      continue;
    }
    std::size_t run_end = run_start;
    while (run_end + 1 < n && layout.built(run_end + 1)) ++run_end;
    const std::size_t rows = run_end - run_start + 1;
    if (rows >= 2) {
      std::vector<Eigen::Vector3d> points;
      points.reserve(rows * kColumns);
      for (std::size_t i = run_start; i <= run_end; ++i) {
        for (std::size_t c = 0; c < kColumns; ++c) {
          if (c == kProfilePoints) {
            points.push_back(layout.pointAt(i, 1, 0.0, 0.0));
            continue;
          }
          const int side = c < kProfilePoints ? -1 : 1;
          const std::size_t k = c < kProfilePoints ? kProfilePoints - 1 - c : c - kProfilePoints - 1;
          const ProfilePoint& point = layout.profile(i, side)[k];
          points.push_back(layout.pointAt(i, side, point.offset_m, point.height_m));
        }
      }
      // A segment takes the label of its outer end; where a curb is cut for a junction between
      // two stations, the sloped transition keeps the curb's (or sidewalk's) label, not road.
      auto label = [&](std::size_t i, std::size_t c) {
        if (c < kProfilePoints) return layout.profile(i, -1)[kProfilePoints - 1 - c].label;
        return layout.profile(i, 1)[c - kProfilePoints].label;
      };
      builder.sheet(points, rows, kColumns, [&](std::size_t row, std::size_t c) {
        const SurfaceLabel here = label(run_start + row, c), next = label(run_start + row + 1, c);
        return here == SurfaceLabel::kRoad ? next : here;
      });
    }
    run_start = run_end + 1;
  }
}

/// Frames cut after `length_m` travelled (0: all).
PoseList cutByDistance(const PoseList& poses, double length_m) {
  if (length_m <= 0) return poses;
  PoseList cut = {poses.front()};
  double travelled = 0.0;
  for (std::size_t i = 1; i < poses.size() && travelled <= length_m; ++i) {
    travelled += (poses[i].translation() - poses[i - 1].translation()).norm();
    cut.push_back(poses[i]);
  }
  return cut;
}

}  // namespace
}  // namespace terramesh::datasets::synthetic

namespace terramesh::datasets {

void StreetSceneConfig::validate() const {
  synthetic::ProblemList problems("StreetSceneConfig");
  problems.require(length_m >= 0, "length_m must be >= 0");
  problems.require(object_density >= 0 && object_density <= 10, "object_density must be in [0, 10]");
  problems.require(road_width_m >= 3 && road_width_m <= 30, "road_width_m must be in [3, 30]");
  problems.require(camber_percent >= 0 && camber_percent <= 10, "camber_percent must be in [0, 10]");
  problems.require(max_grade_percent >= 0 && max_grade_percent <= 15, "max_grade_percent must be in [0, 15]");
  problems.require(min_turn_radius_m >= 20, "min_turn_radius_m must be >= 20");
  problems.require(curb_height_m >= 0 && curb_height_m <= 0.5, "curb_height_m must be in [0, 0.5]");
  problems.require(sidewalk_width_m >= 0.5 && sidewalk_width_m <= 10, "sidewalk_width_m must be in [0.5, 10]");
  problems.require(verge_width_m >= 0 && verge_width_m <= 30, "verge_width_m must be in [0, 30]");
  problems.require(camera_height_m > 0.2 && camera_height_m <= 5, "camera_height_m must be in (0.2, 5]");
  problems.require(speed_m_per_s > 0 && speed_m_per_s <= 40, "speed_m_per_s must be in (0, 40]");
  problems.require(ramp_slope_deg > 1 && ramp_slope_deg < 30, "ramp_slope_deg must be in (1, 30)");
  problems.require(ramp_spacing_m >= 20, "ramp_spacing_m must be >= 20");
  problems.throwIfAny();
}

SyntheticScene buildStreetScene(const StreetSceneConfig& config, const PoseList& trajectory_T_W_C) {
  config.validate();
  SyntheticScene scene;
  scene.name = "street";
  std::vector<Eigen::Vector3d> crown_path;
  if (trajectory_T_W_C.empty()) {
    if (config.length_m < 20) throw std::invalid_argument("StreetSceneConfig: length_m must be >= 20");
    scene.up_W = Eigen::Vector3d::UnitZ();
    scene.frame_description = "procedural street, z-up world frame, metres, road starts at the origin along +x";
    synthetic::Rng rng(config.seed, 1);
    crown_path = synthetic::proceduralCentreline(config.length_m, config.min_turn_radius_m,
                                                 config.max_grade_percent / 100.0, rng);
  } else {
    scene.up_W = Eigen::Vector3d(0.0, -1.0, 0.0);
    scene.frame_description = "KITTI world frame (camera of the first pose file frame: x right, y down, "
                              "z forward), metres";
    scene.frames_T_W_C = synthetic::cutByDistance(trajectory_T_W_C, config.length_m);
    for (const Eigen::Isometry3d& pose : scene.frames_T_W_C) {
      crown_path.push_back(pose.translation() - config.camera_height_m * scene.up_W);
    }
  }
  const double smoothing = trajectory_T_W_C.empty() ? 0.0 : synthetic::kTrajectorySmoothingM;
  const synthetic::CentreLine line(crown_path, scene.up_W, synthetic::kStationSpacingM, smoothing);
  if (trajectory_T_W_C.empty()) {
    scene.frames_T_W_C = synthetic::camerasAlong(
        line, config.speed_m_per_s / kSyntheticFrameRateHz,
        [&](double s) { return Eigen::Vector3d(line.at(s).centre_W + config.camera_height_m * scene.up_W); });
  }
  const synthetic::StreetLayout layout(line, config);
  synthetic::LabeledMeshBuilder builder(scene.up_W);
  synthetic::addGround(layout, builder);
  synthetic::addStreetObjects(layout, builder);
  scene.ground_truth = builder.finish();
  return scene;
}

}  // namespace terramesh::datasets
