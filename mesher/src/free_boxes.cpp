#include "free_boxes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "map_state.h"

namespace terramesh::mesher::internal {
namespace {

/// Whether `axis` separates the tetrahedron from the box centred at the origin with half extents
/// `half` (both in the box's frame). A degenerate axis separates nothing.
bool separates(const std::array<Eigen::Vector3d, 4>& tet, const Eigen::Vector3d& half,
               const Eigen::Vector3d& axis, double tiny) {
  if (!(axis.squaredNorm() > tiny)) return false;
  const double reach = half.dot(axis.cwiseAbs());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Eigen::Vector3d& p : tet) {
    const double d = axis.dot(p);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return lo > reach || hi < -reach;
}

}  // namespace

bool tetrahedronMeetsBox(const std::array<Eigen::Vector3d, 4>& tet, const Eigen::Vector3d& half) {
  double scale = half.maxCoeff();
  for (int a = 0; a < 3; ++a) {
    double lo = tet[0][a], hi = tet[0][a];
    for (int i = 1; i < 4; ++i) {
      lo = std::min(lo, tet[static_cast<std::size_t>(i)][a]);
      hi = std::max(hi, tet[static_cast<std::size_t>(i)][a]);
    }
    if (lo > half[a] || hi < -half[a]) return false;
    scale = std::max({scale, std::abs(lo), std::abs(hi)});
  }
  const double tiny = 1e-24 * scale * scale * scale * scale;
  constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  for (const auto& f : kFaces) {
    const Eigen::Vector3d& a = tet[static_cast<std::size_t>(f[0])];
    const Eigen::Vector3d normal =
        (tet[static_cast<std::size_t>(f[1])] - a).cross(tet[static_cast<std::size_t>(f[2])] - a);
    if (separates(tet, half, normal, tiny)) return false;
  }
  constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (const auto& e : kEdges) {
    const Eigen::Vector3d edge =
        tet[static_cast<std::size_t>(e[1])] - tet[static_cast<std::size_t>(e[0])];
    for (int a = 0; a < 3; ++a) {
      if (separates(tet, half, edge.cross(Eigen::Vector3d::Unit(a)), tiny)) return false;
    }
  }
  return true;
}

/// Whether the tetrahedron meets the box with its centroid above the box's floor (its lowest
/// face, box-frame z = -half z): a cell mostly under the ground that reaches the floor only with
/// a noisy point stays.
static bool meetsAboveFloor(const std::array<Eigen::Vector3d, 4>& tet_W, const FreeBox& box,
                            const Eigen::Matrix3d& R_B_W) {
  std::array<Eigen::Vector3d, 4> tet_B;
  double centroid_z = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    tet_B[i] = R_B_W * (tet_W[i] - box.centre_W);
    centroid_z += 0.25 * tet_B[i].z();
  }
  return centroid_z >= -box.half_extents.z() && tetrahedronMeetsBox(tet_B, box.half_extents);
}

bool tetrahedronMeetsFreeBox(const std::array<Eigen::Vector3d, 4>& tet_W, const FreeBox& box) {
  return meetsAboveFloor(tet_W, box, box.rotation_W_B.normalized().toRotationMatrix().transpose());
}

void addFreeBoxCandidates(MapState& state, const std::vector<FreeBox>& boxes) {
  std::vector<CellHandle> stack;
  for (const FreeBox& box : boxes) {
    const Eigen::Matrix3d R_B_W = box.rotation_W_B.normalized().toRotationMatrix().transpose();
    const std::uint32_t mark = state.nextMark();
    const CellHandle start = state.tri.locate(toPoint(box.centre_W));
    if (start == CellHandle() || state.tri.is_infinite(start)) continue;
    start->info().mark = mark;
    stack.assign(1, start);
    while (!stack.empty()) {
      const CellHandle cell = stack.back();
      stack.pop_back();
      if (!meetsAboveFloor(state.corners(cell), box, R_B_W)) continue;
      if (!cell->info().outside()) state.candidates.add(cell);
      for (int i = 0; i < 4; ++i) {
        const CellHandle next = cell->neighbor(i);
        if (next->info().mark == mark || state.tri.is_infinite(next)) continue;
        next->info().mark = mark;
        stack.push_back(next);
      }
    }
  }
}

GridKey FreeBoxIndex::keyOf(const Eigen::Vector3d& p) const {
  return {static_cast<std::int32_t>(std::floor(p.x() / cube_)),
          static_cast<std::int32_t>(std::floor(p.y() / cube_)),
          static_cast<std::int32_t>(std::floor(p.z() / cube_))};
}

template <class F>
void FreeBoxIndex::forEachCube(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f) const {
  const GridKey a = keyOf(lo), b = keyOf(hi);
  for (std::int32_t i = a.i; i <= b.i; ++i) {
    for (std::int32_t j = a.j; j <= b.j; ++j) {
      for (std::int32_t k = a.k; k <= b.k; ++k) f(GridKey{i, j, k});
    }
  }
}

void FreeBoxIndex::set(std::uint32_t keyframe, const std::vector<FreeBox>& boxes) {
  const auto known = by_keyframe_.find(keyframe);
  if (known != by_keyframe_.end()) {
    for (std::uint32_t slot : known->second) {
      const Entry& entry = entries_[slot];
      forEachCube(entry.lo_W, entry.hi_W, [&](const GridKey& key) {
        const auto cube = cubes_.find(key);
        if (cube == cubes_.end()) return;
        cube->second.erase(std::remove(cube->second.begin(), cube->second.end(), slot),
                           cube->second.end());
        if (cube->second.empty()) cubes_.erase(cube);
      });
      free_slots_.push_back(slot);
      --live_;
    }
    by_keyframe_.erase(known);
  }
  if (boxes.empty()) return;
  std::vector<std::uint32_t>& slots = by_keyframe_[keyframe];
  for (const FreeBox& box : boxes) {
    Entry entry;
    entry.box = box;
    entry.keyframe = keyframe;
    const Eigen::Matrix3d R_W_B = box.rotation_W_B.normalized().toRotationMatrix();
    entry.R_B_W = R_W_B.transpose();
    const Eigen::Vector3d reach = R_W_B.cwiseAbs() * box.half_extents;
    entry.lo_W = box.centre_W - reach;
    entry.hi_W = box.centre_W + reach;
    if (live_ == 0 && entries_.size() == free_slots_.size()) {
      lo_W_ = entry.lo_W;
      hi_W_ = entry.hi_W;
    }
    lo_W_ = lo_W_.cwiseMin(entry.lo_W);
    hi_W_ = hi_W_.cwiseMax(entry.hi_W);
    std::uint32_t slot;
    if (free_slots_.empty()) {
      slot = static_cast<std::uint32_t>(entries_.size());
      entries_.push_back(entry);
    } else {
      slot = free_slots_.back();
      free_slots_.pop_back();
      entries_[slot] = entry;
    }
    forEachCube(entry.lo_W, entry.hi_W, [&](const GridKey& key) { cubes_[key].push_back(slot); });
    slots.push_back(slot);
    ++live_;
  }
}

std::vector<FreeBox> FreeBoxIndex::of(std::uint32_t keyframe) const {
  std::vector<FreeBox> boxes;
  const auto known = by_keyframe_.find(keyframe);
  if (known == by_keyframe_.end()) return boxes;
  for (std::uint32_t slot : known->second) boxes.push_back(entries_[slot].box);
  return boxes;
}

std::vector<std::uint32_t> FreeBoxIndex::keyframes() const {
  std::vector<std::uint32_t> keys;
  keys.reserve(by_keyframe_.size());
  for (const auto& entry : by_keyframe_) keys.push_back(entry.first);
  std::sort(keys.begin(), keys.end());
  return keys;
}

bool FreeBoxIndex::meets(const std::array<Eigen::Vector3d, 4>& tet_W) const {
  if (live_ == 0) return false;
  Eigen::Vector3d lo = tet_W[0], hi = tet_W[0];
  for (const Eigen::Vector3d& p : tet_W) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if ((lo.array() > hi_W_.array()).any() || (hi.array() < lo_W_.array()).any()) return false;
  lo = lo.cwiseMax(lo_W_);
  hi = hi.cwiseMin(hi_W_);
  const auto test = [&](std::uint32_t slot) {
    const Entry& entry = entries_[slot];
    if ((lo.array() > entry.hi_W.array()).any() || (hi.array() < entry.lo_W.array()).any())
      return false;
    return meetsAboveFloor(tet_W, entry.box, entry.R_B_W);
  };
  const GridKey a = keyOf(lo), b = keyOf(hi);
  const double cubes = (static_cast<double>(b.i) - a.i + 1) * (static_cast<double>(b.j) - a.j + 1) *
                       (static_cast<double>(b.k) - a.k + 1);
  if (cubes > static_cast<double>(cubes_.size())) {
    // A cell larger than the indexed region: every box, once.
    for (const auto& [keyframe, slots] : by_keyframe_) {
      for (std::uint32_t slot : slots) {
        if (test(slot)) return true;
      }
    }
    return false;
  }
  bool found = false;
  forEachCube(lo, hi, [&](const GridKey& key) {
    if (found) return;
    const auto cube = cubes_.find(key);
    if (cube == cubes_.end()) return;
    for (std::uint32_t slot : cube->second) {
      if (test(slot)) {
        found = true;
        return;
      }
    }
  });
  return found;
}

std::vector<Eigen::Vector3d> FreeBoxIndex::coverage(const FreeBox& box) {
  const Eigen::Matrix3d R_W_B = box.rotation_W_B.normalized().toRotationMatrix();
  std::vector<Eigen::Vector3d> points{box.centre_W};
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d sign((corner & 1) ? 1.0 : -1.0, (corner & 2) ? 1.0 : -1.0,
                               (corner & 4) ? 1.0 : -1.0);
    points.push_back(box.centre_W + R_W_B * sign.cwiseProduct(box.half_extents));
  }
  return points;
}

}  // namespace terramesh::mesher::internal
