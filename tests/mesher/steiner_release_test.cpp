// Mesher::releaseFarSteiner (the online freeze): the lattice far from the keyframes kept leaves the
// triangulation without changing the surface or the invariants, and comes back where data does.
#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <stdexcept>

#include "mesher/checkpoint.h"
#include "mesher/mesher.h"

namespace terramesh::mesher {
namespace {

constexpr double kDriveM = 160.0;
constexpr double kSpacingM = 2.0;
constexpr double kRangeM = 15.0;

/// Points on the ground z = 0 of a road x in [0, 160 + range], |y| <= 6, about one per m^2.
std::vector<Eigen::Vector3d> groundPoints() {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> x(0.0, kDriveM + kRangeM), y(-6.0, 6.0),
      noise(-0.02, 0.02);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < static_cast<int>((kDriveM + kRangeM) * 12); ++i)
    points.emplace_back(x(random), y(random), noise(random));
  return points;
}

/// Keyframe `k` at x = 2k, 1.6 m up, seeing the points 1-15 m ahead of it.
Keyframe keyframeAt(std::uint64_t k, const std::vector<Eigen::Vector3d>& points) {
  Keyframe keyframe;
  keyframe.id = KeyframeId{k};
  keyframe.position_W_C = Eigen::Vector3d(kSpacingM * static_cast<double>(k), 0.0, 1.6);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double ahead = points[i].x() - keyframe.position_W_C.x();
    if (ahead > 1.0 && ahead < kRangeM) keyframe.observations.push_back({PointId{i}, points[i]});
  }
  return keyframe;
}

MesherConfig smallLattice() {
  MesherConfig config = MesherConfig::forMode(MesherMode::kProposed);
  config.steiner_step_m = 4.0;
  config.max_camera_distance_m = kRangeM;
  return config;
}

class SteinerRelease : public ::testing::Test {
 protected:
  void SetUp() override {
    points_ = groundPoints();
    for (std::uint64_t k = 0; k * kSpacingM <= kDriveM; ++k)
      mesher_.integrateKeyframe(keyframeAt(k, points_));
    // The first 60 m are left behind: their keyframes go, as the freeze retires them.
    for (std::uint64_t k = 0; k * kSpacingM < 60.0; ++k) mesher_.removeKeyframe(KeyframeId{k});
    for (std::uint64_t k = 0; k * kSpacingM <= kDriveM; ++k) {
      if (k * kSpacingM >= 60.0) keep_.push_back(keyframeAt(k, {}).position_W_C);
    }
  }

  std::vector<Eigen::Vector3d> points_;
  std::vector<Eigen::Vector3d> keep_;
  Mesher mesher_{smallLattice()};
};

TEST_F(SteinerRelease, FarLatticeGoesAndTheSurfaceStays) {
  ASSERT_TRUE(mesher_.checkInvariants().ok());
  const TriangleMesh before = mesher_.extractMesh();
  const MapSize size_before = mesher_.size();
  const std::uint64_t revision = mesher_.revision();
  const UpdateStats stats = mesher_.releaseFarSteiner(keep_, kRangeM);
  EXPECT_GT(stats.steiner_released, 20u);
  EXPECT_EQ(mesher_.size().steiner_vertices, size_before.steiner_vertices - stats.steiner_released);
  EXPECT_LT(mesher_.size().cells, size_before.cells);
  const TriangleMesh after = mesher_.extractMesh();
  EXPECT_EQ(after.vertices, before.vertices);
  EXPECT_EQ(after.faces, before.faces);
  EXPECT_EQ(mesher_.revision(), revision);
  const InvariantReport report = mesher_.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
  // Again with the same keyframes: little more goes (a hull node whose neighbours were all in one
  // plane may not be any more), and the surface still stays.
  EXPECT_LT(mesher_.releaseFarSteiner(keep_, kRangeM).steiner_released, stats.steiner_released / 10);
  EXPECT_EQ(mesher_.extractMesh().faces, before.faces);
}

TEST_F(SteinerRelease, LatticeComesBackWhereDataComesBack) {
  mesher_.releaseFarSteiner(keep_, kRangeM);
  // A drive back over the start: its keyframes see the points there again.
  std::size_t inserted = 0;
  for (std::uint64_t k = 0; k < 10; ++k) {
    const UpdateStats stats = mesher_.integrateKeyframe(keyframeAt(k, points_));
    inserted += stats.new_points;
    EXPECT_EQ(stats.dropped_points, 0u) << "keyframe " << k;
    if (k == 0) EXPECT_GT(stats.steiner_points, 0u);
  }
  EXPECT_GT(inserted, 100u);
  const InvariantReport report = mesher_.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
}

TEST_F(SteinerRelease, RefusesABadReach) {
  EXPECT_THROW(mesher_.releaseFarSteiner(keep_, -1.0), std::invalid_argument);
}

TEST_F(SteinerRelease, ACheckpointKeepsTheSparseLattice) {
  mesher_.releaseFarSteiner(keep_, kRangeM);
  std::stringstream saved;
  saveCheckpoint(mesher_, saved);
  Mesher resumed = loadCheckpoint(saved, "sparse.tmckpt").mesher;
  EXPECT_EQ(resumed.size().steiner_vertices, mesher_.size().steiner_vertices);
  // The drive back over the start: the lattice comes back the same way in both (the resumed one
  // knows which nodes it let go), and the meshes stay equal.
  for (std::uint64_t k = 0; k < 10; ++k) {
    const UpdateStats a = mesher_.integrateKeyframe(keyframeAt(k, points_));
    const UpdateStats b = resumed.integrateKeyframe(keyframeAt(k, points_));
    EXPECT_EQ(a.steiner_points, b.steiner_points) << "keyframe " << k;
  }
  EXPECT_EQ(resumed.size().steiner_vertices, mesher_.size().steiner_vertices);
  const TriangleMesh a = mesher_.extractMesh(), b = resumed.extractMesh();
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.faces, b.faces);
  const InvariantReport report = resumed.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
}

TEST(RemoveKeyframes, OneUpdateKeepsThePointsOneRemovalAtATimeKeeps) {
  const std::vector<Eigen::Vector3d> points = groundPoints();
  Mesher one_by_one(smallLattice()), batch(smallLattice());
  for (std::uint64_t k = 0; k < 40; ++k) {
    one_by_one.integrateKeyframe(keyframeAt(k, points));
    batch.integrateKeyframe(keyframeAt(k, points));
  }
  std::vector<KeyframeId> first;
  for (std::uint64_t k = 0; k < 20; ++k) {
    one_by_one.removeKeyframe(KeyframeId{k});
    first.push_back(KeyframeId{k});
  }
  first.push_back(KeyframeId{999});  // unknown: ignored
  const UpdateStats stats = batch.removeKeyframes(first);
  EXPECT_GT(stats.removed_points, 100u);
  EXPECT_EQ(batch.size().inserted_points, one_by_one.size().inserted_points);
  EXPECT_EQ(batch.size().rays, one_by_one.size().rays);
  const InvariantReport report = batch.checkInvariants();
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(batch.removeKeyframes(first).removed_points, 0u);  // gone already
}

TEST(SteinerReleaseBaselines, FixedGridIsKept) {
  MesherConfig config = MesherConfig::forMode(MesherMode::kRomanoni15);
  config.steiner_step_m = 4.0;
  config.fixed_grid_bounds_W =
      AxisAlignedBox{Eigen::Vector3d(-20, -20, -20), Eigen::Vector3d(60, 20, 20)};
  Mesher mesher(config);
  const std::vector<Eigen::Vector3d> points = groundPoints();
  for (std::uint64_t k = 0; k < 10; ++k) mesher.integrateKeyframe(keyframeAt(k, points));
  EXPECT_EQ(mesher.releaseFarSteiner({Eigen::Vector3d(0, 0, 0)}, 1.0).steiner_released, 0u);
}

}  // namespace
}  // namespace terramesh::mesher
