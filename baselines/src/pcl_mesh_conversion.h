#pragma once
// TriangleMesh <-> pcl::PolygonMesh. Internal: included only by the baselines' own sources.

#include <pcl/PCLPointField.h>
#include <pcl/PolygonMesh.h>

#include <cstdint>
#include <string>

#include "mesher/triangle_mesh.h"

namespace terramesh::baselines {

/// One value of a point field of any numeric type (count 1) at `point` (the point's first byte).
double readFieldValue(const std::uint8_t* point, const pcl::PCLPointField& field);

/// The mesh as a PolygonMesh: cloud fields x y z (FLOAT32: PCL's PLY, OBJ and VTK writers accept
/// nothing else, and reject extra fields such as a Steiner flag); one 3-index polygon per face.
pcl::PolygonMesh toPolygonMesh(const mesher::TriangleMesh& mesh);

/// The PolygonMesh as a TriangleMesh: x y z of any numeric field type, `steiner` when present;
/// polygons with n > 3 corners fanned into n - 2 triangles, polygons with fewer dropped.
/// @throw terramesh::InputError (file `source`) if x, y or z is missing or a polygon indexes a
///        missing vertex.
mesher::TriangleMesh fromPolygonMesh(const pcl::PolygonMesh& polygons, const std::string& source);

}  // namespace terramesh::baselines
