#pragma once
// The integer cell of a point in a cubic grid, and its hash: the one grid key the evaluation code
// and the comparison harness share (common/grid_key.h).

#include "common/grid_key.h"

namespace terramesh::evaluation {

/// Index of a cell of a cubic grid (cell (i, j, k) covers [i c, (i + 1) c) along x, and so on).
using CellKey = geometry::CellKey3;
/// geometry::spatialHash3 of the sign-extended indices.
using CellKeyHash = geometry::CellKey3Hash;

}  // namespace terramesh::evaluation
