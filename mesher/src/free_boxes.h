#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "grid_key.h"
#include "mesher/keyframe.h"

namespace terramesh::mesher::internal {

/// Whether a tetrahedron and an oriented box (closed sets) meet: the separating axis test over the
/// box's three axes, the tetrahedron's four face normals and the cross products of their edges.
/// `tet_B` are the tetrahedron's corners in the box's frame, `half` the box's half extents.
bool tetrahedronMeetsBox(const std::array<Eigen::Vector3d, 4>& tet_B, const Eigen::Vector3d& half);

/// Whether the tetrahedron with corners `tet_W` (world frame) meets `box` with its centroid above
/// the box's floor (box-frame z >= -half z): what frees a cell (FreeBoxIndex::meets). A cell mostly
/// under the ground that reaches the floor only with a noisy point stays.
bool tetrahedronMeetsFreeBox(const std::array<Eigen::Vector3d, 4>& tet_W, const FreeBox& box);

/// The free boxes of the keyframes (Keyframe::free_boxes), indexed by the cubes of a regular grid
/// that their bounding boxes overlap, to tell whether a cell meets one of them.
class FreeBoxIndex {
 public:
  /// `cube_units`: the edge of the index's cubes (map units, > 0).
  explicit FreeBoxIndex(double cube_units) : cube_(cube_units) {}

  /// Replaces the boxes of keyframe `keyframe` (a PointRegistry index).
  void set(std::uint32_t keyframe, const std::vector<FreeBox>& boxes);
  void erase(std::uint32_t keyframe) { set(keyframe, {}); }
  /// The boxes of keyframe `keyframe`, in the order set() was given them (empty if none).
  std::vector<FreeBox> of(std::uint32_t keyframe) const;
  /// The keyframes with boxes, ascending.
  std::vector<std::uint32_t> keyframes() const;
  bool empty() const { return live_ == 0; }
  /// Whether the tetrahedron with these corners (world frame) meets one of the boxes with its
  /// centroid above that box's floor.
  bool meets(const std::array<Eigen::Vector3d, 4>& tet_W) const;
  /// The box's centre and its eight corners: the positions whose neighbourhood a change of this
  /// box affects (the shrink region around them reaches enclosing_radius_cells Steiner cells, far
  /// beyond any body's box).
  static std::vector<Eigen::Vector3d> coverage(const FreeBox& box);

 private:
  struct Entry {
    FreeBox box;
    Eigen::Matrix3d R_B_W = Eigen::Matrix3d::Identity();
    Eigen::Vector3d lo_W = Eigen::Vector3d::Zero(), hi_W = Eigen::Vector3d::Zero();
    std::uint32_t keyframe = 0;
  };
  GridKey keyOf(const Eigen::Vector3d& p) const;
  template <class F>
  void forEachCube(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f) const;

  double cube_;
  std::vector<Entry> entries_;
  std::vector<std::uint32_t> free_slots_;
  std::size_t live_ = 0;
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> by_keyframe_;
  std::unordered_map<GridKey, std::vector<std::uint32_t>, GridKeyHash> cubes_;
  Eigen::Vector3d lo_W_ = Eigen::Vector3d::Constant(1), hi_W_ = Eigen::Vector3d::Constant(-1);
};

}  // namespace terramesh::mesher::internal
