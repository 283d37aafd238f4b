#pragma once
// Where the parts of a street go: which stations of the centre line carry road (a second pass
// over the same road builds nothing), the cross-section at each station (road with camber, curb,
// sidewalk, verge), where it is cut flat because another pass crosses (junctions), and how far a
// point is from where the camera drives.

#include <array>
#include <vector>

#include "centre_line.h"
#include "datasets/synthetic_scene.h"

namespace terramesh::datasets::synthetic {

/// A point of a cross-section, `offset_m` out from the crown to one side and `height_m` above
/// the crown; `label` is that of the segment from the previous (inner) point to this one.
struct ProfilePoint {
  double offset_m = 0.0;
  double height_m = 0.0;
  SurfaceLabel label = SurfaceLabel::kRoad;
  bool flattened = false;
};

/// Points of one side of the cross-section, crown excluded: 4 road, curb face, curb top,
/// sidewalk, verge.
inline constexpr std::size_t kProfilePoints = 8;
using SideProfile = std::array<ProfilePoint, kProfilePoints>;
inline constexpr std::size_t kRoadEdge = 3;     ///< index of the road edge at the curb's foot
inline constexpr std::size_t kSidewalkEnd = 6;  ///< index of the sidewalk's outer edge

class StreetLayout {
 public:
  StreetLayout(const CentreLine& line, const StreetSceneConfig& config);

  const CentreLine& line() const { return line_; }
  const StreetSceneConfig& config() const { return config_; }
  /// Whether station i carries road surface (false on a repeated pass over built road).
  bool built(std::size_t i) const { return built_[i]; }
  /// Cross-section of side +1 (left) or -1 (right) at a built station.
  const SideProfile& profile(std::size_t i, int side) const { return profiles_[i][side > 0 ? 1 : 0]; }
  /// Whether any part of that side of station i is cut flat for a crossing.
  bool inJunction(std::size_t i, int side) const;
  /// World position of a profile point.
  Eigen::Vector3d pointAt(std::size_t i, int side, double offset_m, double height_m) const;
  /// Height above the crown of the ground surface at `offset_m` on that side (interpolated).
  double groundHeight(std::size_t i, int side, double offset_m) const;
  /// Whether every station of the camera path is at least `clearance_m` away horizontally.
  bool clearOfTraffic(const Eigen::Vector3d& point_W, double clearance_m) const;

 private:
  void markBuiltStations();
  SideProfile nominalProfile(std::size_t i, int side) const;
  void cutJunctions(std::size_t i, int side, SideProfile& profile) const;

  const CentreLine& line_;
  StreetSceneConfig config_;
  PlanarPointGrid all_stations_;
  std::vector<bool> built_;
  std::vector<std::array<SideProfile, 2>> profiles_;
};

}  // namespace terramesh::datasets::synthetic
