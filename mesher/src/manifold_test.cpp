#include "manifold_test.h"

namespace terramesh::mesher::internal {

bool VertexRegularityTest::edgesFormOneCycle() const {
  const std::size_t n = edges_.size();
  if (n == 0) return true;
  if (n < 3) return false;
  // Walk the cycle from edge 0; each link vertex must have exactly two boundary edges.
  Delaunay::Vertex* const start = edges_[0].first;
  Delaunay::Vertex* current = edges_[0].second;
  std::size_t previous = 0;
  std::size_t walked = 1;
  while (current != start) {
    std::size_t next = n;
    for (std::size_t e = 0; e < n; ++e) {
      if (e == previous) continue;
      if (edges_[e].first == current || edges_[e].second == current) {
        if (next != n) return false;  // three or more boundary edges meet at `current`
        next = e;
      }
    }
    if (next == n) return false;  // dangling edge: cannot happen on a closed link, be safe
    current = edges_[next].first == current ? edges_[next].second : edges_[next].first;
    previous = next;
    if (++walked > n) return false;
  }
  if (walked != n) return false;  // more than one cycle
  // The start vertex must also have exactly two edges (the walk may close through a pinch).
  std::size_t at_start = 0;
  for (const auto& edge : edges_) at_start += (edge.first == start) + (edge.second == start);
  return at_start == 2;
}

}  // namespace terramesh::mesher::internal
