#pragma once

// The robot profile's schema: every numeric key with its range, and the check of a whole profile
// (RobotProfile::validate and the YAML reader of traversability_io share it). Internal.
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "traversability/robot_profile.h"

namespace terramesh::traversability::internal {

/// Allowed range of one numeric field: [lo, hi], either end open if flagged.
struct Range {
  double lo;
  double hi;
  bool lo_open;
  bool hi_open;

  bool contains(double value) const {
    if (!std::isfinite(value)) return false;
    if (lo_open ? value <= lo : value < lo) return false;
    return hi_open ? value < hi : value <= hi;
  }
  std::string text() const {
    std::ostringstream out;
    out << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
    return out.str();
  }
};

/// One numeric key of the YAML schema, the field it fills and its range.
struct NumericKey {
  const char* key;  ///< dotted path, e.g. "footprint.radius_m"
  Range range;
  bool integer;
  std::function<double&(RobotProfile&)> field;
};

/// Every numeric key of the schema, in the order writeRobotProfile writes them.
const std::vector<NumericKey>& numericKeys();

// One bit each in FaceLayers::heading_fits, which the float exports (GeoTIFF, HDF5) hold exactly.
inline const Range kHeadingsRange{1, 24, false, false};
inline const Range kMinRaysRange{0, 1e6, false, false};
inline const Range kSensorHeightRange{0, 20, true, false};

/// A number as the problems and errors print it (10 significant digits).
std::string formatNumber(double value);

/// Every problem of a profile, each "key: value (expected ...)".
std::vector<std::string> problemsOf(const RobotProfile& profile);

}  // namespace terramesh::traversability::internal
