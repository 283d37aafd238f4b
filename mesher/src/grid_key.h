#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "common/grid_key.h"

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

/// geometry::spatialHash3 of the indices zero-extended from 32 bits.
struct GridKeyHash {
  std::size_t operator()(const GridKey& key) const noexcept {
    return static_cast<std::size_t>(geometry::spatialHash3(static_cast<std::uint32_t>(key.i),
                                                           static_cast<std::uint32_t>(key.j),
                                                           static_cast<std::uint32_t>(key.k)));
  }
};

}  // namespace terramesh::mesher::internal
