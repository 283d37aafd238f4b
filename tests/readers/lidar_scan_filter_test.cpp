#include "datasets/lidar_scan_filter.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "common/grid_key.h"

namespace terramesh::test {
namespace {

using datasets::LidarScanFilter;
using datasets::LidarScanOptions;

/// A scan from a sensor at `centre`: one observation per position, ids frame << 32 | index.
mesher::Keyframe scanOf(std::uint64_t frame, const Eigen::Vector3d& centre,
                        const std::vector<Eigen::Vector3d>& positions) {
  mesher::Keyframe scan;
  scan.id.value = frame;
  scan.position_W_C = centre;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    scan.observations.push_back({{(frame << 32) | i}, positions[i]});
  }
  return scan;
}

LidarScanOptions voxels(double size_m, std::uint32_t max_views = 0) {
  LidarScanOptions options = LidarScanOptions::everyReturn();
  options.voxel_size_m = size_m;
  options.max_views_per_point = max_views;
  return options;
}

std::uint64_t voxelId(const Eigen::Vector3d& p, double size_m) {
  const geometry::CellKey3 cell = geometry::cellOf(p, size_m);
  return geometry::packCell3(cell.i, cell.j, cell.k);
}

TEST(LidarScanFilter, KeepsTheReturnNearestEachVoxelCentre) {
  // Oracle: per voxel, the return nearest its centre, found by brute force over every return.
  std::mt19937_64 generator(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  std::vector<Eigen::Vector3d> positions(3000);
  for (Eigen::Vector3d& p : positions)
    p = {coordinate(generator), coordinate(generator), coordinate(generator)};
  const double size_m = 0.5;
  std::map<std::uint64_t, std::size_t> nearest;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const geometry::CellKey3 c = geometry::cellOf(positions[i], size_m);
    const Eigen::Vector3d centre =
        (Eigen::Vector3d(c.i, c.j, c.k) + Eigen::Vector3d::Constant(0.5)) * size_m;
    const auto [slot, inserted] = nearest.try_emplace(voxelId(positions[i], size_m), i);
    if (!inserted && (positions[i] - centre).norm() < (positions[slot->second] - centre).norm())
      slot->second = i;
  }

  LidarScanFilter filter(voxels(size_m));
  mesher::Keyframe scan = scanOf(1, Eigen::Vector3d::Zero(), positions);
  filter.filter(scan);
  ASSERT_EQ(scan.observations.size(), nearest.size());
  std::set<std::size_t> kept_indices;
  std::size_t previous_index = 0;
  for (const mesher::PointObservation& observation : scan.observations) {
    const std::uint64_t id = observation.point.value;
    ASSERT_EQ(id, voxelId(observation.position_W, size_m));
    const std::size_t index = nearest.at(id);
    EXPECT_EQ(observation.position_W, positions[index]);  // a return, exactly, not a mean
    EXPECT_TRUE(kept_indices.empty() || index > previous_index)
        << "kept in the order of the returns";
    kept_indices.insert(index);
    previous_index = index;
  }
  EXPECT_EQ(filter.voxels(), nearest.size());
  EXPECT_EQ(filter.counts().same_voxel, positions.size() - nearest.size());
  EXPECT_EQ(filter.counts().new_points, nearest.size());
}

TEST(LidarScanFilter, AReturnInAnOccupiedVoxelIsAnotherViewOfItsPoint) {
  LidarScanFilter filter(voxels(1.0));
  const Eigen::Vector3d wall(5.2, 0.3, 1.4);
  mesher::Keyframe first = scanOf(1, Eigen::Vector3d::Zero(), {wall});
  filter.filter(first);
  ASSERT_EQ(first.observations.size(), 1u);
  const mesher::PointId wall_id = first.observations[0].point;

  // The next scan sees the wall 0.3 m away from the first return, inside the same voxel, and a
  // return in a voxel no scan has seen.
  mesher::Keyframe second =
      scanOf(2, Eigen::Vector3d(1, 0, 0),
             {Eigen::Vector3d(5.5, 0.1, 1.2), Eigen::Vector3d(5.5, 1.5, 1.2)});
  filter.filter(second);
  ASSERT_EQ(second.observations.size(), 2u);
  EXPECT_EQ(second.observations[0].point, wall_id);
  EXPECT_EQ(second.observations[0].position_W, wall);  // the point stays where it was first seen
  EXPECT_NE(second.observations[1].point, wall_id);
  EXPECT_EQ(second.observations[1].position_W, Eigen::Vector3d(5.5, 1.5, 1.2));
  EXPECT_EQ(filter.counts().new_points, 2u);
  EXPECT_EQ(filter.counts().merged_views, 1u);
  EXPECT_EQ(filter.voxels(), 2u);
}

TEST(LidarScanFilter, ViewCapDropsLaterReturnsOfAWellSeenVoxel) {
  LidarScanFilter filter(voxels(1.0, 2));
  std::vector<std::size_t> kept;
  for (std::uint64_t frame = 0; frame < 4; ++frame) {
    mesher::Keyframe scan =
        scanOf(frame, Eigen::Vector3d(frame, 0, 0), {Eigen::Vector3d(10.5, 0.5, 0.5)});
    filter.filter(scan);
    kept.push_back(scan.observations.size());
  }
  EXPECT_EQ(kept, (std::vector<std::size_t>{1, 1, 0, 0}));
  EXPECT_EQ(filter.counts().over_view_cap, 2u);
}

TEST(LidarScanFilter, RangeLimitsFromTheSensor) {
  LidarScanOptions options = LidarScanOptions::everyReturn();
  options.min_range_m = 1.0;
  options.max_range_m = 10.0;
  LidarScanFilter filter(options);
  const Eigen::Vector3d sensor(100, 0, 0);
  mesher::Keyframe scan =
      scanOf(3, sensor,
             {sensor + Eigen::Vector3d(0.5, 0, 0), sensor + Eigen::Vector3d(0, 9.9, 0),
              sensor + Eigen::Vector3d(0, 0, -10.1)});
  filter.filter(scan);
  // Without voxels the kept returns keep their ids and positions.
  ASSERT_EQ(scan.observations.size(), 1u);
  EXPECT_EQ(scan.observations[0].point.value, (std::uint64_t{3} << 32) | 1u);
  EXPECT_EQ(scan.observations[0].position_W, sensor + Eigen::Vector3d(0, 9.9, 0));
  EXPECT_EQ(filter.counts().out_of_range, 2u);
  // A reader that dropped returns before the filter (KITTI, ahead of its subset) counts them in.
  filter.countDroppedOutOfRange(5);
  EXPECT_EQ(filter.counts().out_of_range, 7u);
  EXPECT_EQ(filter.counts().returns, 8u);
  EXPECT_NE(filter.describe().find("8 returns of 1 scans -> 1 observations"), std::string::npos)
      << filter.describe();
}

TEST(LidarScanFilter, FilteringAFilteredStreamChangesNothing) {
  // What makes the KITTI folder, its converted stream and a bag of that stream one mesh.
  std::mt19937_64 generator(3);
  std::uniform_real_distribution<double> coordinate(-4.0, 4.0);
  LidarScanOptions options;
  options.max_range_m = 4.5;  // cuts through the returns: a merged view keeps its return's verdict
  LidarScanFilter first(options);
  LidarScanFilter again(options);
  for (std::uint64_t frame = 0; frame < 5; ++frame) {
    std::vector<Eigen::Vector3d> positions(2000);
    for (Eigen::Vector3d& p : positions)
      p = {coordinate(generator), coordinate(generator), 0.01 * coordinate(generator)};
    mesher::Keyframe scan = scanOf(frame, Eigen::Vector3d(0.5 * frame, 0, 1.7), positions);
    first.filter(scan);
    mesher::Keyframe refiltered = scan;
    again.filter(refiltered);
    ASSERT_EQ(refiltered.observations.size(), scan.observations.size());
    for (std::size_t i = 0; i < scan.observations.size(); ++i) {
      EXPECT_EQ(refiltered.observations[i].point, scan.observations[i].point);
      EXPECT_EQ(refiltered.observations[i].position_W, scan.observations[i].position_W);
    }
  }
  EXPECT_GT(first.counts().merged_views, 0u);
  EXPECT_GT(first.counts().over_view_cap, 0u);
  EXPECT_GT(first.counts().out_of_range, 0u);
}

TEST(LidarScanFilter, InvalidOptionsAreRefused) {
  LidarScanOptions options;
  options.voxel_size_m = -0.1;
  options.min_range_m = 5.0;
  options.max_range_m = 2.0;
  EXPECT_EQ(options.problems().size(), 2u);
  EXPECT_THROW(LidarScanFilter{options}, std::invalid_argument);
  EXPECT_TRUE(LidarScanOptions().problems().empty());
  EXPECT_TRUE(LidarScanOptions::everyReturn().problems().empty());
}

TEST(LidarScanFilter, AReturnTooFarForAVoxelIdIsRefused) {
  LidarScanFilter filter(voxels(0.1));
  mesher::Keyframe scan = scanOf(0, Eigen::Vector3d::Zero(), {Eigen::Vector3d(2.0e5, 0, 0)});
  EXPECT_THROW(filter.filter(scan), std::out_of_range);
  EXPECT_EQ(filter.voxels(), 0u);
}

}  // namespace
}  // namespace terramesh::test
