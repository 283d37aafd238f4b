#include "visibility_weights.h"

#include <cmath>

namespace terramesh::mesher::internal {

WeightField::WeightField(double crossed, double neighbour, double second_neighbour,
                         double free_threshold, int spread_cap)
    : cap_(static_cast<std::uint32_t>(spread_cap)),
      crossed_(toFixed(crossed)),
      neighbour_(toFixed(neighbour)),
      second_neighbour_(toFixed(second_neighbour)),
      threshold_(toFixed(free_threshold)) {}

std::int32_t WeightField::toFixed(double weight) {
  return static_cast<std::int32_t>(std::lround(weight * kFixedPointScale));
}

void WeightField::propagateCrossingChange(const CellHandle& cell, std::uint32_t crossings_before,
                                          std::uint32_t spreading_before,
                                          GrowCandidates& candidates) const {
  const CellInfo& info = cell->info();
  const auto crossings =
      static_cast<std::int32_t>(info.crossings) - static_cast<std::int32_t>(crossings_before);
  if (crossings != 0) add(cell, crossed_ * crossings, candidates);
  const auto delta = static_cast<std::int32_t>(spread(info.spreading) - spread(spreading_before));
  if (delta == 0 || (neighbour_ == 0 && second_neighbour_ == 0)) return;
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
    weight += static_cast<std::int64_t>(neighbour_) * spread(n->info().spreading);
    for (int j = 0; j < 4; ++j) {
      const CellHandle m = n->neighbor(j);
      if (m != cell) weight += static_cast<std::int64_t>(second_neighbour_) * spread(m->info().spreading);
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
