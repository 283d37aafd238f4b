#pragma once

// The per-face layers of a traversability map as named data: one registry (name, unit, file type,
// no-data value, description, how to read and set the value) that the exports (traversability.ply,
// the GeoTIFF bands, the mesh_navigation HDF5's own layers), the summary, the incremental tests and
// the viewer (served as JSON by `terramesh view`) iterate. Adding a layer is one FaceLayers field,
// the stage that computes it, and one entry here.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "traversability/layered_mesh.h"

namespace terramesh::traversability {

/// How a layer is stored in traversability.ply (GeoTIFF bands and HDF5 channels are Float32).
enum class LayerType : std::uint8_t { kFloat32, kUInt8, kUInt16, kUInt32 };

/// One per-face layer of FaceLayers.
struct LayerInfo {
  const char* name;         ///< file and API name; the unit is in the name where it has one
  const char* unit;         ///< "deg", "m", "fraction", "count", "code", "bits" or "" (a cost)
  LayerType type;           ///< its PLY property type
  const char* description;  ///< one line: the viewer's label and the docs' table
  /// The value of a face (exact for the integer layers); NaN where the face has none (`cost` of
  /// an unknown face).
  double (*get)(const FaceLayers& face);
  /// Sets the value read back from a file (integer layers receive an exact integer in range).
  void (*set)(FaceLayers& face, double value);
  /// Files written before the layer existed lack it: readers keep the default then.
  bool optional_in_files;
  /// Which end is worse for the robot, for the per-vertex value (LayeredMesh::vertexWorst).
  LayeredMesh::Worst worst;
  /// A fixed display range [min, max] for viewers; min > max: none (the data's range).
  float display_min;
  float display_max;
  /// Statistics over known faces in traversability_summary.txt.
  bool in_summary;
  /// A per-vertex layer of its own in traversability.h5 (beside those under mesh_map's names).
  bool in_mesh_map;
};

/// Every per-face layer, in the order traversability.ply writes them after the class flags (and
/// the GeoTIFF after its `class` band).
const std::vector<LayerInfo>& faceLayerRegistry();

/// The layer named `name`, or null.
const LayerInfo* findFaceLayer(std::string_view name);

/// Bits of FaceLayers::reasons: why a face is not free. The numeric values are written to files:
/// never renumber.
namespace reason {
inline constexpr std::uint16_t kTooSteep = 1u << 0;            ///< lethal: measured slope over the limit
inline constexpr std::uint16_t kNoHeadingFits = 1u << 1;       ///< lethal: step, support or an obstacle at every heading
inline constexpr std::uint16_t kLowClearance = 1u << 2;        ///< lethal: measured geometry above, too low
inline constexpr std::uint16_t kGuessedWall = 1u << 3;         ///< uncertain: interpolated and too steep
inline constexpr std::uint16_t kPossibleStep = 1u << 4;        ///< uncertain: rises over a step, inside unsupported
inline constexpr std::uint16_t kSlopeMayExceed = 1u << 5;      ///< uncertain: within the points' noise, too steep
// Uncertain, the footprint fits as reconstructed but not in the worst case, at any heading that
// fits, because of:
inline constexpr std::uint16_t kWorstCaseRelief = 1u << 6;     ///< the ground's relief (a step or lost support)
inline constexpr std::uint16_t kPossibleObstacle = 1u << 7;    ///< interpolated geometry in the body
inline constexpr std::uint16_t kObstacleExtension = 1u << 8;   ///< where a measured obstacle may extend
inline constexpr std::uint16_t kUnconfirmedPoint = 1u << 9;    ///< a point too few keyframes saw, grown
inline constexpr std::uint16_t kUnknownLowClearance = 1u << 10; ///< uncertain: closing geometry above, too low
inline constexpr std::uint16_t kClosingGeometry = 1u << 11;    ///< unknown: touches a Steiner vertex
inline constexpr std::uint16_t kFewRays = 1u << 12;            ///< unknown: observed by fewer than min_rays rays
inline constexpr std::uint16_t kSeenFromBehind = 1u << 13;     ///< uncertain: its points seen only from behind it
/// How many bits there are.
inline constexpr std::size_t kCount = 14;
/// Names of the bits, lowest first ("too_steep", ...): kCount of them.
const std::vector<const char*>& names();
}  // namespace reason

}  // namespace terramesh::traversability
