// Free boxes (Keyframe::free_boxes, the robot's body volume): the tetrahedron-box test against
// sampled points, a box carving the cells no ray crosses and giving them back when its keyframe
// goes, and checkpoints keeping the boxes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <sstream>
#include <string>

#include "free_boxes.h"
#include "mesher/checkpoint.h"
#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"

namespace terramesh::mesher {
namespace {

bool insideBox(const Eigen::Vector3d& p, const Eigen::Vector3d& half) {
  return (p.cwiseAbs() - half).maxCoeff() <= 0;
}

TEST(FreeBoxTest, TheTetrahedronTestAgreesWithSampledPointsAndCornerCases) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-2.0, 2.0), size(0.05, 1.0), weight(0.0, 1.0);
  int met = 0, apart = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d half(size(rng), size(rng), size(rng));
    std::array<Eigen::Vector3d, 4> tet;
    for (Eigen::Vector3d& p : tet) p = Eigen::Vector3d(coord(rng), coord(rng), coord(rng));
    const bool meets = internal::tetrahedronMeetsBox(tet, half);
    (meets ? met : apart)++;
    // A point of the tetrahedron inside the box proves they meet.
    for (int s = 0; s < 400 && !meets; ++s) {
      double w[4] = {weight(rng), weight(rng), weight(rng), weight(rng)};
      const double sum = w[0] + w[1] + w[2] + w[3];
      const Eigen::Vector3d p =
          (w[0] * tet[0] + w[1] * tet[1] + w[2] * tet[2] + w[3] * tet[3]) / sum;
      ASSERT_FALSE(insideBox(p, half))
          << "trial " << trial << ": a point of the tetrahedron lies in the box";
    }
    // A corner of the box inside the tetrahedron proves it too (barycentric coordinates >= 0).
    if (!meets) {
      Eigen::Matrix3d edges;
      for (int i = 0; i < 3; ++i) edges.col(i) = tet[static_cast<std::size_t>(i) + 1] - tet[0];
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d c((corner & 1) ? half.x() : -half.x(),
                                (corner & 2) ? half.y() : -half.y(),
                                (corner & 4) ? half.z() : -half.z());
        const Eigen::Vector3d l = edges.fullPivLu().solve(c - tet[0]);
        ASSERT_FALSE(l.minCoeff() >= 0 && l.sum() <= 1)
            << "trial " << trial << ": a box corner lies in the tetrahedron";
      }
    }
  }
  EXPECT_GT(met, 300);
  EXPECT_GT(apart, 300);
  const Eigen::Vector3d unit(1, 1, 1);
  // A box inside a large tetrahedron, and a tetrahedron inside the box.
  EXPECT_TRUE(internal::tetrahedronMeetsBox(
      {Eigen::Vector3d(-10, -10, -10), {30, -10, -10}, {-10, 30, -10}, {-10, -10, 30}}, unit));
  EXPECT_TRUE(internal::tetrahedronMeetsBox(
      {Eigen::Vector3d(0, 0, 0), {0.1, 0, 0}, {0, 0.1, 0}, {0, 0, 0.1}}, unit));
  // Every box axis overlaps, yet the sliver's own plane x + y = 2.2 passes beyond the box's edge
  // x = y = 1 (x + y = 2); a box reaching x = y = 1.2 meets it.
  const std::array<Eigen::Vector3d, 4> sliver = {
      Eigen::Vector3d(2.2, 0.0, -3), {0.0, 2.2, -3}, {2.2, 0.0, 3}, {0.0, 2.2, 3.01}};
  EXPECT_FALSE(internal::tetrahedronMeetsBox(sliver, unit));
  EXPECT_TRUE(internal::tetrahedronMeetsBox(sliver, Eigen::Vector3d(1.2, 1.2, 1)));
  // A free box frees a cell only with the cell's centroid above the box's floor: a cell under the
  // ground that pokes 2 cm into the box stays.
  FreeBox box;
  box.centre_W = Eigen::Vector3d(0, 0, 0.55);
  box.half_extents = Eigen::Vector3d(1, 1, 0.5);  // floor at z = 0.05
  const std::array<Eigen::Vector3d, 4> under = {
      Eigen::Vector3d(-1, -1, 0.07), {1, -1, 0}, {0, 1, 0}, {0, 0, -3}};
  std::array<Eigen::Vector3d, 4> under_B = under;
  for (Eigen::Vector3d& p : under_B) p -= box.centre_W;
  EXPECT_TRUE(internal::tetrahedronMeetsBox(under_B, box.half_extents)) << "it meets the box";
  EXPECT_FALSE(internal::tetrahedronMeetsFreeBox(under, box));
  std::array<Eigen::Vector3d, 4> above = under;
  above[3] = Eigen::Vector3d(0, 0, 1);
  EXPECT_TRUE(internal::tetrahedronMeetsFreeBox(above, box));
}

constexpr double kPostHeight = 0.5;
const Eigen::Vector3d kPost(0.0, 1.0, kPostHeight);
constexpr std::uint64_t kPostId = 900000;
/// A second post with no driven ground around it.
const Eigen::Vector3d kBarePost(0.0, -4.0, kPostHeight);
constexpr std::uint64_t kBarePostId = 900001;
constexpr std::uint64_t kBodyId = 700000;
constexpr std::uint64_t kDrivenId = std::uint64_t{1} << 62;

MesherConfig planeConfig() {
  MesherConfig config = MesherConfig::forMode(MesherMode::kProposed);
  config.steiner_step_m = 4.0;
  config.driven_ground_up_W = Eigen::Vector3d::UnitZ();
  return config;
}

/// The plane scene with a point `kPostHeight` above the ground that every keyframe sees, and
/// driven-ground samples on the ground around its foot (a 2 m square, 0.5 m apart) that the first
/// keyframe sees: a box frees only cells above driven ground.
std::vector<Keyframe> keyframesWithPost() {
  std::vector<Keyframe> keyframes = test::planeScene(test::SceneOptions{}).keyframes;
  for (Keyframe& keyframe : keyframes) {
    keyframe.observations.push_back({PointId{kPostId}, kPost, PointKind::kSlam});
    keyframe.observations.push_back({PointId{kBarePostId}, kBarePost, PointKind::kSlam});
  }
  std::uint64_t id = kDrivenId;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      const Eigen::Vector3d at(kPost.x() + 0.5 * i + 0.01 * j, kPost.y() + 0.5 * j, 0.0);
      keyframes.front().observations.push_back({PointId{id++}, at, PointKind::kDrivenGround});
    }
  }
  return keyframes;
}

/// A keyframe with no observations that vouches for the free space around both posts, from
/// `floor_m` above the ground to 1.2 m.
Keyframe bodyAroundPost(double floor_m = 0.05) {
  Keyframe body;
  body.id = KeyframeId{kBodyId};
  body.position_W_C = Eigen::Vector3d(kPost.x(), kPost.y(), 1.0);
  FreeBox box;
  box.centre_W = Eigen::Vector3d(kPost.x(), kPost.y(), 0.5 * (1.2 + floor_m));
  box.rotation_W_B = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  box.half_extents = Eigen::Vector3d(1.0, 0.8, 0.5 * (1.2 - floor_m));
  FreeBox bare = box;
  bare.centre_W += kBarePost - kPost;
  body.free_boxes = {box, bare};
  return body;
}

bool onSurface(const Mesher& mesher, std::uint64_t point) {
  for (const SurfaceFace& face : mesher.surfaceFaces()) {
    for (const VertexKey& key : face.vertices) {
      if (!key.steiner && key.value == VertexKey::point(PointId{point}).value) return true;
    }
  }
  return false;
}

void expectHealthy(const Mesher& mesher, const std::string& where) {
  const InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << where << ": " << report.summary();
  EXPECT_TRUE(analyzeTopology(mesher.extractMesh()).isClosedManifold()) << where;
}

TEST(FreeBoxTest, ABoxCarvesWhatNoRayCrossesAndItsKeyframesRemovalGivesItBack) {
  Mesher mesher(planeConfig());
  for (const Keyframe& keyframe : keyframesWithPost()) mesher.integrateKeyframe(keyframe);
  expectHealthy(mesher, "the plane with its post");
  ASSERT_TRUE(onSurface(mesher, kPostId))
      << "rays end at the post and none passes under it: it stands on the surface";

  ASSERT_TRUE(onSurface(mesher, kBarePostId));

  mesher.integrateKeyframe(bodyAroundPost());
  expectHealthy(mesher, "with the body's box");
  EXPECT_FALSE(onSurface(mesher, kPostId)) << "every cell around the post meets the box";
  EXPECT_TRUE(onSurface(mesher, kBarePostId)) << "a box frees only cells above driven ground";

  mesher.removeKeyframe(KeyframeId{kBodyId});
  expectHealthy(mesher, "the body's keyframe removed");
  EXPECT_TRUE(onSurface(mesher, kPostId))
      << "without the box the cells under the post are inside again";
}

TEST(FreeBoxTest, ABoxAbovePostLeavesItAndResendingTheKeyframeReplacesItsBoxes) {
  Mesher mesher(planeConfig());
  for (const Keyframe& keyframe : keyframesWithPost()) mesher.integrateKeyframe(keyframe);
  mesher.integrateKeyframe(bodyAroundPost(kPostHeight + 0.3));
  expectHealthy(mesher, "a box above the post");
  EXPECT_TRUE(onSurface(mesher, kPostId)) << "no cell incident to the post reaches 0.8 m";
  mesher.integrateKeyframe(bodyAroundPost());
  expectHealthy(mesher, "the box re-sent lower");
  EXPECT_FALSE(onSurface(mesher, kPostId));
}

TEST(FreeBoxTest, ACheckpointKeepsTheBoxes) {
  const std::vector<Keyframe> keyframes = keyframesWithPost();
  Mesher mesher(planeConfig());
  for (std::size_t k = 0; k < 16; ++k) mesher.integrateKeyframe(keyframes[k]);
  mesher.integrateKeyframe(bodyAroundPost());
  std::stringstream bytes;
  saveCheckpoint(mesher, bytes, "");
  LoadedCheckpoint loaded = loadCheckpoint(bytes, "memory");
  Mesher& resumed = loaded.mesher;
  EXPECT_TRUE(resumed.checkInvariants().ok());
  // The rest of the scene re-observes the post: each update shrinks and regrows the cells around
  // it, which stay carved only if the resumed mesher still knows the box.
  for (std::size_t k = 16; k < keyframes.size(); ++k) {
    mesher.integrateKeyframe(keyframes[k]);
    resumed.integrateKeyframe(keyframes[k]);
  }
  EXPECT_FALSE(onSurface(resumed, kPostId));
  EXPECT_EQ(resumed.extractMesh().faces, mesher.extractMesh().faces);
  expectHealthy(resumed, "resumed");
}

}  // namespace
}  // namespace terramesh::mesher
