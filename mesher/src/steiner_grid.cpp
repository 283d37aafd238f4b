#include "steiner_grid.h"

#include <algorithm>
#include <cmath>

namespace terramesh::mesher::internal {
namespace {

// Fractions of the step by which the lattice is shifted from the first point it covers.
constexpr double kOffsetX = 0.5 + 0.1234567;
constexpr double kOffsetY = 0.5 + 0.2718281;
constexpr double kOffsetZ = 0.5 + 0.0314159;

}  // namespace

SteinerGrid::SteinerGrid(double step, const Eigen::Vector3d& origin_shift, bool global_phase)
    : step_(step), origin_shift_(origin_shift), global_phase_(global_phase) {}

GridKey SteinerGrid::cellOf(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d scaled = (p - origin_) / step_;
  return {static_cast<std::int32_t>(std::floor(scaled.x())),
          static_cast<std::int32_t>(std::floor(scaled.y())),
          static_cast<std::int32_t>(std::floor(scaled.z()))};
}

Eigen::Vector3d SteinerGrid::nodePosition(const GridKey& node) const {
  return origin_ + step_ * Eigen::Vector3d(node.i, node.j, node.k);
}

GridKey SteinerGrid::nodeOf(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d scaled = (p - origin_) / step_;
  return {static_cast<std::int32_t>(std::lround(scaled.x())),
          static_cast<std::int32_t>(std::lround(scaled.y())),
          static_cast<std::int32_t>(std::lround(scaled.z()))};
}

bool SteinerGrid::coversCell(const GridKey& key, int margin) const {
  return initialized_ && key.i - margin >= lo_.i && key.j - margin >= lo_.j &&
         key.k - margin >= lo_.k && key.i + 1 + margin <= hi_.i && key.j + 1 + margin <= hi_.j &&
         key.k + 1 + margin <= hi_.k;
}

std::vector<Eigen::Vector3d> SteinerGrid::coverPoint(const Eigen::Vector3d& p, int margin) {
  return coverBox(p, p, margin);
}

std::vector<Eigen::Vector3d> SteinerGrid::coverBox(const Eigen::Vector3d& min,
                                                   const Eigen::Vector3d& max, int margin) {
  if (!initialized_) {
    const Eigen::Vector3d start = global_phase_ ? Eigen::Vector3d(step_ * (min / step_).array().floor().matrix()) : min;
    origin_ = start - step_ * Eigen::Vector3d(kOffsetX, kOffsetY, kOffsetZ) + origin_shift_;
  }
  const GridKey a = cellOf(min);
  const GridKey b = cellOf(max);
  GridKey lo{a.i - margin, a.j - margin, a.k - margin};
  GridKey hi{b.i + 1 + margin, b.j + 1 + margin, b.k + 1 + margin};
  if (sparse_) return addNodes(lo, hi);
  if (initialized_) {
    if (lo.i >= lo_.i && lo.j >= lo_.j && lo.k >= lo_.k && hi.i <= hi_.i && hi.j <= hi_.j &&
        hi.k <= hi_.k) {
      return {};
    }
    lo = {std::min(lo.i, lo_.i), std::min(lo.j, lo_.j), std::min(lo.k, lo_.k)};
    hi = {std::max(hi.i, hi_.i), std::max(hi.j, hi_.j), std::max(hi.k, hi_.k)};
  }
  return growNodeBox(lo, hi);
}

std::vector<Eigen::Vector3d> SteinerGrid::growNodeBox(const GridKey& lo, const GridKey& hi) {
  std::vector<Eigen::Vector3d> added;
  auto inside_old = [this](std::int32_t i, std::int32_t j, std::int32_t k) {
    return initialized_ && i >= lo_.i && i <= hi_.i && j >= lo_.j && j <= hi_.j && k >= lo_.k &&
           k <= hi_.k;
  };
  for (std::int32_t i = lo.i; i <= hi.i; ++i) {
    for (std::int32_t j = lo.j; j <= hi.j; ++j) {
      for (std::int32_t k = lo.k; k <= hi.k; ++k) {
        if (!inside_old(i, j, k)) added.push_back(nodePosition({i, j, k}));
      }
    }
  }
  lo_ = lo;
  hi_ = hi;
  initialized_ = true;
  return added;
}

std::vector<Eigen::Vector3d> SteinerGrid::addNodes(const GridKey& lo, const GridKey& hi) {
  std::vector<Eigen::Vector3d> added;
  for (std::int32_t i = lo.i; i <= hi.i; ++i) {
    for (std::int32_t j = lo.j; j <= hi.j; ++j) {
      for (std::int32_t k = lo.k; k <= hi.k; ++k) {
        if (present_.insert({i, j, k}).second) added.push_back(nodePosition({i, j, k}));
      }
    }
  }
  if (!initialized_) {
    lo_ = lo;
    hi_ = hi;
    initialized_ = true;
  }
  lo_ = {std::min(lo.i, lo_.i), std::min(lo.j, lo_.j), std::min(lo.k, lo_.k)};
  hi_ = {std::max(hi.i, hi_.i), std::max(hi.j, hi_.j), std::max(hi.k, hi_.k)};
  return added;
}

void SteinerGrid::makeSparse() {
  if (sparse_) return;
  sparse_ = true;
  if (!initialized_) return;
  for (std::int32_t i = lo_.i; i <= hi_.i; ++i) {
    for (std::int32_t j = lo_.j; j <= hi_.j; ++j) {
      for (std::int32_t k = lo_.k; k <= hi_.k; ++k) present_.insert({i, j, k});
    }
  }
}

std::size_t SteinerGrid::nodeCount() const {
  if (sparse_) return present_.size();
  if (!initialized_) return 0;
  return static_cast<std::size_t>(hi_.i - lo_.i + 1) * static_cast<std::size_t>(hi_.j - lo_.j + 1) *
         static_cast<std::size_t>(hi_.k - lo_.k + 1);
}

}  // namespace terramesh::mesher::internal
