#pragma once

#include <cstdint>
#include <functional>

namespace terramesh::mesher {

/// A strongly typed 64-bit identifier: ids of different kinds cannot be mixed up.
template <class Tag>
struct StrongId {
  std::uint64_t value = 0;

  friend constexpr bool operator==(StrongId a, StrongId b) { return a.value == b.value; }
  friend constexpr bool operator!=(StrongId a, StrongId b) { return a.value != b.value; }
  friend constexpr bool operator<(StrongId a, StrongId b) { return a.value < b.value; }
};

/// Identifier of a SLAM map point, as given by the SLAM system.
using PointId = StrongId<struct PointIdTag>;
/// Identifier of a SLAM keyframe, as given by the SLAM system.
using KeyframeId = StrongId<struct KeyframeIdTag>;

}  // namespace terramesh::mesher

template <class Tag>
struct std::hash<terramesh::mesher::StrongId<Tag>> {
  std::size_t operator()(terramesh::mesher::StrongId<Tag> id) const noexcept {
    return std::hash<std::uint64_t>{}(id.value);
  }
};
