#include "street_objects.h"

#include <cmath>
#include <vector>

#include "primitives.h"

namespace terramesh::datasets::synthetic {
namespace {

/// Random streams of the scene seed, one per kind of object.
enum Stream : std::uint64_t { kRampStream = 10, kBuildingStream, kCarStream, kTreeStream };

constexpr double kBuildingSetbackM = 1.0;   // from the sidewalk's outer edge
constexpr double kSinkM = 0.5;              // how far solids reach below the ground they stand on
constexpr double kEgoClearanceM = 1.3;      // parked cars keep this far from the camera path

/// An interval of arc length on one side of the street that buildings must leave free.
struct Reserved {
  int side;
  double from_s, to_s;
};

class StreetFurnisher {
 public:
  StreetFurnisher(const StreetLayout& layout, LabeledMeshBuilder& builder)
      : layout_(layout), builder_(builder), config_(layout.config()),
        stations_(layout.line().stations()), half_road_(config_.road_width_m / 2),
        sidewalk_end_(half_road_ + config_.sidewalk_width_m) {}

  void addRamps() {
    const double length = kStreetRampHeightM / std::tan(config_.ramp_slope_deg * M_PI / 180.0);
    const double width = 2.0;
    const double start = std::min(60.0, layout_.line().length() / 3.0);
    int side = 1;
    for (double s = start; s + length < layout_.line().length(); s += config_.ramp_spacing_m, side = -side) {
      // Try a few places near s until one is clear.
      for (double shift = 0.0; shift < 50.0; shift += 10.0) {
        const std::size_t i = stationAt(s + shift);
        const double lateral = sidewalk_end_ + 0.3 + width / 2;
        if (!usable(i, side) ||
            !footprintClear(i, side, 0.0, length, lateral - width / 2, lateral + width / 2, sidewalk_end_)) {
          continue;
        }
        const Eigen::Vector3d origin = layout_.pointAt(i, side, lateral, layout_.profile(i, side).back().height_m);
        addWedge(builder_, uprightFrame(origin, stations_[i].heading_W, layout_.line().up()), length, width,
                 kStreetRampHeightM, kSinkM, SurfaceLabel::kRamp, SurfaceLabel::kObstacle);
        reserved_.push_back({side, stations_[i].s_m - 3.0, stations_[i].s_m + length + 3.0});
        break;
      }
    }
  }

  void addBuildings() {
    if (config_.object_density <= 0) return;
    Rng rng(config_.seed, kBuildingStream);
    for (const int side : {-1, 1}) {
      double next_s = rng.uniform(0.0, 10.0);
      for (std::size_t i = 0; i < stations_.size(); ++i) {
        if (stations_[i].s_m < next_s || !usable(i, side)) continue;
        const double length = rng.uniform(8.0, 25.0);
        const double depth = rng.uniform(8.0, 14.0);
        const double height = rng.uniform(6.0, 20.0);
        const double front = sidewalk_end_ + kBuildingSetbackM;
        if (isReserved(side, stations_[i].s_m, stations_[i].s_m + length) ||
            !footprintClear(i, side, 0.0, length, front, front + depth, sidewalk_end_ + 0.5)) {
          next_s = stations_[i].s_m + 2.0;
          continue;
        }
        const double ground = layout_.profile(i, side).back().height_m;
        const Eigen::Vector3d centre = layout_.pointAt(i, side, front + depth / 2, ground - kSinkM) +
                                       stations_[i].heading_W * length / 2;
        addBox(builder_, uprightFrame(centre, stations_[i].heading_W, layout_.line().up()),
               {length, depth, height + kSinkM}, SurfaceLabel::kWall, SurfaceLabel::kWall);
        next_s = stations_[i].s_m + length + rng.uniform(3.0, 15.0) / config_.object_density;
      }
    }
  }

  void addCars() {
    if (config_.object_density <= 0) return;
    Rng rng(config_.seed, kCarStream);
    const double lateral = half_road_ - kCarWidthM / 2 - 0.25;
    for (const int side : {-1, 1}) {
      double next_s = rng.uniform(5.0, 30.0) / config_.object_density;
      for (std::size_t i = 0; i < stations_.size(); ++i) {
        if (stations_[i].s_m < next_s || !usable(i, side)) continue;
        next_s = stations_[i].s_m + 2.0;
        if (!nearJunctionFree(i, side) ||
            !footprintClear(i, side, -kCarLengthM / 2, kCarLengthM / 2, lateral - kCarWidthM / 2,
                            lateral + kCarWidthM / 2, kEgoClearanceM)) {
          continue;
        }
        const Eigen::Vector3d base = layout_.pointAt(i, side, lateral, layout_.groundHeight(i, side, lateral));
        // Parked cars face the direction of their side's traffic.
        const Eigen::Vector3d heading = side > 0 ? Eigen::Vector3d(-stations_[i].heading_W) : stations_[i].heading_W;
        addCar(builder_, uprightFrame(base, heading, layout_.line().up()));
        next_s = stations_[i].s_m + kCarLengthM + rng.uniform(1.0, 30.0) / config_.object_density;
      }
    }
  }

  void addTrees() {
    if (config_.object_density <= 0) return;
    Rng rng(config_.seed, kTreeStream);
    const double lateral = sidewalk_end_ - 0.6;
    for (const int side : {-1, 1}) {
      double next_s = rng.uniform(0.0, 15.0) / config_.object_density;
      for (std::size_t i = 0; i < stations_.size(); ++i) {
        if (stations_[i].s_m < next_s || !usable(i, side)) continue;
        next_s = stations_[i].s_m + 2.0;
        const Eigen::Vector3d base = layout_.pointAt(i, side, lateral, layout_.groundHeight(i, side, lateral));
        if (!nearJunctionFree(i, side) || !layout_.clearOfTraffic(base, half_road_ + 1.0)) continue;
        const double trunk = rng.uniform(2.2, 3.2);
        const double crown = rng.uniform(1.2, 2.2);
        addCylinder(builder_, base - kSinkM * layout_.line().up(), 0.15, trunk + kSinkM, 8, SurfaceLabel::kVegetation);
        addBlob(builder_, base + (trunk + 0.7 * crown) * layout_.line().up(), crown, 0.2, rng,
                SurfaceLabel::kVegetation);
        next_s = stations_[i].s_m + rng.uniform(8.0, 20.0) / config_.object_density;
      }
    }
  }

 private:
  std::size_t stationAt(double s) const {
    const std::size_t i = static_cast<std::size_t>(std::lround(s / layout_.line().spacing()));
    return std::min(i, stations_.size() - 1);
  }

  /// A station where things may stand on this side: built, not in a junction, not the last.
  bool usable(std::size_t i, int side) const {
    return i + 1 < stations_.size() && layout_.built(i) && !layout_.inJunction(i, side);
  }

  /// No junction within 10 m along the road.
  bool nearJunctionFree(std::size_t i, int side) const {
    const std::size_t from = i >= 10 ? i - 10 : 0;
    const std::size_t to = std::min(i + 10, stations_.size() - 1);
    for (std::size_t j = from; j <= to; ++j) {
      if (!layout_.built(j) || layout_.inJunction(j, side)) return false;
    }
    return true;
  }

  /// Whether a rectangle [along0, along1] x [lateral0, lateral1] in station i's frame (on `side`)
  /// keeps `clearance_m` from every station of the camera path, sampled every metre.
  bool footprintClear(std::size_t i, int side, double along0, double along1, double lateral0,
                      double lateral1, double clearance_m) const {
    const PathStation& station = stations_[i];
    for (double a = along0;; a = std::min(a + 1.0, along1)) {
      for (double l = lateral0;; l = std::min(l + 1.0, lateral1)) {
        const Eigen::Vector3d p = station.centre_W + a * station.heading_W + side * l * station.left_W;
        if (!layout_.clearOfTraffic(p, clearance_m)) return false;
        if (l >= lateral1) break;
      }
      if (a >= along1) break;
    }
    return true;
  }

  bool isReserved(int side, double from_s, double to_s) const {
    for (const Reserved& r : reserved_) {
      if (r.side == side && from_s < r.to_s && to_s > r.from_s) return true;
    }
    return false;
  }

  const StreetLayout& layout_;
  LabeledMeshBuilder& builder_;
  const StreetSceneConfig& config_;
  const std::vector<PathStation>& stations_;
  double half_road_;
  double sidewalk_end_;
  std::vector<Reserved> reserved_;
};

}  // namespace

void addStreetObjects(const StreetLayout& layout, LabeledMeshBuilder& builder) {
  StreetFurnisher furnisher(layout, builder);
  furnisher.addRamps();
  furnisher.addBuildings();
  furnisher.addCars();
  furnisher.addTrees();
}

}  // namespace terramesh::datasets::synthetic
