#pragma once
// The SLAM points the mesher has not inserted (mesher::Mesher::unconfirmedPoints), in the layers'
// frame L, indexed in the horizontal plane: possible obstacles for the faces around them. Internal.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ground_frame.h"
#include "mesher/mesher.h"
#include "surface_store.h"

namespace terramesh::traversability::internal {

class UnconfirmedPoints {
 public:
  /// @param R_L_W rotation taking map-frame directions to L (up_W -> +z); @param cell_m the
  /// horizontal grid cell (metres, > 0).
  UnconfirmedPoints(const Eigen::Matrix3d& R_L_W, double metres_per_unit, double cell_m);

  /// Replaces the set by `points` (map frame). Appends to `changed_L` the positions (L) of the
  /// points added and removed, and both positions of those that moved. O(old + new size).
  void replace(const std::vector<mesher::UnconfirmedPoint>& points, std::vector<Eigen::Vector3d>& changed_L);
  /// Applies the changes of mesher::Mesher::unconfirmedChangesSince (complete): the same set, and
  /// the same positions appended to `changed_L`, as replace() with the whole new set would give.
  /// O(changes).
  void apply(const mesher::UnconfirmedChanges& changes, std::vector<Eigen::Vector3d>& changed_L);

  /// Calls `visit(p_L)` for every point (at least) whose horizontal position lies in the box
  /// [lo, hi] (L): the points of the grid cells it overlaps, or all of them when that is cheaper.
  template <class Visit>
  void forEachInBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, Visit visit) const {
    if (points_.empty()) return;
    const bool done = grid_.inBox(lo, hi, points_.size(), [&](const Entry& entry) { visit(entry.p_L); });
    if (done) return;
    for (const auto& entry : points_) visit(entry.second);
  }

  std::size_t size() const { return points_.size(); }

 private:
  Eigen::Matrix3d R_L_W_;
  double metres_per_unit_;
  /// A point as the grid lists it: with its position, so that a box query reads no map.
  struct Entry {
    std::uint64_t id = 0;
    Eigen::Vector3d p_L = Eigen::Vector3d::Zero();
    bool operator==(const Entry& other) const { return id == other.id; }
  };
  /// A mesher position (map frame, map units) in L.
  Eigen::Vector3d toL(const Eigen::Vector3d& position_W) const { return R_L_W_ * (position_W * metres_per_unit_); }

  HashMap<std::uint64_t, Eigen::Vector3d> points_;
  HorizontalGrid<Entry> grid_;
};

}  // namespace terramesh::traversability::internal
