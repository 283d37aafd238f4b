// Grid keys: the cell of a point, the packed 2-D and 3-D keys (unique over a range of signed cells) and
// the hashes the grids use (exact values, since hash tables iterate in their order).
#include <gtest/gtest.h>

#include <cstdint>
#include <unordered_set>

#include "common/grid_key.h"

namespace terramesh::geometry {
namespace {

TEST(GridKeyTest, CellOfFloorsTowardsMinusInfinity) {
  EXPECT_EQ(cellOf(Eigen::Vector2d(0.0, 0.99), 1.0), (CellKey2{0, 0}));
  EXPECT_EQ(cellOf(Eigen::Vector2d(-0.01, 2.0), 1.0), (CellKey2{-1, 2}));
  EXPECT_EQ(cellOf(Eigen::Vector2d(-2.5, 2.5), 0.5), (CellKey2{-5, 5}));
  EXPECT_EQ(cellOf(Eigen::Vector3d(1.5, -1.5, -3.0), 1.5), (CellKey3{1, -1, -2}));
  EXPECT_NE(cellOf(Eigen::Vector3d(0, 0, 0), 1.0), cellOf(Eigen::Vector3d(0, 0, -1e-9), 1.0));
}

TEST(GridKeyTest, PackedKeysAreUniqueOverSignedCells) {
  std::unordered_set<std::uint64_t> seen;
  for (std::int64_t i = -40; i <= 40; ++i) {
    for (std::int64_t j = -40; j <= 40; ++j) EXPECT_TRUE(seen.insert(packCell2(i, j)).second) << i << ' ' << j;
  }
  // The extremes of the 32-bit range stay apart from each other and from their neighbours.
  const std::int64_t lo = -(std::int64_t{1} << 31), hi = (std::int64_t{1} << 31) - 1;
  for (const std::int64_t i : {lo, lo + 1, hi - 1, hi}) {
    for (const std::int64_t j : {lo, lo + 1, hi - 1, hi}) EXPECT_TRUE(seen.insert(packCell2(i, j)).second);
  }
  EXPECT_EQ(seen.size(), 81u * 81u + 16u);
}

TEST(GridKeyTest, PackedKeyHoldsTheLow32BitsSideBySide) {
  EXPECT_EQ(packCell2(0, 0), 0u);
  EXPECT_EQ(packCell2(1, 2), 0x0000000100000002ull);
  EXPECT_EQ(packCell2(-1, 0), 0xffffffff00000000ull);
  EXPECT_EQ(packCell2(0, -1), 0x00000000ffffffffull);
  EXPECT_EQ(packCell2(-2, -3), 0xfffffffefffffffdull);
  static_assert(packCell2(3, 4) == ((3ull << 32) | 4ull), "constexpr");
}

TEST(GridKeyTest, MortonKeyInterleavesTheOffsetIndices) {
  constexpr std::int64_t kZero = -(std::int64_t{1} << 31);  // offset to 0
  EXPECT_EQ(mortonCell2(kZero, kZero), 0u);
  EXPECT_EQ(mortonCell2(kZero, kZero + 1), 1u);  // j in the even bits
  EXPECT_EQ(mortonCell2(kZero + 1, kZero), 2u);
  EXPECT_EQ(mortonCell2(kZero + 3, kZero + 3), 15u);
  EXPECT_EQ(mortonCell2(kZero + 2, kZero), 8u);
  // 0 offset is 2^31: bit 31 of each, interleaved into bits 63 (i) and 62 (j).
  EXPECT_EQ(mortonCell2(0, 0), 0xc000000000000000ull);
  // The Z curve visits a 2x2 block before moving on, at every scale: the four cells of each
  // aligned 2^k block take consecutive keys.
  std::unordered_set<std::uint64_t> seen;
  for (std::int64_t i = -8; i < 8; ++i) {
    for (std::int64_t j = -8; j < 8; ++j) EXPECT_TRUE(seen.insert(mortonCell2(i, j)).second);
  }
  for (std::int64_t i = -8; i < 8; i += 2) {
    for (std::int64_t j = -8; j < 8; j += 2) {
      const std::uint64_t first = mortonCell2(i, j);
      EXPECT_EQ(first % 4, 0u);
      EXPECT_EQ(mortonCell2(i, j + 1), first + 1);
      EXPECT_EQ(mortonCell2(i + 1, j), first + 2);
      EXPECT_EQ(mortonCell2(i + 1, j + 1), first + 3);
    }
  }
}

TEST(GridKeyTest, Packed3DKeysAreUniqueWithinTheirRangeAndLeaveBit63Clear) {
  std::unordered_set<std::uint64_t> seen;
  constexpr std::int64_t lo = -(std::int64_t{1} << 20), hi = (std::int64_t{1} << 20) - 1;
  for (const std::int64_t i : {lo, lo + 1, std::int64_t{-1}, std::int64_t{0}, std::int64_t{1}, hi - 1, hi}) {
    for (const std::int64_t j : {lo, std::int64_t{-1}, std::int64_t{0}, hi}) {
      for (const std::int64_t k : {lo, std::int64_t{-2}, std::int64_t{-1}, std::int64_t{0}, std::int64_t{1}, hi}) {
        ASSERT_TRUE(fitsPackCell3(i, j, k));
        const std::uint64_t key = packCell3(i, j, k);
        EXPECT_TRUE(seen.insert(key).second) << i << ' ' << j << ' ' << k;
        EXPECT_EQ(key >> 63, 0u);
      }
    }
  }
  EXPECT_FALSE(fitsPackCell3(hi + 1, 0, 0));
  EXPECT_FALSE(fitsPackCell3(0, lo - 1, 0));
  EXPECT_FALSE(fitsPackCell3(0, 0, hi + 1));
  static_assert(packCell3(1, 2, 3) == ((1ull << 42) | (2ull << 21) | 3ull), "constexpr");
}

TEST(GridKeyTest, SpatialHashIsTeschnersInWrappingArithmetic) {
  EXPECT_EQ(spatialHash3(0, 0, 0), 0u);
  EXPECT_EQ(spatialHash3(1, 0, 0), 73856093u);
  EXPECT_EQ(spatialHash3(0, 1, 0), 19349663u);
  EXPECT_EQ(spatialHash3(0, 0, 1), 83492791u);
  EXPECT_EQ(spatialHash3(1, 1, 1), 73856093ull ^ 19349663ull ^ 83492791ull);
  // Sign-extended -1 wraps to -73856093; zero-extended from 32 bits it does not.
  EXPECT_EQ(spatialHash3(static_cast<std::uint64_t>(std::int64_t{-1}), 0, 0), ~std::uint64_t{73856093u} + 1);
  EXPECT_EQ(spatialHash3(std::uint32_t{0xffffffffu}, 0, 0), 0xffffffffull * 73856093ull);
  EXPECT_EQ(CellKey3Hash{}(CellKey3{-1, 2, -3}),
            static_cast<std::size_t>(std::int64_t{-1} * 73856093LL ^ 2 * 19349663LL ^ std::int64_t{-3} * 83492791LL));
}

TEST(GridKeyTest, CellKey2HashMixesTheFirstIndex) {
  EXPECT_EQ(CellKey2Hash{}(CellKey2{0, 5}), 5u);
  EXPECT_EQ(CellKey2Hash{}(CellKey2{1, 0}), 0x9E3779B97F4A7C15ull);
  EXPECT_EQ(CellKey2Hash{}(CellKey2{-1, 1}), (0ull - 0x9E3779B97F4A7C15ull) ^ 1ull);
  // Distinct over a block of cells with j >= 0; a negative j sets every high bit, so rows may then
  // collide (the hash is kept as the level segmentation's tables were built with it).
  std::unordered_set<std::size_t> hashes;
  for (std::int64_t i = -30; i <= 30; ++i) {
    for (std::int64_t j = 0; j <= 60; ++j) hashes.insert(CellKey2Hash{}(CellKey2{i, j}));
  }
  EXPECT_EQ(hashes.size(), 61u * 61u);
}

}  // namespace
}  // namespace terramesh::geometry
