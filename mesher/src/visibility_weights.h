#pragma once

#include <algorithm>
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
///   w(c) = W1 k(c) + W2 sum_{n in N(c)} S(n) + W3 sum_{n in N(c)} sum_{m in N(n), m != c} S(m)
/// where k is the number of stored rays crossing a cell, s the number of those that spread (every
/// crossing except in the ray's last cell, the one incident to its point: the apex of the inverse
/// cone, as in Romanoni & Matteucci 2015), S(n) = min(s(n), cap) (S = s when cap is 0) and N the
/// face neighbours. So each crossing adds W1 to its cell and, away from the point, W2 to each
/// neighbour and W3 to each neighbour's other neighbours, up to `cap` crossings per neighbour.
/// Weights are fixed point (1/16) so incremental updates equal a recomputation exactly.
class WeightField {
 public:
  static constexpr int kFixedPointScale = 16;

  WeightField(double crossed, double neighbour, double second_neighbour, double free_threshold,
              int spread_cap);

  static std::int32_t toFixed(double weight);

  bool isFree(const CellHandle& cell) const { return cell->info().weight > threshold_; }
  std::int32_t threshold() const { return threshold_; }

  /// Applies a change of the crossing counts of `cell` (from the given previous values to its
  /// current ones) to the weights of its 2-ring. Cells that become free and are not in O are
  /// reported to `candidates`.
  void propagateCrossingChange(const CellHandle& cell, std::uint32_t crossings_before,
                               std::uint32_t spreading_before, GrowCandidates& candidates) const;

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

  /// What a neighbour with `spreading` spreading crossings contributes (in crossings).
  std::int64_t spread(std::uint32_t spreading) const {
    return cap_ == 0 ? spreading : std::min<std::uint32_t>(spreading, cap_);
  }

  std::uint32_t cap_;
  std::int32_t crossed_;
  std::int32_t neighbour_;
  std::int32_t second_neighbour_;
  std::int32_t threshold_;
};

}  // namespace terramesh::mesher::internal
