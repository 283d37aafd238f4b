// The footprint's sample grid: what a sample found, and the grid's node indices along one axis
// (LayerComputer's ground sampling and its setup). Internal.
#pragma once

#include <algorithm>

namespace terramesh::traversability::internal {

/// What a footprint sample found: no ground in its band, ground steeper than max_slope, level.
inline constexpr char kNoGround = 0;
inline constexpr char kSteepGround = 1;
inline constexpr char kLevelGround = 2;
/// No measured ground in the sample's band, but closing (Steiner) geometry: nobody looked there.
inline constexpr char kUnknownGround = 3;
/// No ground in the sample's band, and its reference point lies in space nobody carved: the first
/// face above it faces up (matter the rays never reached), or none does (beyond the map). The
/// surface is closed, so space the rays carved lies under a face that faces down.
inline constexpr char kNoDataGround = 4;

/// floor and ceil of a double known to lie well within the int range (std::floor is a library
/// call without SSE4.1).
inline int floorInt(double t) {
  const int i = static_cast<int>(t);
  return static_cast<double>(i) > t ? i - 1 : i;
}
inline int ceilInt(double t) {
  const int i = static_cast<int>(t);
  return static_cast<double>(i) < t ? i + 1 : i;
}

/// Of the nodes centre + i * spacing (|i| <= k) of one axis of the footprint's sample grid: the
/// first index that may lie at or above lo and the last that may lie at or below hi (one node of
/// margin for rounding; NaN: all).
inline int firstNode(double lo, double centre, double spacing, int k) {
  const double t = (lo - centre) / spacing;
  if (!(t > -k)) return -k;
  return t > k ? k + 1 : std::max(-k, floorInt(t) - 1);
}
inline int lastNode(double hi, double centre, double spacing, int k) {
  const double t = (hi - centre) / spacing;
  if (!(t < k)) return k;
  return t < -k ? -k - 1 : std::min(k, floorInt(t) + 1);
}

/// Whether some node centre + i * spacing, i in [first, last], lies in [lo, hi] (computed as a
/// footprint sample's position is).
inline bool holdsNode(int first, int last, double lo, double hi, double centre, double spacing) {
  for (int i = first; i <= last; ++i) {
    const double v = centre + i * spacing;
    if (!(lo > v) && !(hi < v)) return true;
  }
  return false;
}

}  // namespace terramesh::traversability::internal
