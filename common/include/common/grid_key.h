#pragma once

// Integer cells of square and cubic grids, their keys and hashes: the one home of the grid-index
// formulas of the hash grids across terramesh.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace terramesh::geometry {

/// A cell of a square grid of size c: cell (i, j) covers [i c, (i + 1) c) x [j c, (j + 1) c).
struct CellKey2 {
  std::int64_t i = 0;
  std::int64_t j = 0;
  friend bool operator==(const CellKey2& a, const CellKey2& b) { return a.i == b.i && a.j == b.j; }
  friend bool operator!=(const CellKey2& a, const CellKey2& b) { return !(a == b); }
};

/// A cell of a cubic grid of size c: cell (i, j, k) covers [i c, (i + 1) c) along x, and so on.
struct CellKey3 {
  std::int64_t i = 0;
  std::int64_t j = 0;
  std::int64_t k = 0;
  friend bool operator==(const CellKey3& a, const CellKey3& b) { return a.i == b.i && a.j == b.j && a.k == b.k; }
  friend bool operator!=(const CellKey3& a, const CellKey3& b) { return !(a == b); }
};

/// The cell of p in a grid of squares `cell` wide (same units as p). @pre cell > 0; the
/// coordinates over cell fit in 64 bits.
inline CellKey2 cellOf(const Eigen::Vector2d& p, double cell) {
  return {static_cast<std::int64_t>(std::floor(p.x() / cell)), static_cast<std::int64_t>(std::floor(p.y() / cell))};
}

/// The cell of p in a grid of cubes `cell` wide (same units as p). @pre as for the 2-D cellOf.
inline CellKey3 cellOf(const Eigen::Vector3d& p, double cell) {
  return {static_cast<std::int64_t>(std::floor(p.x() / cell)), static_cast<std::int64_t>(std::floor(p.y() / cell)),
          static_cast<std::int64_t>(std::floor(p.z() / cell))};
}

/// One word for a 2-D cell: the low 32 bits of i (high half) and of j (low half); unique for
/// cells with i and j in [-2^31, 2^31), so the word itself can key a hash table.
constexpr std::uint64_t packCell2(std::int64_t i, std::int64_t j) noexcept {
  return (static_cast<std::uint64_t>(i) << 32) | (static_cast<std::uint64_t>(j) & 0xffffffffull);
}

/// The Z-order (Morton) index of a 2-D cell: the bits of i and j, each offset by 2^31, interleaved
/// (j's in the even bits). Cells close in the plane are mostly close in this order, at every
/// scale: sorting by it gives a walk over the plane that stays local. @pre i and j in
/// [-2^31, 2^31).
constexpr std::uint64_t mortonCell2(std::int64_t i, std::int64_t j) noexcept {
  const auto spread = [](std::uint64_t v) {
    v &= 0xffffffffull;
    v = (v | (v << 16)) & 0x0000ffff0000ffffull;
    v = (v | (v << 8)) & 0x00ff00ff00ff00ffull;
    v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
    return v;
  };
  constexpr std::uint64_t kOffset = std::uint64_t{1} << 31;
  return (spread(static_cast<std::uint64_t>(i) + kOffset) << 1) | spread(static_cast<std::uint64_t>(j) + kOffset);
}

/// Cells that packCell3 can pack: every index in [-2^20, 2^20).
constexpr bool fitsPackCell3(std::int64_t i, std::int64_t j, std::int64_t k) noexcept {
  constexpr std::int64_t kLimit = std::int64_t{1} << 20;
  return i >= -kLimit && i < kLimit && j >= -kLimit && j < kLimit && k >= -kLimit && k < kLimit;
}

/// One word for a 3-D cell: the low 21 bits of i, j and k (bits 62-42, 41-21, 20-0; bit 63 is
/// 0), unique for cells where fitsPackCell3 holds, so the word can key a table or name the cell.
constexpr std::uint64_t packCell3(std::int64_t i, std::int64_t j, std::int64_t k) noexcept {
  constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
  return ((static_cast<std::uint64_t>(i) & kMask) << 42) | ((static_cast<std::uint64_t>(j) & kMask) << 21) |
         (static_cast<std::uint64_t>(k) & kMask);
}

/// The spatial hash of Teschner et al. (2003), three large primes XORed, in wrapping unsigned
/// arithmetic. Callers pass the coordinates as 64-bit words: sign-extended (the cast of a signed
/// index) or zero-extended from 32 bits (the cast of a std::uint32_t) give different, equally
/// spread hashes; a table keeps the one it was built with, since its iteration order follows it.
constexpr std::uint64_t spatialHash3(std::uint64_t i, std::uint64_t j, std::uint64_t k) noexcept {
  return i * 73856093u ^ j * 19349663u ^ k * 83492791u;
}

/// Hash of a 2-D cell: i times the 64-bit golden ratio, XOR j (rows may collide where j < 0).
struct CellKey2Hash {
  std::size_t operator()(const CellKey2& key) const noexcept {
    return static_cast<std::size_t>(key.i) * 0x9E3779B97F4A7C15ull ^ static_cast<std::size_t>(key.j);
  }
};

/// Hash of a 3-D cell for std::unordered_map: `spatialHash3` of the sign-extended indices.
struct CellKey3Hash {
  std::size_t operator()(const CellKey3& key) const noexcept {
    return static_cast<std::size_t>(spatialHash3(static_cast<std::uint64_t>(key.i), static_cast<std::uint64_t>(key.j),
                                                 static_cast<std::uint64_t>(key.k)));
  }
};

}  // namespace terramesh::geometry
