#include "street_layout.h"

#include <algorithm>
#include <cmath>

namespace terramesh::datasets::synthetic {
namespace {

/// Stations this far apart along the path belong to different passes (or different roads).
constexpr double kOtherPassArcM = 40.0;
/// A pass crosses another when their headings differ by more than this.
constexpr double kCrossingAngleDeg = 25.0;
constexpr double kCurbTopWidthM = 0.15;
/// Sidewalks rise away from the road by this fraction (2 %), so water runs to the gutter.
constexpr double kSidewalkCrossSlope = 0.02;
/// A cross-section reaches at most this fraction of the turn radius on the inside of a turn, so
/// the swept surface never folds over itself.
constexpr double kInnerReachOfRadius = 0.85;

}  // namespace

StreetLayout::StreetLayout(const CentreLine& line, const StreetSceneConfig& config)
    : line_(line), config_(config), all_stations_(line.up(), 10.0) {
  const auto& stations = line_.stations();
  for (std::size_t i = 0; i < stations.size(); ++i) all_stations_.insert(stations[i].centre_W, i);
  markBuiltStations();
  profiles_.resize(stations.size());
  for (std::size_t i = 0; i < stations.size(); ++i) {
    if (!built_[i]) continue;
    for (const int side : {-1, 1}) {
      SideProfile profile = nominalProfile(i, side);
      cutJunctions(i, side, profile);
      profiles_[i][side > 0 ? 1 : 0] = profile;
    }
  }
}

void StreetLayout::markBuiltStations() {
  const auto& stations = line_.stations();
  const double half_road = config_.road_width_m / 2;
  PlanarPointGrid built_grid(line_.up(), 10.0);
  built_.assign(stations.size(), false);
  for (std::size_t i = 0; i < stations.size(); ++i) {
    bool covered = false;
    built_grid.forEachWithin(stations[i].centre_W, half_road, [&](std::size_t j) {
      covered = covered || stations[i].s_m - stations[j].s_m > kOtherPassArcM;
    });
    if (covered) continue;
    built_[i] = true;
    built_grid.insert(stations[i].centre_W, i);
  }
}

SideProfile StreetLayout::nominalProfile(std::size_t i, int side) const {
  const double half = config_.road_width_m / 2;
  const double camber = config_.camber_percent / 100.0;
  const double edge = -camber * half;
  const double curb = edge + config_.curb_height_m;
  const double sidewalk_end = half + config_.sidewalk_width_m;
  const double sidewalk_top = curb + kSidewalkCrossSlope * config_.sidewalk_width_m;
  SideProfile profile;
  for (std::size_t k = 0; k < 4; ++k) {
    const double offset = half * static_cast<double>(k + 1) / 4.0;
    profile[k] = {offset, -camber * offset, SurfaceLabel::kRoad};
  }
  profile[4] = {half, curb, SurfaceLabel::kCurb};
  profile[5] = {half + kCurbTopWidthM, curb + kSidewalkCrossSlope * kCurbTopWidthM, SurfaceLabel::kCurb};
  profile[6] = {sidewalk_end, sidewalk_top, SurfaceLabel::kSidewalk};
  profile[7] = {sidewalk_end + config_.verge_width_m, sidewalk_top, SurfaceLabel::kVegetation};
  // On the inside of a turn, keep the section short of the turn's centre.
  const double curvature = line_.stations()[i].curvature_per_m;
  if (curvature * side > 0) {
    const double reach = kInnerReachOfRadius / std::abs(curvature);
    for (ProfilePoint& point : profile) point.offset_m = std::min(point.offset_m, reach);
  }
  return profile;
}

void StreetLayout::cutJunctions(std::size_t i, int side, SideProfile& profile) const {
  const auto& stations = line_.stations();
  const double cos_crossing = std::cos(kCrossingAngleDeg * M_PI / 180.0);
  const double reach = config_.road_width_m / 2 + 0.5;
  const double edge_height = profile[kRoadEdge].height_m;
  std::size_t outermost = 0;  // outermost point inside a crossing road, 0 if none
  for (std::size_t k = kRoadEdge + 1; k < kProfilePoints; ++k) {
    const Eigen::Vector3d p = pointAt(i, side, profile[k].offset_m, profile[k].height_m);
    bool crossed = false;
    all_stations_.forEachWithin(p, reach, [&](std::size_t j) {
      crossed = crossed || (std::abs(stations[i].s_m - stations[j].s_m) > kOtherPassArcM &&
                            std::abs(stations[i].heading_W.dot(stations[j].heading_W)) < cos_crossing);
    });
    if (crossed) outermost = k;
  }
  // The crossing road joins this one: everything from the curb out to it is road level.
  for (std::size_t k = kRoadEdge + 1; k <= outermost; ++k) {
    profile[k].height_m = edge_height;
    profile[k].label = SurfaceLabel::kRoad;
    profile[k].flattened = true;
  }
}

bool StreetLayout::inJunction(std::size_t i, int side) const {
  const SideProfile& p = profile(i, side);
  return std::any_of(p.begin(), p.end(), [](const ProfilePoint& point) { return point.flattened; });
}

Eigen::Vector3d StreetLayout::pointAt(std::size_t i, int side, double offset_m, double height_m) const {
  const PathStation& station = line_.stations()[i];
  return station.centre_W + side * offset_m * station.left_W + height_m * line_.up();
}

double StreetLayout::groundHeight(std::size_t i, int side, double offset_m) const {
  const SideProfile& p = profile(i, side);
  double inner_offset = 0.0, inner_height = 0.0;
  for (const ProfilePoint& point : p) {
    if (offset_m <= point.offset_m && point.offset_m > inner_offset) {
      const double t = (offset_m - inner_offset) / (point.offset_m - inner_offset);
      return inner_height + t * (point.height_m - inner_height);
    }
    inner_offset = point.offset_m;
    inner_height = point.height_m;
  }
  return p.back().height_m;
}

bool StreetLayout::clearOfTraffic(const Eigen::Vector3d& point_W, double clearance_m) const {
  bool clear = true;
  all_stations_.forEachWithin(point_W, clearance_m, [&clear](std::size_t) { clear = false; });
  return clear;
}

}  // namespace terramesh::datasets::synthetic
