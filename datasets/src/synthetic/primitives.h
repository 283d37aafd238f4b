#pragma once
// Closed and open solids from which the scenes are assembled. Every face is wound to face away
// from the solid (towards free space).

#include <Eigen/Geometry>

#include "mesh_builder.h"
#include "rng.h"

namespace terramesh::datasets::synthetic {

/// A frame at `origin_W` with x along `heading_W` (made horizontal), z along `up_W`.
Eigen::Isometry3d uprightFrame(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& heading_W,
                               const Eigen::Vector3d& up_W);

/// A rectangle centred at `centre` spanning +-`half_u` and +-`half_v`; it faces u x v.
void addRectangle(LabeledMeshBuilder& builder, const Eigen::Vector3d& centre,
                  const Eigen::Vector3d& half_u, const Eigen::Vector3d& half_v, SurfaceLabel label);

/// A box standing on the origin of `T_W_B`: [-sx/2, sx/2] x [-sy/2, sy/2] x [0, sz] in B, with
/// four sides and a top, no bottom.
void addBox(LabeledMeshBuilder& builder, const Eigen::Isometry3d& T_W_B, const Eigen::Vector3d& size,
            SurfaceLabel sides, SurfaceLabel top);

/// An upright cylinder (sides and top cap) of `segments` facets standing on `base_W`.
void addCylinder(LabeledMeshBuilder& builder, const Eigen::Vector3d& base_W, double radius_m,
                 double height_m, int segments, SurfaceLabel label);

/// A closed lumpy ball: a twice-subdivided icosahedron whose radius varies smoothly by up to
/// `roughness` (relative) in random directions. For rocks and tree crowns.
void addBlob(LabeledMeshBuilder& builder, const Eigen::Vector3d& centre_W, double radius_m,
             double roughness, Rng& rng, SurfaceLabel label);

/// A wedge on the origin of `T_W_B`: footprint x in [0, length], y in [-width/2, width/2]; top
/// rising from height 0 at x = 0 to `height_m` at x = length (label `top`); its sides and high
/// end reach `skirt_m` below the base (label `sides`) so it sits on uneven ground.
void addWedge(LabeledMeshBuilder& builder, const Eigen::Isometry3d& T_W_B, double length_m,
              double width_m, double height_m, double skirt_m, SurfaceLabel top, SurfaceLabel sides);

/// A parked car on the origin of `T_W_B` (x forward, z up): wheels, body and cabin boxes.
void addCar(LabeledMeshBuilder& builder, const Eigen::Isometry3d& T_W_B);

/// Footprint of addCar along x and y.
inline constexpr double kCarLengthM = 4.3;
inline constexpr double kCarWidthM = 1.8;

}  // namespace terramesh::datasets::synthetic
