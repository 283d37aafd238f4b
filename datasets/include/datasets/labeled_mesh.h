#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "mesher/triangle_mesh.h"

namespace terramesh::datasets {

/// What a ground-truth face is. The numeric values are written to files: never renumber.
enum class SurfaceLabel : std::uint8_t {
  kRoad = 0,        ///< drivable paved or dirt surface (also flattened road in junctions)
  kSidewalk = 1,
  kCurb = 2,        ///< curb faces and curb tops
  kWall = 3,        ///< building and garage walls, roofs, slab edges
  kObstacle = 4,    ///< cars, rocks, ramp sides: things a robot must not drive into
  kVegetation = 5,  ///< grass, terrain off the track, trees
  kCeiling = 6,     ///< downward-facing undersides (garage ceilings)
  kRamp = 7,        ///< inclined drivable surfaces (street ramps, garage ramp)
};

/// Number of SurfaceLabel values.
inline constexpr std::size_t kSurfaceLabelCount = 8;

/// Lower-case name of a label ("road", "sidewalk", ...).
std::string_view toString(SurfaceLabel label);
/// The label with this name, or nothing.
std::optional<SurfaceLabel> parseSurfaceLabel(std::string_view name);

/// A ground-truth surface: a triangle mesh with, per face, a label and its true slope.
///
/// Faces are wound counter-clockwise seen from free space (normals towards where cameras can
/// be). `slope_deg[f]` is the angle in degrees between face f's normal and the scene's up
/// vector: 0 for level ground, 90 for a wall, 180 for a ceiling.
struct LabeledMesh {
  mesher::TriangleMesh mesh;
  std::vector<SurfaceLabel> labels;
  std::vector<float> slope_deg;

  /// @throw std::invalid_argument if labels or slopes do not have one entry per face.
  void validate() const;
};

/// Writes binary little-endian PLY: vertex `double x, y, z`; face `list uchar uint
/// vertex_indices`, `uchar label` (SurfaceLabel value) and `float slope_deg`. Written atomically.
/// @throw std::invalid_argument if the mesh does not validate; std::runtime_error if writing fails.
void writeLabeledPly(const std::filesystem::path& path, const LabeledMesh& mesh);

/// Reads a labelled PLY (ascii or binary, either endianness) with face properties `label` and
/// `slope_deg`, as written by writeLabeledPly. Other properties and elements are skipped.
/// @throw terramesh::InputError naming the file and the line (header) or element (body), e.g.
///        "face 12: label 9 is not a surface label".
LabeledMesh readLabeledPly(const std::filesystem::path& path);

}  // namespace terramesh::datasets
