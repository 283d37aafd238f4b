#pragma once
// Hand-made faces as the mesher reports them, and their layers, for the evidence tests.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "mesher/surface_delta.h"
#include "mesher/triangle_mesh.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {

inline const std::filesystem::path kRobots =
    std::filesystem::path(TERRAMESH_SOURCE_DIR) / "traversability" / "robots";

inline RobotProfile smallWheeled() { return loadRobotProfile(kRobots / "small_wheeled.yaml"); }

/// The faces of `mesh` as the mesher reports them: `rays` observations each, `crossings` of them
/// through the free space in front (0: nobody observed the span), `driven` driven-ground vertices.
/// Faces whose index satisfies `unobserved` get no crossings.
inline std::vector<mesher::SurfaceFace> facesOf(const mesher::TriangleMesh& mesh, std::uint32_t crossings,
                                                const std::function<bool(std::size_t)>& unobserved = {},
                                                std::uint8_t driven = 0) {
  std::vector<mesher::SurfaceFace> faces;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    mesher::SurfaceFace face;
    bool steiner = false;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t v = mesh.faces[f][i];
      steiner = steiner || (!mesh.is_steiner.empty() && mesh.is_steiner[v] != 0);
      face.vertices[i] = mesher::VertexKey{v, false};
      face.positions_W[i] = mesh.vertices[v];
    }
    face.key = mesher::FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    face.touches_steiner = steiner;
    face.rays = steiner ? 0 : 10;
    face.front_crossings = steiner || (unobserved && unobserved(f)) ? 0 : crossings;
    face.driven_vertices = driven;
    faces.push_back(face);
  }
  return faces;
}

/// The layers of a map's faces by key.
inline std::map<mesher::FaceKey, FaceLayers> layersByKey(const TraversabilityMap& map) {
  const LayeredMesh snapshot = map.snapshot();
  std::map<mesher::FaceKey, FaceLayers> by_key;
  for (std::size_t f = 0; f < snapshot.layers.size(); ++f) by_key.emplace(snapshot.face_keys[f], snapshot.layers[f]);
  return by_key;
}

/// The layers of `faces` by key, with the drive's poses if given.
inline std::map<mesher::FaceKey, FaceLayers> layersByKey(const std::vector<mesher::SurfaceFace>& faces,
                                                         const RobotProfile& profile,
                                                         const DrivePoseLookup& poses = {}) {
  TraversabilityMap map(profile, MapFrame{});
  if (poses) map.setDrivePoses(poses);
  map.reset(faces);
  return layersByKey(map);
}

/// The layers of `faces` in the order given (the map's snapshot sorts by key).
inline std::vector<FaceLayers> layersOf(const std::vector<mesher::SurfaceFace>& faces, const RobotProfile& profile) {
  const std::map<mesher::FaceKey, FaceLayers> by_key = layersByKey(faces, profile);
  std::vector<FaceLayers> out;
  for (const mesher::SurfaceFace& face : faces) out.push_back(by_key.at(face.key));
  return out;
}

/// A drive along y = 0: the first `floor_faces` faces are driven ground where all their vertices
/// lie within `half_width` of that line.
inline void driveAlongX(std::vector<mesher::SurfaceFace>& faces, std::size_t floor_faces, double half_width) {
  for (std::size_t f = 0; f < floor_faces; ++f) {
    bool on_strip = true;
    for (const auto& p : faces[f].positions_W) on_strip = on_strip && std::abs(p.y()) <= half_width + 1e-9;
    faces[f].driven_vertices = on_strip ? 3 : 0;
  }
}

/// For a drive along y = 0: the robot's base where each vertex of `mesh` lies, on that line
/// beside it, facing +x (`mesh` must outlive the lookup).
inline DrivePoseLookup basesAlongX(const mesher::TriangleMesh& mesh) {
  return [&mesh](mesher::PointId id) -> std::optional<Eigen::Isometry3d> {
    if (id.value >= mesh.vertices.size()) return std::nullopt;
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translation() = Eigen::Vector3d(mesh.vertices[id.value].x(), 0, 0);
    return base;
  };
}

/// The centroid of face f.
inline Eigen::Vector3d centroid(const mesher::TriangleMesh& mesh, std::size_t f) {
  const auto& t = mesh.faces[f];
  return (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
}

/// The classes of the floor faces (the first `floor_faces` of `mesh`) whose centroid lies within
/// 2.5 cm of (x, y).
inline std::vector<FaceClass> floorClassesAt(const mesher::TriangleMesh& mesh, std::size_t floor_faces,
                                             const std::vector<FaceLayers>& layers, double x, double y) {
  std::vector<FaceClass> out;
  for (std::size_t f = 0; f < floor_faces; ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    if (std::abs(c.x() - x) < 0.025 && std::abs(c.y() - y) < 0.025) out.push_back(layers[f].face_class);
  }
  return out;
}

/// A hand-made delta that adds `faces`, or removes them.
inline mesher::SurfaceDelta deltaOf(const std::vector<mesher::SurfaceFace>& faces, bool remove) {
  mesher::SurfaceDelta delta{0, 0, true, {}, {}, {}};
  for (const mesher::SurfaceFace& face : faces) {
    if (remove) {
      delta.removed.push_back(face.key);
    } else {
      delta.added.push_back(face);
    }
  }
  return delta;
}

/// Expects the layers `map` keeps current to equal a full computation's (`full`, by key): evidence,
/// class, contact and reasons.
inline void expectLayersMatch(const TraversabilityMap& map, const std::map<mesher::FaceKey, FaceLayers>& full,
                              const char* what) {
  const std::map<mesher::FaceKey, FaceLayers> incremental = layersByKey(map);
  ASSERT_EQ(incremental.size(), full.size()) << what;
  for (const auto& [key, want] : full) {
    const FaceLayers& got = incremental.at(key);
    EXPECT_EQ(got.evidence, want.evidence) << what;
    EXPECT_EQ(got.face_class, want.face_class) << what;
    EXPECT_EQ(got.contact, want.contact) << what;
    EXPECT_EQ(got.reasons, want.reasons) << what;
  }
}

}  // namespace terramesh::traversability
