#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesher/triangle_mesh.h"

namespace terramesh::mesher {

/// Writes a binary little-endian PLY: vertex x y z (float64) and `steiner` (uchar, 1 for Steiner
/// vertices), then `driven` (uchar, 1 for driven-ground samples) only if some vertex is driven,
/// and face vertex_indices (uchar count, uint32 indices), then the faces' `rays` and
/// `front_crossings` (uint32) and `view_sides` (uchar) where the mesh has them, with `comments`
/// in the header after the first ("terramesh manifold mesh"). Written atomically.
/// @throw std::runtime_error if the file cannot be written.
void writePly(const std::filesystem::path& path, const TriangleMesh& mesh,
              const std::vector<std::string>& comments = {});

/// Writes a Wavefront OBJ (v and f records, 1-based). Written atomically.
/// @throw std::runtime_error if the file cannot be written.
void writeObj(const std::filesystem::path& path, const TriangleMesh& mesh);

/// Reads a triangle mesh from PLY (ascii or binary, either endianness), OBJ or OFF, chosen by
/// extension (.ply/.obj/.off). Reads the `steiner` and `driven` vertex properties when present.
/// @throw terramesh::InputError naming the file and the offending line or element.
TriangleMesh readMesh(const std::filesystem::path& path);

/// A face's `view_sides` as a PLY file holds it (SurfaceFace::view_sides, view_side bits: 0-3).
/// @throw terramesh::InputError naming `file` and `where` if `value` is not one.
std::uint8_t checkedViewSides(double value, const std::string& file, const std::string& where);

/// A face's rays behind it and their cell's depth as a PLY file holds them
/// (SurfaceFace::back_crossings, a count; SurfaceFace::back_depth, a finite distance >= 0), appended
/// to `mesh.face_back_crossings` and `mesh.face_back_depth`.
/// @throw terramesh::InputError naming `file` and `where` if they are not.
void appendCheckedBehind(double crossings, double depth, const std::string& file, const std::string& where,
                         TriangleMesh& mesh);

}  // namespace terramesh::mesher
