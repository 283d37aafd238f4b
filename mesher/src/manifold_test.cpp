#include "manifold_test.h"

#include <cstdint>

namespace terramesh::mesher::internal {

VertexRegularityTest::LinkSlot& VertexRegularityTest::slotOf(const Delaunay::Vertex* vertex) {
  const std::size_t mask = table_.size() - 1;
  std::size_t i = (reinterpret_cast<std::uintptr_t>(vertex) >> 4) * 0x9E3779B97F4A7C15ull >> 40 & mask;
  while (true) {
    LinkSlot& slot = table_[i];
    if (slot.generation != generation_) {
      slot.vertex = vertex;
      slot.generation = generation_;
      slot.degree = 0;
      return slot;
    }
    if (slot.vertex == vertex) return slot;
    i = (i + 1) & mask;
  }
}

bool VertexRegularityTest::edgesFormOneCycle() {
  const std::size_t n = edges_.size();
  if (n == 0) return true;
  if (n < 3) return false;
  // A table at least four times the number of link vertices (2n ends) keeps probing short.
  std::size_t capacity = 64;
  while (capacity < 4 * n) capacity *= 2;
  if (table_.size() < capacity) {
    table_.assign(capacity, LinkSlot{});
    generation_ = 0;
  }
  if (++generation_ == 0) {
    for (LinkSlot& slot : table_) slot.generation = 0;
    generation_ = 1;
  }
  // Every link vertex must end exactly two boundary edges.
  for (std::size_t e = 0; e < n; ++e) {
    for (const Delaunay::Vertex* end : {edges_[e].first, edges_[e].second}) {
      LinkSlot& slot = slotOf(end);
      if (slot.degree == 2) return false;
      slot.edge[slot.degree++] = static_cast<std::uint32_t>(e);
    }
  }
  // Degrees are all 2 once every end is seen twice, so the edges form disjoint cycles: walk the one
  // through edge 0 and check it uses every edge.
  Delaunay::Vertex* const start = edges_[0].first;
  Delaunay::Vertex* current = edges_[0].second;
  std::size_t edge = 0;
  std::size_t walked = 1;
  while (current != start) {
    const LinkSlot& slot = slotOf(current);
    if (slot.degree != 2) return false;
    edge = slot.edge[0] == edge ? slot.edge[1] : slot.edge[0];
    current = edges_[edge].first == current ? edges_[edge].second : edges_[edge].first;
    if (++walked > n) return false;
  }
  return walked == n && slotOf(start).degree == 2;
}

}  // namespace terramesh::mesher::internal
