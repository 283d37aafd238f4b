#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

namespace terramesh::mesher::internal {

/// Integer index of a Steiner-grid cell (or of a lattice node, depending on context).
struct GridKey {
  std::int32_t i = 0;
  std::int32_t j = 0;
  std::int32_t k = 0;

  friend bool operator==(const GridKey& a, const GridKey& b) {
    return a.i == b.i && a.j == b.j && a.k == b.k;
  }
  friend bool operator!=(const GridKey& a, const GridKey& b) { return !(a == b); }
};

struct GridKeyHash {
  std::size_t operator()(const GridKey& key) const noexcept {
    // Large odd multipliers spread neighbouring keys over the table.
    const std::uint64_t h = static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.i)) * 73856093u ^
                            static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.j)) * 19349663u ^
                            static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.k)) * 83492791u;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace terramesh::mesher::internal
