#pragma once

#include <cstdint>
#include <vector>

#include "cgal_types.h"

namespace terramesh::mesher::internal {

/// Cells whose weight rose above the free-space threshold during an update: seeds for growing.
/// Each cell is listed once (kCellCandidate flag); entries of cells destroyed later are detected
/// by their uid.
class GrowCandidates {
 public:
  void add(const CellHandle& cell) {
    if (cell->info().flags & kCellCandidate) return;
    cell->info().flags |= kCellCandidate;
    cells_.push_back({cell, cell->info().uid});
  }
  /// Hands over the list; the caller must clear kCellCandidate on the live cells it visits.
  std::vector<StampedCell> take() {
    std::vector<StampedCell> out;
    out.swap(cells_);
    return out;
  }

 private:
  std::vector<StampedCell> cells_;
};

/// The inverse-cone weight of every cell, kept equal to
///   w(c) = W1 k(c) + W2 sum_{n in N(c)} k(n) + W3 sum_{n in N(c)} sum_{m in N(n), m != c} k(m)
/// where k is the number of stored rays crossing a cell and N the face neighbours: each crossing
/// adds W1 to the cell, W2 to each neighbour and W3 to each neighbour's other neighbours.
/// Weights are fixed point (1/16) so that incremental updates equal a recomputation exactly.
class WeightField {
 public:
  static constexpr int kFixedPointScale = 16;

  WeightField(double crossed, double neighbour, double second_neighbour, double free_threshold);

  static std::int32_t toFixed(double weight);

  bool isFree(const CellHandle& cell) const { return cell->info().weight > threshold_; }
  std::int32_t threshold() const { return threshold_; }

  /// Applies a change of `delta` crossings of `cell` to the weights of its 2-ring. Cells that
  /// become free and are not in O are reported to `candidates`.
  void propagateCrossingChange(const CellHandle& cell, std::int32_t delta,
                               GrowCandidates& candidates) const;

  /// The weight of `cell` recomputed from the crossing counts around it.
  std::int32_t computeWeight(const CellHandle& cell) const;

  /// Sets the weight of `cell` from computeWeight; reports it if it became free.
  void recompute(const CellHandle& cell, GrowCandidates& candidates) const;

 private:
  void add(const CellHandle& cell, std::int32_t amount, GrowCandidates& candidates) const {
    std::int32_t& weight = cell->info().weight;
    const bool was_free = weight > threshold_;
    weight += amount;
    if (!was_free && weight > threshold_ && !cell->info().outside()) candidates.add(cell);
  }

  std::int32_t crossed_;
  std::int32_t neighbour_;
  std::int32_t second_neighbour_;
  std::int32_t threshold_;
};

}  // namespace terramesh::mesher::internal
