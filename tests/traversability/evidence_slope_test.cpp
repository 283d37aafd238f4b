// Ramps and slopes from sparse points: a rise of more than a step is a ramp only where measured
// points confirm its plane, and a slope near the limit is free only where they confirm it far
// enough.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "evidence_faces.h"
#include "test_support/traversability_scenes.h"
#include "traversability/layer_registry.h"
#include "traversability/traversability_map.h"

namespace terramesh::traversability {
namespace {

TEST(EvidenceTest, ARampObservedDenselyStaysFree) {
  // A 15 degree ramp with points every 0.25 m and rays over it: free, measured.
  const RobotProfile profile = smallWheeled();
  const double t = std::tan(15.0 * M_PI / 180.0);
  const mesher::TriangleMesh ramp = test::heightFieldMesh(-3, 3, -3, 3, 0.25, [t](double x, double) { return t * x; });
  const std::vector<FaceLayers> layers = layersOf(facesOf(ramp, 4), profile);
  std::size_t inner = 0;
  for (std::size_t f = 0; f < ramp.faces.size(); ++f) {
    if (centroid(ramp, f).head<2>().cwiseAbs().maxCoeff() > 2.0) continue;
    ++inner;
    EXPECT_EQ(layers[f].evidence, Evidence::kMeasured);
    EXPECT_EQ(layers[f].face_class, FaceClass::kFree);
  }
  EXPECT_GT(inner, 100u);
}

TEST(EvidenceTest, ASparseRampConfirmedAlongItsSlopeIsFree) {
  // The same 15 degree slope as the slab's interpolated ramp, seen at vertices 1.5 m apart over
  // 9 m: each face rises 0.4 m, more than a step, but the points up and down the slope lie on its
  // plane, so it is a ramp: free away from the ends.
  const RobotProfile profile = smallWheeled();
  const double t = std::tan(15.0 * M_PI / 180.0);
  const mesher::TriangleMesh ramp = test::heightFieldMesh(-6, 6, -6, 6, 1.5, [t](double x, double) {
    return t * std::clamp(x, -4.5, 4.5);
  });
  const std::vector<FaceLayers> layers = layersOf(facesOf(ramp, 4), profile);
  std::size_t inner = 0;
  for (std::size_t f = 0; f < ramp.faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(ramp, f);
    if (std::abs(c.x()) > 3.0 || std::abs(c.y()) > 4.0) continue;
    ++inner;
    EXPECT_EQ(layers[f].face_class, FaceClass::kFree) << "at (" << c.x() << ", " << c.y() << ")";
  }
  EXPECT_GT(inner, 10u);
}

TEST(EvidenceTest, ASlopeJustUnderTheLimitIsFreeOnlyWhereMeasuredPointsConfirmItFarEnough) {
  // 18.5 degrees, under small_wheeled's 20 degree limit. With 3 cm of point noise, a plane confirmed
  // over 0.75 m (points 0.25 m apart: a face and the neighbour vertices on its plane) may be 22.5
  // degrees steep: uncertain, never lethal (what was measured is under the limit). Confirmed over
  // several metres (points 1.5 m apart on one plane), the worst case stays under 20 degrees: free.
  const RobotProfile profile = smallWheeled();
  const double t = std::tan(18.5 * M_PI / 180.0);
  const auto ramp_at = [t](double x, double) { return t * std::clamp(x, -4.5, 4.5); };
  const mesher::TriangleMesh dense = test::heightFieldMesh(-3, 3, -3, 3, 0.25, ramp_at);
  const std::vector<FaceLayers> near = layersOf(facesOf(dense, 4), profile);
  std::size_t inner = 0;
  for (std::size_t f = 0; f < dense.faces.size(); ++f) {
    if (centroid(dense, f).head<2>().cwiseAbs().maxCoeff() > 2.0) continue;
    ++inner;
    EXPECT_NEAR(near[f].slope_deg, 18.5, 0.01);
    EXPECT_EQ(near[f].evidence, Evidence::kMeasured);
    EXPECT_EQ(near[f].face_class, FaceClass::kUncertain) << "face " << f;
    EXPECT_TRUE(near[f].reasons & reason::kSlopeMayExceed) << "face " << f << ": reasons " << near[f].reasons;
  }
  EXPECT_GT(inner, 100u);
  const mesher::TriangleMesh sparse = test::heightFieldMesh(-6, 6, -6, 6, 1.5, ramp_at);
  const std::vector<FaceLayers> far = layersOf(facesOf(sparse, 4), profile);
  inner = 0;
  for (std::size_t f = 0; f < sparse.faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(sparse, f);
    if (std::abs(c.x()) > 3.0 || std::abs(c.y()) > 4.0) continue;
    ++inner;
    EXPECT_EQ(far[f].face_class, FaceClass::kFree) << "at (" << c.x() << ", " << c.y() << ")";
    EXPECT_EQ(far[f].reasons, 0) << "a free face has no reason not to be";
  }
  EXPECT_GT(inner, 10u);
  // A noisier sensor (10 cm) cannot vouch for it even over metres.
  RobotProfile noisy = profile;
  noisy.evidence.point_noise_m = 0.1;
  const std::vector<FaceLayers> doubted = layersOf(facesOf(sparse, 4), noisy);
  for (std::size_t f = 0; f < sparse.faces.size(); ++f) {
    const Eigen::Vector3d c = centroid(sparse, f);
    if (std::abs(c.x()) > 3.0 || std::abs(c.y()) > 4.0) continue;
    EXPECT_EQ(doubted[f].face_class, FaceClass::kUncertain) << "at (" << c.x() << ", " << c.y() << ")";
  }
}

TEST(EvidenceTest, AFaceFromTheRoadUpToSomethingBesideItIsNoRamp) {
  // Level road for x < 0 with a row of points 0.25 m before x = 0, and faces from the road at x = 0
  // up to points 1 m higher at x = 4 (14 degrees, under the 20 degree limit): the mesh spanning
  // from the road to something standing beside it. Nothing confirms that rise: the points just
  // past its foot lie on its plane only as closely as on the level road (0.06 m apart there,
  // within the 0.07 m tolerance), so they say nothing. A possible step, uncertain, never a ramp.
  const RobotProfile profile = smallWheeled();
  const std::vector<double> xs = {-3, -0.25, 0, 4};
  mesher::TriangleMesh mesh;
  const auto index = [&](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(i * 13 + j); };
  for (double x : xs) {
    for (int j = 0; j <= 12; ++j) mesh.vertices.emplace_back(x, -3 + 0.5 * j, x > 0 ? 0.25 * x : 0.0);
  }
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    for (std::size_t j = 0; j < 12; ++j) {
      mesh.faces.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      mesh.faces.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  }
  const std::vector<FaceLayers> layers = layersOf(facesOf(mesh, 4), profile);
  std::size_t spans = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (centroid(mesh, f).x() < 0) continue;
    ++spans;
    EXPECT_EQ(layers[f].face_class, FaceClass::kUncertain) << "face " << f;
    EXPECT_TRUE(layers[f].reasons & reason::kPossibleStep) << "face " << f << ": " << layers[f].reasons;
    EXPECT_GE(layers[f].height_uncertainty_m, 1.0f);
  }
  EXPECT_EQ(spans, 24u);
}

}  // namespace
}  // namespace terramesh::traversability
