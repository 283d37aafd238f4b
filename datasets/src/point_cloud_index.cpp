#include "datasets/point_cloud_index.h"

#include <nanoflann.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace terramesh::datasets {
namespace {

/// The dataset interface nanoflann reads the points through.
struct Cloud {
  std::vector<Eigen::Vector3d> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const {
    return points[index][static_cast<Eigen::Index>(dim)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box& /*box*/) const {
    return false;  // nanoflann computes it
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, std::uint32_t>;

/// nanoflann result set for the nearest point within a radius: the radius bounds the search from
/// the start (nanoflann 1.4's KNN result set has no radius; its radius set collects every point).
class NearestWithin {
 public:
  explicit NearestWithin(double max_squared) : worst_(max_squared) {}
  std::size_t size() const { return found_ ? 1 : 0; }
  bool full() const { return true; }  // worstDist() is the bound from the start
  bool addPoint(double squared, std::uint32_t index) {
    if (squared < worst_) {
      worst_ = squared;
      index_ = index;
      found_ = true;
    }
    return true;
  }
  double worstDist() const { return worst_; }
  bool found() const { return found_; }
  std::uint32_t index() const { return index_; }

 private:
  double worst_;
  std::uint32_t index_ = 0;
  bool found_ = false;
};

}  // namespace

struct PointCloudIndex::Impl {
  Cloud cloud;
  std::unique_ptr<KdTree> tree;  ///< reads `cloud`: Impl never moves once built
};

PointCloudIndex::PointCloudIndex(std::vector<Eigen::Vector3d> points) : impl_(std::make_unique<Impl>()) {
  if (points.size() >= std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument("PointCloudIndex: more than 2^32 - 1 points");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) throw std::invalid_argument("PointCloudIndex: point " + std::to_string(i) + " is not finite");
  }
  impl_->cloud.points = std::move(points);
  impl_->tree = std::make_unique<KdTree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  impl_->tree->buildIndex();
}

PointCloudIndex::~PointCloudIndex() = default;
PointCloudIndex::PointCloudIndex(PointCloudIndex&&) noexcept = default;
PointCloudIndex& PointCloudIndex::operator=(PointCloudIndex&&) noexcept = default;

const std::vector<Eigen::Vector3d>& PointCloudIndex::points() const { return impl_->cloud.points; }

std::optional<PointCloudIndex::Nearest> PointCloudIndex::nearest(const Eigen::Vector3d& query,
                                                                 double max_distance_m) const {
  if (impl_->cloud.points.empty() || !(max_distance_m >= 0.0)) return std::nullopt;
  // Search a hair beyond the radius (squaring rounds); the exact distance decides below.
  const double bound = max_distance_m * (1.0 + 1e-12);
  NearestWithin result(std::isfinite(bound) ? bound * bound : std::numeric_limits<double>::infinity());
  impl_->tree->findNeighbors(result, query.data(), nanoflann::SearchParams());
  if (!result.found()) return std::nullopt;
  const double distance = (impl_->cloud.points[result.index()] - query).norm();
  if (distance > max_distance_m) return std::nullopt;
  return Nearest{result.index(), distance};
}

}  // namespace terramesh::datasets
