#include "mesher/surface_delta.h"

#include <utility>

namespace terramesh::mesher {

FaceKey FaceKey::of(VertexKey a, VertexKey b, VertexKey c) {
  // Three compare-exchanges sort three keys (stable order of equal keys does not matter).
  if (b < a) std::swap(a, b);
  if (c < b) std::swap(b, c);
  if (b < a) std::swap(a, b);
  return FaceKey{{a, b, c}};
}

}  // namespace terramesh::mesher
