// A face's footprint samples: the ground each sample of the footprint's grid finds in its height
// band (LayerComputer::sampleGround), and whether the columns that find none lie in space the rays
// carved (markUnseenColumns). Internal.
#include <algorithm>
#include <array>
#include <limits>
#include <optional>

#include "footprint_samples.h"
#include "layer_computer.h"

namespace terramesh::traversability::internal {
namespace {

constexpr double kSliceToleranceM = LayerComputer::kSliceToleranceM;

/// The edges of a face's horizontal projection, prepared for slicing by vertical lines x = const.
struct ProjectedEdges {
  struct Edge {
    double x_min, x_max;  ///< x range of the edge
    double x0, y0;        ///< start point
    double y1;            ///< end point's y
    double slope;         ///< dy/dx (unused if parallel)
    bool parallel;        ///< (nearly) parallel to the slicing lines: the slice takes all of it
  };
  std::array<Edge, 3> edges;

  explicit ProjectedEdges(const SampleGeometry& g) {
    const std::array<Eigen::Vector2d, 3> corners{Eigen::Vector2d(g.x0, g.y0), Eigen::Vector2d(g.x0 + g.bx, g.y0 + g.by),
                                                 Eigen::Vector2d(g.x0 + g.cx, g.y0 + g.cy)};
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector2d& p = corners[e];
      const Eigen::Vector2d& q = corners[(e + 1) % 3];
      const double dx = q.x() - p.x();
      Edge& edge = edges[e];
      edge.x_min = std::min(p.x(), q.x());
      edge.x_max = std::max(p.x(), q.x());
      edge.x0 = p.x();
      edge.y0 = p.y();
      edge.y1 = q.y();
      edge.parallel = std::abs(dx) < kSliceToleranceM;
      edge.slope = edge.parallel ? 0.0 : (q.y() - p.y()) / dx;
    }
  }

  /// The y range [y_lo, y_hi] (a superset, up to rounding) of the projection on the line at x;
  /// false if the line misses it (farther than kSliceToleranceM).
  bool slice(double x, double& y_lo, double& y_hi) const {
    y_lo = std::numeric_limits<double>::infinity();
    y_hi = -y_lo;
    for (const Edge& e : edges) {
      if (x < e.x_min - kSliceToleranceM || x > e.x_max + kSliceToleranceM) continue;
      if (e.parallel) {
        y_lo = std::min({y_lo, e.y0, e.y1});
        y_hi = std::max({y_hi, e.y0, e.y1});
        continue;
      }
      const double y = e.y0 + (std::clamp(x, e.x_min, e.x_max) - e.x0) * e.slope;
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
    return y_lo <= y_hi;
  }
};

}  // namespace

void LayerComputer::sampleGround(const SurfaceStore& store, const Eigen::Vector3d& c, bool driven_only) const {
  const int K = k_;
  z_.assign(offsets_.size(), std::numeric_limits<double>::quiet_NaN());
  level_.assign(offsets_.size(), kNoGround);
  z_relief_.assign(offsets_.size(), 0.0);
  const double spacing = spacing_m_;
  const auto first = [&](double lo, double centre) { return firstNode(lo, centre, spacing, K); };
  const auto last = [&](double hi, double centre) { return lastNode(hi, centre, spacing, K); };
  // Grid indices of the nodes at or above lo, at or below hi (NaN: all).
  const auto ceilIndex = [&](double lo, double centre) {
    const double t = (lo - centre) / spacing;
    if (!(t > -K)) return -K;
    return t > K ? K + 1 : ceilInt(t);
  };
  const auto floorIndex = [&](double hi, double centre) {
    const double t = (hi - centre) / spacing;
    if (!(t < K)) return K;
    return t < -K ? -K - 1 : floorInt(t);
  };
  // Candidate by candidate (in the order of candidates_), each over the samples in its box: per
  // sample, the same candidates in the same order as a sample-by-sample search, so the same result.
  for (Slot t : candidates_) {
    const SampleGeometry& g = store.geometry(t);
    if (!g.sampleable) continue;  // heightAt finds nothing on it
    // Steiner faces are invented: they mark a sample as unknown, never as ground (measured ground
    // anywhere in the band wins, whatever its distance).
    const char level = g.steiner || (driven_only && !g.driven) ? kUnknownGround
                       : g.normal_z >= cos_max_slope_        ? kLevelGround
                                                             : kSteepGround;
    const int i0 = first(g.box_min.x(), c.x()), i1 = last(g.box_max.x(), c.x());
    const int j0 = first(g.box_min.y(), c.y()), j1 = last(g.box_max.y(), c.y());
    // A face between the samples (a dense mesh under a large footprint) holds none.
    if (!holdsNode(i0, i1, g.box_min.x(), g.box_max.x(), c.x(), spacing) ||
        !holdsNode(j0, j1, g.box_min.y(), g.box_max.y(), c.y(), spacing)) {
      continue;
    }
    const ProjectedEdges edges(g);
    for (int i = i0; i <= i1; ++i) {
      // Only the samples of this column near the triangle's slice [y_lo, y_hi] at its x.
      double y_lo = 0, y_hi = 0;
      if (!edges.slice(c.x() + i * spacing, y_lo, y_hi)) continue;
      const int j_lo = std::max(j0, ceilIndex(y_lo - kSliceToleranceM, c.y()));
      const int j_hi = std::min(j1, floorIndex(y_hi + kSliceToleranceM, c.y()));
      for (int j = j_lo; j <= j_hi; ++j) {
        const int k = offset_index_[static_cast<std::size_t>((i + K) * (2 * K + 1) + j + K)];
        if (k < 0) continue;
        const Eigen::Vector2d& o = offsets_[static_cast<std::size_t>(k)];
        const double x = c.x() + o.x(), y = c.y() + o.y();
        if (g.box_min.x() > x || g.box_max.x() < x || g.box_min.y() > y || g.box_max.y() < y) continue;
        const std::optional<double> z = g.heightAt(x, y);
        const double ref_z = ref_[static_cast<std::size_t>(k)];
        if (!z || *z < ref_z - band_down_m_ || *z > ref_z + profile_.min_clearance_m) continue;
        double& best = z_[static_cast<std::size_t>(k)];
        char& best_level = level_[static_cast<std::size_t>(k)];
        if (level == kUnknownGround) {
          if (best_level == kNoGround) best_level = kUnknownGround;
          continue;
        }
        const bool measured = best_level == kLevelGround || best_level == kSteepGround;
        const double d = std::abs(*z - ref_z), best_d = measured ? std::abs(best - ref_z) : 0.0;
        if (!measured || d < best_d || (d == best_d && *z < best)) {
          best = *z;
          best_level = level;
          z_relief_[static_cast<std::size_t>(k)] = g.relief_m;
        }
      }
    }
  }
  if (driven_only) markUnseenColumns(store, c);
}

void LayerComputer::markUnseenColumns(const SurfaceStore& store, const Eigen::Vector3d& c) const {
  for (std::size_t k = 0; k < offsets_.size(); ++k) {
    if (level_[k] != kNoGround) continue;
    const double x = c.x() + offsets_[k].x(), y = c.y() + offsets_[k].y();
    // The first face over the sample's reference height: facing down, it is the lid over space the
    // rays carved (a hole or a drop, ground missing); facing up, the sample lies in matter nobody
    // carved; none, beyond the map.
    double first_z = std::numeric_limits<double>::infinity();
    bool carved = false;
    store.forEachAt(x, y, [&](Slot u) {
      if (!store.bounds(u).alive) return;
      const SampleGeometry& g = store.geometry(u);
      if (!g.sampleable) return;
      const std::optional<double> z = g.heightAt(x, y);
      if (!z || *z <= ref_[k] || *z >= first_z) return;
      first_z = *z;
      carved = g.normal_z < 0;
    });
    if (!carved) level_[k] = kNoDataGround;
  }
}

}  // namespace terramesh::traversability::internal
