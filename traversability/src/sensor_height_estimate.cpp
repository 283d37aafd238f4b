// The sensor height from the points under the path, and the decision whether a trajectory was
// driven (traversability/trajectory_evidence.h).
#include "traversability/trajectory_evidence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <optional>
#include <utility>
#include <sstream>
#include <stdexcept>


#include "ground_frame.h"

namespace terramesh::traversability {
namespace {

using internal::HorizontalGrid;
using internal::requireFrame;

/// MAD to standard deviation for Gaussian data.
constexpr double kMadToSigma = 1.4826;

/// The q-quantile (0 <= q <= 1) of `values`, linearly interpolated; NaN if empty.
double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (at - static_cast<double>(below)) * (values[above] - values[below]);
}

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  if (values.size() % 2 == 1) return *mid;
  const double upper = *mid;
  const double lower = *std::max_element(values.begin(), mid);
  return 0.5 * (lower + upper);
}

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f m", value);
  return text;
}

/// Keeps, of the depths beneath one sensor, the nearest layer that holds min_points_per_keyframe
/// of them: depths sorted and split where consecutive ones are more than layer_gap_m apart (a
/// floor of a multi-storey garage hides the levels below it; they are not the ground under the
/// path). Objects beside the path lie within the ground's layer. Empty if no layer holds enough.
void keepNearestLayer(std::vector<double>& depths, const TrajectoryEvidenceConfig& config) {
  std::sort(depths.begin(), depths.end());
  const auto needed = static_cast<std::size_t>(config.min_points_per_keyframe);
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= depths.size(); ++i) {
    if (i < depths.size() && depths[i] - depths[i - 1] <= config.layer_gap_m) continue;
    if (i - begin >= needed) {
      depths.erase(depths.begin() + static_cast<std::ptrdiff_t>(i), depths.end());
      depths.erase(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(begin));
      return;
    }
    begin = i;
  }
  depths.clear();
}

}  // namespace

SensorHeightEstimate estimateSensorHeight(const std::vector<Eigen::Vector3d>& sensors_W,
                                          const std::vector<Eigen::Vector3d>& points_W, const Eigen::Vector3d& up_W,
                                          double metres_per_unit, const TrajectoryEvidenceConfig& config) {
  config.validate();
  requireFrame(up_W, metres_per_unit);
  const geometry::PlanFrame plane = geometry::planFrame(up_W);
  const double radius = config.estimate_radius_m / metres_per_unit;
  const HorizontalGrid<std::uint32_t> grid(points_W, plane, radius);
  SensorHeightEstimate estimate;
  estimate.keyframes_total = sensors_W.size();
  std::vector<double> heights;
  std::vector<double> depths;
  for (const Eigen::Vector3d& sensor : sensors_W) {
    const Eigen::Vector2d at = plane.project(sensor);
    depths.clear();
    grid.around(at, [&](std::uint32_t index) {
      const Eigen::Vector3d& p = points_W[index];
      const double depth_m = (sensor - p).dot(up_W) * metres_per_unit;
      if (depth_m >= config.min_depth_below_m && (plane.project(p) - at).norm() <= radius) depths.push_back(depth_m);
    });
    if (depths.size() < static_cast<std::size_t>(config.min_points_per_keyframe)) continue;
    keepNearestLayer(depths, config);
    if (depths.size() < static_cast<std::size_t>(config.min_points_per_keyframe)) continue;
    const double envelope = quantile(depths, config.envelope_quantile);
    depths.erase(std::remove_if(depths.begin(), depths.end(),
                                [&](double d) { return d < envelope - config.ground_band_m; }),
                 depths.end());
    heights.push_back(median(depths));
  }
  estimate.keyframes_used = heights.size();
  const double needed = std::max(static_cast<double>(config.min_keyframes),
                                 config.min_keyframe_fraction * static_cast<double>(sensors_W.size()));
  if (static_cast<double>(heights.size()) < needed) {
    std::ostringstream reason;
    reason << "only " << heights.size() << " of " << sensors_W.size() << " keyframes have "
           << config.min_points_per_keyframe << " or more points within " << config.estimate_radius_m
           << " m beneath them (needed " << std::ceil(needed) << ")";
    estimate.reason = reason.str();
    estimate.height_m = std::numeric_limits<double>::quiet_NaN();
    estimate.spread_m = std::numeric_limits<double>::quiet_NaN();
    return estimate;
  }
  estimate.height_m = median(heights);
  std::vector<double> deviations;
  deviations.reserve(heights.size());
  for (double h : heights) deviations.push_back(std::abs(h - estimate.height_m));
  estimate.spread_m = kMadToSigma * median(deviations);
  if (estimate.height_m > config.max_sensor_height_m) {
    estimate.status = SensorHeightEstimate::Status::kNotDriven;
    estimate.reason = "the sensor is " + metres(estimate.height_m) + " above the points beneath the path (more than " +
                      metres(config.max_sensor_height_m) + ": not a ground robot)";
  } else if (estimate.spread_m > config.max_height_spread_m) {
    estimate.status = SensorHeightEstimate::Status::kNotDriven;
    estimate.reason = "the sensor's height above the points beneath the path varies by " + metres(estimate.spread_m) +
                      " (more than " + metres(config.max_height_spread_m) + ": not a sensor mounted on a ground robot)";
  } else {
    estimate.status = SensorHeightEstimate::Status::kDriven;
  }
  return estimate;
}

TrajectoryEvidenceDecision decideTrajectoryEvidence(const SensorHeightEstimate& estimate,
                                                    std::optional<double> profile_height_m,
                                                    std::optional<double> override_height_m,
                                                    const TrajectoryEvidenceConfig& config) {
  TrajectoryEvidenceDecision decision;
  decision.estimate = estimate;
  const std::optional<double> given = override_height_m ? override_height_m : profile_height_m;
  const std::string given_source = override_height_m ? "--sensor-height-m" : "the robot profile";
  const std::string measured = "sensor height estimated from the points beneath the path: " +
                               metres(estimate.height_m) + " (spread " + metres(estimate.spread_m) + ", " +
                               std::to_string(estimate.keyframes_used) + " of " +
                               std::to_string(estimate.keyframes_total) + " keyframes)";
  using Status = SensorHeightEstimate::Status;
  if (estimate.status == Status::kNotDriven) {
    decision.summary = "trajectory evidence: off, the trajectory does not look driven: " + estimate.reason;
    return decision;
  }
  if (estimate.status == Status::kNoData && !given) {
    decision.summary = "trajectory evidence: off, no sensor height given and none can be estimated: " + estimate.reason;
    return decision;
  }
  decision.enabled = true;
  if (!given) {
    decision.sensor_height_m = estimate.height_m;
    decision.source = "the data";
    decision.summary = "trajectory evidence: on, " + measured;
    return decision;
  }
  decision.sensor_height_m = *given;
  decision.source = given_source;
  decision.summary = "trajectory evidence: on, sensor height " + metres(*given) + " from " + given_source;
  if (estimate.status == Status::kNoData) {
    decision.summary += " (not checked against the data: " + estimate.reason + ")";
    return decision;
  }
  decision.summary += "; " + measured;
  const double tolerance = std::max(config.disagreement_tolerance_m, 3 * estimate.spread_m);
  if (std::abs(*given - estimate.height_m) > tolerance) {
    decision.warning = "the sensor height from " + given_source + " (" + metres(*given) +
                       ") disagrees with the data (" + metres(estimate.height_m) + " +- " +
                       metres(estimate.spread_m) + " above the points beneath the path); using " + metres(*given);
  }
  return decision;
}


}  // namespace terramesh::traversability
