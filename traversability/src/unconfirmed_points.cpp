#include "unconfirmed_points.h"

namespace terramesh::traversability::internal {

UnconfirmedPoints::UnconfirmedPoints(const Eigen::Matrix3d& R_L_W, double metres_per_unit, double cell_m)
    : R_L_W_(R_L_W), metres_per_unit_(metres_per_unit), grid_(cell_m) {}

void UnconfirmedPoints::replace(const std::vector<mesher::UnconfirmedPoint>& points,
                                std::vector<Eigen::Vector3d>& changed_L) {
  HashMap<std::uint64_t, Eigen::Vector3d> next;
  next.reserve(points.size());
  for (const mesher::UnconfirmedPoint& point : points) {
    const Eigen::Vector3d p_L = toL(point.position_W);
    if (!p_L.allFinite()) continue;
    next.emplace(point.id.value, p_L);
  }
  for (const auto& [id, p_L] : points_) {
    const auto it = next.find(id);
    if (it != next.end() && it->second == p_L) continue;
    changed_L.push_back(p_L);  // removed, or moved away from here
    grid_.erase(p_L.head<2>(), Entry{id, p_L});
  }
  for (const auto& [id, p_L] : next) {
    const auto it = points_.find(id);
    if (it != points_.end() && it->second == p_L) continue;
    changed_L.push_back(p_L);  // added, or moved here
    grid_.add(p_L.head<2>(), Entry{id, p_L});
  }
  points_ = std::move(next);
}

void UnconfirmedPoints::apply(const mesher::UnconfirmedChanges& changes, std::vector<Eigen::Vector3d>& changed_L) {
  const auto remove = [&](std::uint64_t id) {
    const auto it = points_.find(id);
    if (it == points_.end()) return;
    changed_L.push_back(it->second);  // removed, or moved away from here
    grid_.erase(it->second.head<2>(), Entry{id, it->second});
    points_.erase(it);
  };
  for (const mesher::PointId id : changes.gone) remove(id.value);
  for (const mesher::UnconfirmedPoint& point : changes.waiting) {
    const Eigen::Vector3d p_L = toL(point.position_W);
    const auto it = points_.find(point.id.value);
    if (it != points_.end() && p_L.allFinite() && it->second == p_L) continue;
    remove(point.id.value);
    if (!p_L.allFinite()) continue;
    changed_L.push_back(p_L);  // added, or moved here
    grid_.add(p_L.head<2>(), Entry{point.id.value, p_L});
    points_.emplace(point.id.value, p_L);
  }
}

}  // namespace terramesh::traversability::internal
