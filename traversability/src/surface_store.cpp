#include "surface_store.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <Eigen/Geometry>

#include "common/grid_key.h"

namespace terramesh::traversability::internal {

SurfaceStore::SurfaceStore(const Eigen::Matrix3d& R_L_W, double metres_per_unit, double cell_m,
                           double centroid_cell_m)
    : R_L_W_(R_L_W), metres_per_unit_(metres_per_unit), cell_m_(cell_m), centroid_cell_m_(centroid_cell_m) {}

std::int64_t SurfaceStore::cellIndex(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_m_)); }
std::int64_t SurfaceStore::centroidCellIndex(double v) const {
  return static_cast<std::int64_t>(std::floor(v / centroid_cell_m_));
}
SurfaceStore::CellKey SurfaceStore::centroidCellKey(const Eigen::Vector3d& c) const {
  return cellKey(centroidCellIndex(c.x()), centroidCellIndex(c.y()));
}

SurfaceStore::CellKey SurfaceStore::cellKey(std::int64_t i, std::int64_t j) const { return geometry::packCell2(i, j); }

void SurfaceStore::sortByLocality(std::vector<Slot>& slots, std::size_t first, std::size_t last) const {
  std::vector<std::pair<std::uint64_t, Slot>> keyed;
  keyed.reserve(last - first);
  for (std::size_t i = first; i < last; ++i) {
    const geometry::CellKey2 cell = geometry::cellOf(Eigen::Vector2d(centroids_[slots[i]].head<2>()), kLocalityCellM);
    keyed.emplace_back(geometry::mortonCell2(cell.i, cell.j), slots[i]);
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t i = first; i < last; ++i) slots[i] = keyed[i - first].second;
}

std::vector<Slot> SurfaceStore::aliveSlotsByLocality() const {
  std::vector<Slot> slots;
  slots.reserve(size());
  for (Slot s = 0; s < slotCount(); ++s) {
    if (faces_[s].alive) slots.push_back(s);
  }
  sortByLocality(slots, 0, slots.size());
  return slots;
}

void SurfaceStore::setDrive(Slot s,
                                const std::function<std::optional<Eigen::Isometry3d>(mesher::PointId)>& lookup) {
  StoredFace& f = faces_[s];
  f.drive_axis.setZero();
  f.drive_centre.setZero();
  if (f.driven_vertices < 2 || !lookup) return;
  // Axes modulo a half turn: the doubled angle's mean (a strip driven both ways has one axis).
  double c2 = 0, s2 = 0;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  int bases = 0;
  for (const mesher::VertexKey& v : f.vertices) {
    const std::optional<Eigen::Isometry3d> base_W = lookup(mesher::PointId{v.value});
    if (!base_W) continue;  // a SLAM point beside two driven samples
    centre += (R_L_W_ * (base_W->translation() * metres_per_unit_)).head<2>();
    ++bases;
    const Eigen::Vector2d h = (R_L_W_ * base_W->linear().col(0)).head<2>();
    if (!(h.squaredNorm() > 0)) return;
    const double angle = std::atan2(h.y(), h.x());
    c2 += std::cos(2 * angle);
    s2 += std::sin(2 * angle);
  }
  // Headings whose axes spread over more than about 60 degrees give no axis.
  if (bases < f.driven_vertices || !(std::hypot(c2, s2) > 0.5 * bases)) return;
  const double angle = 0.5 * std::atan2(s2, c2);
  f.drive_axis = Eigen::Vector2d(std::cos(angle), std::sin(angle));
  f.drive_centre = centre / bases;
}

Slot SurfaceStore::add(const mesher::SurfaceFace& input) {
  remove(input.key);
  // Slots share their grid entries with two flag bits.
  if (free_slots_.empty() && faces_.size() > kSlotMask) throw std::length_error("SurfaceStore: too many faces");
  Slot s;
  if (!free_slots_.empty()) {
    s = free_slots_.back();
    free_slots_.pop_back();
  } else {
    s = static_cast<Slot>(faces_.size());
    faces_.emplace_back();
    bounds_.emplace_back();
    geometry_.emplace_back();
    centroids_.emplace_back();
  }
  StoredFace& f = faces_[s];
  f = StoredFace{};
  f.key = input.key;
  f.vertices = input.vertices;
  f.positions_W = input.positions_W;
  for (int i = 0; i < 3; ++i) f.p_L[i] = R_L_W_ * (input.positions_W[i] * metres_per_unit_);
  f.centroid_L = (f.p_L[0] + f.p_L[1] + f.p_L[2]) / 3.0;
  centroids_[s] = f.centroid_L;
  const Eigen::Vector3d n = (f.p_L[1] - f.p_L[0]).cross(f.p_L[2] - f.p_L[0]);
  f.normal_L = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
  f.box_min = f.p_L[0].head<2>().cwiseMin(f.p_L[1].head<2>()).cwiseMin(f.p_L[2].head<2>());
  f.box_max = f.p_L[0].head<2>().cwiseMax(f.p_L[1].head<2>()).cwiseMax(f.p_L[2].head<2>());
  {
    const Eigen::Vector2d a = f.p_L[0].head<2>(), b = f.p_L[1].head<2>(), c = f.p_L[2].head<2>();
    f.projected_det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  }
  f.min_z = std::min({f.p_L[0].z(), f.p_L[1].z(), f.p_L[2].z()});
  f.max_z = std::max({f.p_L[0].z(), f.p_L[1].z(), f.p_L[2].z()});
  f.rays = input.rays;
  f.front_crossings = input.front_crossings;
  f.back_crossings = input.back_crossings;
  f.back_depth_W = input.back_depth;
  f.back_depth_m = input.back_depth * metres_per_unit_;
  f.view_sides = input.view_sides;
  f.driven_vertices = input.driven_vertices;
  f.underside_vertices = input.underside_vertices;
  f.steiner = input.touches_steiner;
  for (const auto& v : input.vertices) f.steiner = f.steiner || v.steiner;
  f.alive = true;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  bounds_[s] = FaceBounds{f.box_min, f.box_max, f.normal_L.z(), true,
                          std::nextafter(static_cast<float>(f.min_z), -kInf),
                          std::nextafter(static_cast<float>(f.max_z), kInf)};
  SampleGeometry& g = geometry_[s];
  g = SampleGeometry{};
  g.box_min = f.box_min;
  g.box_max = f.box_max;
  g.x0 = f.p_L[0].x();
  g.y0 = f.p_L[0].y();
  g.bx = f.p_L[1].x() - g.x0;
  g.by = f.p_L[1].y() - g.y0;
  g.cx = f.p_L[2].x() - g.x0;
  g.cy = f.p_L[2].y() - g.y0;
  g.z0 = f.p_L[0].z();
  g.z1 = f.p_L[1].z();
  g.z2 = f.p_L[2].z();
  g.min_z = f.min_z;
  g.max_z = f.max_z;
  g.normal_z = f.normal_L.z();
  g.normal_xy = f.normal_L.head<2>();
  g.steiner = f.steiner;
  g.touches_driven = f.driven_vertices > 0;
  g.driven = f.driven_vertices == 3 && !f.steiner;
  g.span_m = std::sqrt(std::max({(f.p_L[1] - f.p_L[0]).head<2>().squaredNorm(), (f.p_L[2] - f.p_L[1]).head<2>().squaredNorm(),
                                 (f.p_L[0] - f.p_L[2]).head<2>().squaredNorm()}));
  // heightAt: u = ((b - q) x (c - q)) / det, v = ((c - q) x (a - q)) / det, relative to a.
  const double det = g.bx * g.cy - g.cx * g.by;
  g.sampleable = std::abs(det) >= 1e-12 && std::abs(f.projected_det) >= 1e-12;
  if (g.sampleable) {
    g.ux = (g.by - g.cy) / det;
    g.uy = (g.cx - g.bx) / det;
    g.vx = g.cy / det;
    g.vy = -g.cx / det;
  }
  by_key_[f.key] = s;
  link(s);
  return s;
}

bool SurfaceStore::remove(const mesher::FaceKey& key) {
  const auto it = by_key_.find(key);
  if (it == by_key_.end()) return false;
  const Slot s = it->second;
  by_key_.erase(it);
  release(s);
  return true;
}

void SurfaceStore::removeSlot(Slot s) {
  by_key_.erase(faces_[s].key);
  release(s);
}

void SurfaceStore::release(Slot s) {
  unlink(s);
  faces_[s].alive = false;
  bounds_[s].alive = false;
  geometry_[s].sampleable = false;
  free_slots_.push_back(s);
}

void SurfaceStore::clear() {
  faces_.clear();
  bounds_.clear();
  geometry_.clear();
  centroids_.clear();
  free_slots_.clear();
  by_key_.clear();
  by_vertex_.clear();
  grid_.clear();
  centroid_grid_.clear();
}

std::optional<Slot> SurfaceStore::find(const mesher::FaceKey& key) const {
  const auto it = by_key_.find(key);
  if (it == by_key_.end()) return std::nullopt;
  return it->second;
}

void SurfaceStore::link(Slot s) {
  const StoredFace& f = faces_[s];
  for (const auto& v : f.vertices) by_vertex_[v].push_back(s);
  const std::int64_t i0 = cellIndex(f.box_min.x()), j0 = cellIndex(f.box_min.y());
  for (std::int64_t i = i0; i <= cellIndex(f.box_max.x()); ++i) {
    for (std::int64_t j = j0; j <= cellIndex(f.box_max.y()); ++j) {
      grid_[cellKey(i, j)].push_back(s | (i == i0 ? 0u : kNotFirstColumn) | (j == j0 ? 0u : kNotFirstRow));
    }
  }
  centroid_grid_[centroidCellKey(f.centroid_L)].push_back(s);
}

void SurfaceStore::unlink(Slot s) {
  const StoredFace& f = faces_[s];
  const auto erase = [s](std::vector<Slot>& list) {
    const auto it = std::find(list.begin(), list.end(), s);
    if (it != list.end()) {
      *it = list.back();
      list.pop_back();
    }
  };
  const auto eraseEntry = [s](std::vector<GridEntry>& list) {
    const auto it = std::find_if(list.begin(), list.end(), [s](GridEntry e) { return (e & kSlotMask) == s; });
    if (it != list.end()) {
      *it = list.back();
      list.pop_back();
    }
  };
  for (const auto& v : f.vertices) {
    const auto it = by_vertex_.find(v);
    if (it == by_vertex_.end()) continue;
    erase(it.value());
    if (it->second.empty()) by_vertex_.erase(it);
  }
  for (std::int64_t i = cellIndex(f.box_min.x()); i <= cellIndex(f.box_max.x()); ++i) {
    for (std::int64_t j = cellIndex(f.box_min.y()); j <= cellIndex(f.box_max.y()); ++j) {
      const auto it = grid_.find(cellKey(i, j));
      if (it == grid_.end()) continue;
      eraseEntry(it.value());
      // Empty cells go: the grid holds the faces' area, not every cell they ever covered.
      if (it->second.empty()) grid_.erase(it);
    }
  }
  const auto it = centroid_grid_.find(centroidCellKey(f.centroid_L));
  if (it == centroid_grid_.end()) return;
  erase(it.value());
  if (it->second.empty()) centroid_grid_.erase(it);
}

void SurfaceStore::neighbours(Slot s, std::vector<Slot>& out) const {
  out.clear();
  const StoredFace& f = faces_[s];
  for (int e = 0; e < 3; ++e) {
    const mesher::VertexKey& a = f.vertices[e];
    const mesher::VertexKey& b = f.vertices[(e + 1) % 3];
    const auto it = by_vertex_.find(a);
    if (it == by_vertex_.end()) continue;
    for (Slot t : it->second) {
      if (t == s) continue;
      const auto& tv = faces_[t].vertices;
      if (std::find(tv.begin(), tv.end(), b) != tv.end() &&
          std::find(out.begin(), out.end(), t) == out.end()) {
        out.push_back(t);
      }
    }
  }
}

}  // namespace terramesh::traversability::internal
