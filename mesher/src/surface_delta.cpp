#include "mesher/surface_delta.h"

#include <algorithm>

namespace terramesh::mesher {

FaceKey FaceKey::of(VertexKey a, VertexKey b, VertexKey c) {
  FaceKey key{{a, b, c}};
  std::sort(key.sorted.begin(), key.sorted.end());
  return key;
}

}  // namespace terramesh::mesher
