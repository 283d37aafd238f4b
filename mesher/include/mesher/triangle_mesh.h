#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "mesher/surface_delta.h"

namespace terramesh::mesher {

/// An indexed triangle mesh. Faces are wound counter-clockwise seen from free space, so face
/// normals point out of the matter, towards the cameras.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> faces;
  /// One flag per vertex: 1 for a Steiner (grid) vertex, 0 for a measured SLAM point.
  /// Either empty (unknown) or the same size as `vertices`.
  std::vector<std::uint8_t> is_steiner;
  /// One value per vertex, its mesher::PointKind: 1 for a driven-ground sample (kDrivenGround:
  /// ground under the robot's own trajectory), 2 for the underside under one (kDrivenUnderside), 0
  /// otherwise. Either empty (unknown or none, e.g. a mesh read from a file without the `driven`
  /// property) or the same size as `vertices`.
  std::vector<std::uint8_t> driven_kind;
  /// Stable identity of each vertex (SLAM point id or Steiner lattice node). Either empty
  /// (unknown, e.g. a mesh read from a file) or the same size as `vertices`.
  std::vector<VertexKey> vertex_keys;
  /// Per face, how it was observed (SurfaceFace::rays and SurfaceFace::front_crossings when the
  /// mesh was extracted). Either empty (unknown, e.g. a mesh from another program) or the same
  /// size as `faces`; the PLY writer and reader keep them (face properties `rays`,
  /// `front_crossings`).
  std::vector<std::uint32_t> face_rays;
  std::vector<std::uint32_t> face_front_crossings;
  /// Per face, SurfaceFace::view_sides (view_side bits). Either empty (unknown) or the same size
  /// as `faces`; the PLY writer and reader keep it (face property `view_sides`).
  std::vector<std::uint8_t> face_view_sides;
  /// Per face, SurfaceFace::back_crossings and SurfaceFace::back_depth (map units). Either both
  /// empty (unknown) or both the same size as `faces`; the PLY writer and reader keep them (face
  /// properties `back_crossings`, `back_depth`).
  std::vector<std::uint32_t> face_back_crossings;
  std::vector<double> face_back_depth;

  std::size_t vertexCount() const { return vertices.size(); }
  std::size_t faceCount() const { return faces.size(); }
};

/// Topology summary of a triangle mesh, computed by `analyzeTopology`.
struct MeshTopology {
  std::size_t vertices = 0;             ///< vertices referenced by at least one face
  std::size_t edges = 0;                ///< undirected edges
  std::size_t faces = 0;
  std::size_t boundary_edges = 0;       ///< edges with exactly one face
  std::size_t non_manifold_edges = 0;   ///< edges with more than two faces
  std::size_t non_manifold_vertices = 0;///< vertices whose faces form more than one fan
  std::size_t orientation_errors = 0;   ///< directed edges used by more than one face
  std::size_t components = 0;           ///< connected components (through shared vertices)
  long euler_characteristic = 0;        ///< V - E + F over the referenced vertices
  /// Sum over closed components of their genus (2 - chi) / 2; open components are skipped.
  long total_genus = 0;

  bool isClosedManifold() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && non_manifold_vertices == 0 &&
           orientation_errors == 0;
  }
};

/// Counts vertices, edges, faces, components, genus and manifold defects. O(F log F).
MeshTopology analyzeTopology(const TriangleMesh& mesh);

/// Returns the open surface made of the faces that touch no Steiner vertex, with unreferenced
/// vertices removed. Requires `mesh.is_steiner` to be filled; `vertex_keys` and `driven_kind` are
/// carried along when they have one entry per vertex.
/// @throw std::invalid_argument if `is_steiner` does not match the vertex count.
TriangleMesh dropSteinerFaces(const TriangleMesh& mesh);

/// The faces whose flag in `keep` is set, in order, with unreferenced vertices removed (vertices
/// numbered by first use); every per-vertex and per-face array of one entry per element is carried
/// along. O(V + F).
/// @throw std::invalid_argument if `keep` does not have one flag per face.
TriangleMesh selectFaces(const TriangleMesh& mesh, const std::vector<std::uint8_t>& keep);

}  // namespace terramesh::mesher
