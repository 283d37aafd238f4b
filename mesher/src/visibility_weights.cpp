#include "visibility_weights.h"

#include <cmath>

namespace terramesh::mesher::internal {

WeightField::WeightField(double crossed, double neighbour, double second_neighbour,
                         double free_threshold)
    : crossed_(toFixed(crossed)),
      neighbour_(toFixed(neighbour)),
      second_neighbour_(toFixed(second_neighbour)),
      threshold_(toFixed(free_threshold)) {}

std::int32_t WeightField::toFixed(double weight) {
  return static_cast<std::int32_t>(std::lround(weight * kFixedPointScale));
}

void WeightField::propagateCrossingChange(const CellHandle& cell, std::int32_t delta,
                                          GrowCandidates& candidates) const {
  if (delta == 0) return;
  add(cell, crossed_ * delta, candidates);
  if (neighbour_ == 0 && second_neighbour_ == 0) return;
  for (int i = 0; i < 4; ++i) {
    const CellHandle n = cell->neighbor(i);
    if (neighbour_ != 0) add(n, neighbour_ * delta, candidates);
    if (second_neighbour_ == 0) continue;
    for (int j = 0; j < 4; ++j) {
      const CellHandle m = n->neighbor(j);
      if (m != cell) add(m, second_neighbour_ * delta, candidates);
    }
  }
}

std::int32_t WeightField::computeWeight(const CellHandle& cell) const {
  std::int64_t weight = static_cast<std::int64_t>(crossed_) * cell->info().crossings;
  for (int i = 0; i < 4; ++i) {
    const CellHandle n = cell->neighbor(i);
    weight += static_cast<std::int64_t>(neighbour_) * n->info().crossings;
    for (int j = 0; j < 4; ++j) {
      const CellHandle m = n->neighbor(j);
      if (m != cell) weight += static_cast<std::int64_t>(second_neighbour_) * m->info().crossings;
    }
  }
  return static_cast<std::int32_t>(weight);
}

void WeightField::recompute(const CellHandle& cell, GrowCandidates& candidates) const {
  const std::int32_t weight = computeWeight(cell);
  std::int32_t& stored = cell->info().weight;
  const bool was_free = stored > threshold_;
  stored = weight;
  if (!was_free && weight > threshold_ && !cell->info().outside()) candidates.add(cell);
}

}  // namespace terramesh::mesher::internal
