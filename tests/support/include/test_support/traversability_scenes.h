#pragma once
// Scenes with known traversability (a ramp, a step, a low ceiling) as SLAM streams for the mesher,
// and small hand-made height-field meshes where the tests need exact geometry. All z-up, metres.

#include <Eigen/Core>
#include <functional>

#include "mesher/triangle_mesh.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::test {

/// Ground z = tan(slope) * x over [-12, 12] x [-8, 8]; cameras 2.5 m above it move along +x
/// (y in [-1, 1]) looking ahead and 35 degrees down.
AnalyticScene rampScene(double slope_deg, const SceneOptions& options);

/// Ground z = 0 for y < 0 and z = height_m for y >= 0 (a curb or a ledge along the x axis) over
/// [-12, 12] x [-8, 8], with points on the vertical riser; cameras 2.5 m above the lower level at
/// y = -3 move along +x looking across the step and down.
AnalyticScene stepScene(double height_m, const SceneOptions& options);

/// Floor z = 0 over [-12, 16] x [-8, 8] and a slab [0, 6] x [-3, 3] x [ceiling_m, ceiling_m + 0.3]
/// above it; cameras at half the ceiling height drive along the x axis under the slab, looking
/// ahead and slightly down. Points on the floor, the slab's underside and its faces.
AnalyticScene lowCeilingScene(double ceiling_m, const SceneOptions& options);

/// A height field z = height(x, y) on a regular grid over [x0, x1] x [y0, y1] with the given
/// spacing, two triangles per cell, wound counter-clockwise seen from above (normals up). No
/// Steiner flags, no vertex keys.
mesher::TriangleMesh heightFieldMesh(double x0, double x1, double y0, double y1, double spacing_m,
                                     const std::function<double(double, double)>& height);

/// Appends `b` to `a` (vertex indices of b shifted).
void appendMesh(mesher::TriangleMesh& a, const mesher::TriangleMesh& b);

/// An axis-aligned horizontal rectangle [x0, x1] x [y0, y1] at height z as two triangles, facing
/// down (a ceiling seen from below) if `facing_down`, else up.
mesher::TriangleMesh horizontalQuad(double x0, double x1, double y0, double y1, double z, bool facing_down);

/// A vertical rectangle from (x0, y0) to (x1, y1) between heights z0 and z1 as two triangles,
/// facing to the right of the direction (x0, y0) -> (x1, y1) seen from above. A thin wall is this
/// plus the same with the ends swapped (thinWall).
mesher::TriangleMesh verticalQuad(double x0, double y0, double x1, double y1, double z0, double z1);

/// A two-sided vertical wall of no thickness (both faces of verticalQuad), as walls, posts and
/// fences come out of a mesher that sees both sides.
mesher::TriangleMesh thinWall(double x0, double y0, double x1, double y1, double z0, double z1);

}  // namespace terramesh::test
