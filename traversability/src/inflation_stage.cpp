// The inflation stage (layer_stages.h): distances along the surface to the nearest lethal face.
#include <cmath>
#include <limits>

#include "layer_stages.h"

namespace terramesh::traversability::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

InflationStage::InflationStage(double inflation_radius_m)
    : radius_m_(inflation_radius_m),
      declaration_{"inflation",
                   {"geometry", "lethal"},
                   {"lethal_distance_m"},
                   {StageReach::Kind::kGeodesic, inflation_radius_m}} {}

void InflationStage::resize(std::size_t slots) {
  distance_.resize(slots, kInf);
  marks_.resize(slots);
}

void InflationStage::removing(const SurfaceStore& store, Slot s, StageChanges& changes) {
  // A face at no finite distance lies on no shortest path: removing it changes no distance.
  if (std::isfinite(distance_[s])) changes.lethal_changes.push_back(store.centroid(s));
  distance_[s] = kInf;
}

template <class Inside>
void InflationStage::dijkstra(const SurfaceStore& store, Inside&& inside) {
  graph::boundedDijkstra(
      heap_, [&](Slot s) -> double& { return distance_[s]; },
      [&](Slot s, const auto& relax) {
        store.neighbours(s, scratch_);
        for (Slot t : scratch_) {
          if (inside(t)) relax(t, edgeM(store, s, t));
        }
      },
      radius_m_);
}

void InflationStage::computeAll(SurfaceStore& store) {
  for (Slot s = 0; s < store.slotCount(); ++s) {
    distance_[s] = kInf;
    if (store.face(s).alive && store.face(s).lethal) {
      distance_[s] = 0;
      graph::pushCost(heap_, 0.0, s);
    }
  }
  dijkstra(store, [](Slot) { return true; });
  for (Slot s = 0; s < store.slotCount(); ++s) {
    if (store.face(s).alive) store.face(s).layers.lethal_distance_m = static_cast<float>(distance_[s]);
  }
}

void InflationStage::update(SurfaceStore& store, StageChanges& changes) {
  for (Slot s : changes.added) distance_[s] = kInf;
  const double r = radius_m_ * (1 + 1e-9) + 1e-9;
  marks_.next();
  std::vector<Slot>& region = changes.redistanced;
  for (const Eigen::Vector3d& p : changes.lethal_changes) {
    const Eigen::Vector2d h = p.head<2>(), rr(r, r);
    store.forEachCentroidInBox(h - rr, h + rr, [&](Slot s) {
      if (marks_.marked(s) || (store.centroid(s) - p).norm() > r) return;
      marks_.mark(s);
      region.push_back(s);
    });
  }
  for (Slot s : region) distance_[s] = kInf;
  for (Slot s : region) {
    if (store.face(s).lethal) {
      distance_[s] = 0;
      graph::pushCost(heap_, 0.0, s);
      continue;
    }
    store.neighbours(s, scratch_);
    for (Slot b : scratch_) {
      if (marks_.marked(b) || !std::isfinite(distance_[b])) continue;
      const double nd = distance_[b] + edgeM(store, b, s);
      if (nd <= radius_m_ && nd < distance_[s]) distance_[s] = nd;
    }
    if (std::isfinite(distance_[s])) graph::pushCost(heap_, distance_[s], s);
  }
  dijkstra(store, [&](Slot t) { return marks_.marked(t); });
  for (Slot s : region) {
    if (store.face(s).alive) store.face(s).layers.lethal_distance_m = static_cast<float>(distance_[s]);
  }
}

}  // namespace terramesh::traversability::internal
