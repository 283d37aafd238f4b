// The edge of the strip the robot drove: a face from two driven samples to a SLAM point beside them
// is driven ground when it is level within a step and its centroid lies within the footprint's half
// width of the drive (LayerComputer::onDrivenEdge); a face on one driven sample, a face rising more
// than a step, and a face whose centroid lies beyond the strip keep the SLAM point's evidence.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <vector>

#include "evidence_faces.h"
#include "test_support/traversability_scenes.h"

namespace terramesh::traversability {
namespace {

constexpr double kStripHalfWidthM = 0.3;

/// Bases on the line y = line_y, facing +x, for the vertices within the strip |y| <= 0.3 (the
/// driven samples); none for the others (SLAM points), as TrajectoryEvidence::baseOf answers.
DrivePoseLookup basesOnLine(const mesher::TriangleMesh& mesh, double line_y) {
  return [&mesh, line_y](mesher::PointId id) -> std::optional<Eigen::Isometry3d> {
    if (id.value >= mesh.vertices.size()) return std::nullopt;
    const Eigen::Vector3d& p = mesh.vertices[id.value];
    if (std::abs(p.y()) > kStripHalfWidthM + 1e-9) return std::nullopt;
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translation() = Eigen::Vector3d(p.x(), line_y, 0);
    return base;
  };
}

struct EdgeCounts {
  std::size_t two_driven_level = 0, two_driven_level_driven = 0;
  std::size_t two_driven_rising = 0, two_driven_rising_driven = 0;
  std::size_t one_driven = 0, one_driven_driven = 0;
};

TEST(DrivenEdgeTest, ALevelFaceFromTheStripToAPointBesideItIsDrivenWhereItsCentroidLiesOnTheStrip) {
  const RobotProfile profile = smallWheeled();  // a 0.34 m disc, 0.18 m step, 20 degrees
  // A floor 0.1 m apart, driven at |y| <= 0.3; beyond, SLAM points: 0.03 m higher for x < 0
  // (level within a step), 0.3 m higher for x > 0 (a rise no drive explains).
  const mesher::TriangleMesh mesh = test::heightFieldMesh(-3, 3, -1, 1, 0.1, [](double x, double y) {
    return std::abs(y) <= kStripHalfWidthM + 1e-9 ? 0.0 : (x < 0 ? 0.03 : 0.3);
  });
  std::vector<mesher::SurfaceFace> faces = facesOf(mesh, 4);
  for (mesher::SurfaceFace& face : faces) {
    face.driven_vertices = 0;
    for (const Eigen::Vector3d& p : face.positions_W) {
      face.driven_vertices += std::abs(p.y()) <= kStripHalfWidthM + 1e-9 ? 1 : 0;
    }
  }
  const auto count = [&](double line_y) {
    const std::map<mesher::FaceKey, FaceLayers> layers = layersByKey(faces, profile, basesOnLine(mesh, line_y));
    EdgeCounts n;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const Eigen::Vector3d c = centroid(mesh, f);
      if (std::abs(c.x()) < 0.2 || std::abs(c.x()) > 2.8) continue;  // away from the ends and x = 0
      const FaceLayers& l = layers.at(faces[f].key);
      const bool driven = l.evidence == Evidence::kDriven;
      if (faces[f].driven_vertices == 3) {
        EXPECT_TRUE(driven) << "a face of the strip at (" << c.x() << ", " << c.y() << ")";
      } else if (faces[f].driven_vertices == 2) {
        std::size_t& total = c.x() < 0 ? n.two_driven_level : n.two_driven_rising;
        std::size_t& hits = c.x() < 0 ? n.two_driven_level_driven : n.two_driven_rising_driven;
        ++total;
        hits += driven ? 1 : 0;
        if (driven) {
          EXPECT_NEAR(l.height_uncertainty_m, profile.evidence.driven_uncertainty_m, 1e-6);
        }
      } else if (faces[f].driven_vertices == 1) {
        ++n.one_driven;
        n.one_driven_driven += driven ? 1 : 0;
      } else {
        EXPECT_FALSE(driven) << "a face of SLAM points at (" << c.x() << ", " << c.y() << ")";
      }
    }
    return n;
  };
  // The drive along y = 0: the level edge faces (centroids 0.33 m off it) are driven.
  const EdgeCounts on_line = count(0.0);
  EXPECT_GE(on_line.two_driven_level, 40u);
  EXPECT_EQ(on_line.two_driven_level_driven, on_line.two_driven_level);
  EXPECT_GE(on_line.two_driven_rising, 40u);
  EXPECT_EQ(on_line.two_driven_rising_driven, 0u);
  EXPECT_GE(on_line.one_driven, 80u);
  EXPECT_EQ(on_line.one_driven_driven, 0u);
  // The same samples put down by a drive along y = -0.2: the edge faces at y > 0 lie 0.53 m off
  // it, beyond the disc's radius, and keep their points' evidence; those at y < 0 (0.13 m off)
  // are driven.
  const EdgeCounts off_line = count(-0.2);
  EXPECT_EQ(off_line.two_driven_level_driven, on_line.two_driven_level / 2);
  EXPECT_EQ(off_line.two_driven_rising_driven, 0u);

  // Incrementally as in a full computation: a stretch of the strip and its edges added last, then
  // removed again.
  const DrivePoseLookup poses = basesOnLine(mesh, 0.0);
  std::vector<mesher::SurfaceFace> rest, stretch;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(mesh, f);
    (c.x() > -2.0 && c.x() < -1.0 && std::abs(c.y()) < 0.6 ? stretch : rest).push_back(faces[f]);
  }
  TraversabilityMap map(profile, MapFrame{});
  map.setDrivePoses(poses);
  map.reset(rest);
  map.apply(deltaOf(stretch, false), {});
  expectLayersMatch(map, layersByKey(faces, profile, poses), "the stretch added");
  map.apply(deltaOf(stretch, true), {});
  expectLayersMatch(map, layersByKey(rest, profile, poses), "the stretch removed");
}

}  // namespace
}  // namespace terramesh::traversability
