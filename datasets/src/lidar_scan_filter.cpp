#include "datasets/lidar_scan_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/grid_key.h"

namespace terramesh::datasets {

LidarScanOptions LidarScanOptions::everyReturn() {
  LidarScanOptions options;
  options.max_range_m = std::numeric_limits<double>::infinity();
  options.voxel_size_m = 0.0;
  options.max_views_per_point = 0;
  return options;
}

std::vector<std::string> LidarScanOptions::problems() const {
  std::vector<std::string> found;
  if (!(min_range_m >= 0) || !std::isfinite(min_range_m)) {
    found.push_back("min_range_m must be a finite number >= 0");
  }
  if (!(max_range_m > min_range_m)) found.push_back("max_range_m must exceed min_range_m");
  if (!(voxel_size_m >= 0) || !std::isfinite(voxel_size_m)) {
    found.push_back("voxel_size_m must be a finite number >= 0 (0: off)");
  }
  return found;
}

LidarScanFilter::LidarScanFilter(const LidarScanOptions& options) : options_(options) {
  if (const std::vector<std::string> problems = options.problems(); !problems.empty()) {
    std::string message = "LidarScanFilter: invalid options:";
    for (const std::string& problem : problems) message += " " + problem + ";";
    message.pop_back();
    throw std::invalid_argument(message);
  }
}

std::vector<LidarScanFilter::Candidate> LidarScanFilter::nearestInVoxels(
    const mesher::Keyframe& scan) {
  const double size = options_.voxel_size_m;
  std::vector<Candidate> candidates;
  scratch_.clear();
  for (std::size_t index = 0; index < scan.observations.size(); ++index) {
    const Eigen::Vector3d& p = scan.observations[index].position_W;
    const geometry::CellKey3 cell = geometry::cellOf(p, size);
    const Eigen::Vector3d centre =
        (Eigen::Vector3d(static_cast<double>(cell.i), static_cast<double>(cell.j),
                         static_cast<double>(cell.k)) +
         Eigen::Vector3d::Constant(0.5)) *
        size;
    // By the voxel's centre: a merged view sits at its point, not at the return, and must get
    // the decision its return got (so that filtering again changes nothing).
    if (!options_.inRange((centre - scan.position_W_C).squaredNorm())) {
      ++counts_.out_of_range;
      continue;
    }
    if (!geometry::fitsPackCell3(cell.i, cell.j, cell.k)) {
      throw std::out_of_range("LidarScanFilter: a return at (" + std::to_string(p.x()) + ", " +
                              std::to_string(p.y()) + ", " + std::to_string(p.z()) +
                              ") lies more than 2^20 voxels of " + std::to_string(size) +
                              " m from the world origin (use larger voxels or a range limit)");
    }
    const Candidate candidate{geometry::packCell3(cell.i, cell.j, cell.k), index,
                              (p - centre).squaredNorm()};
    const auto [slot, inserted] = scratch_.try_emplace(candidate.key, candidates.size());
    if (inserted) {
      candidates.push_back(candidate);
      continue;
    }
    ++counts_.same_voxel;
    // Strictly nearer: of equally near returns the first stays, whatever the reader.
    Candidate& best = candidates[slot->second];
    if (candidate.centre_distance_sq < best.centre_distance_sq) best = candidate;
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.index < b.index; });
  return candidates;
}

void LidarScanFilter::filter(mesher::Keyframe& scan) {
  ++counts_.scans;
  counts_.returns += scan.observations.size();
  std::vector<mesher::PointObservation> kept;
  if (options_.voxel_size_m <= 0) {
    for (const mesher::PointObservation& observation : scan.observations) {
      if (options_.inRange((observation.position_W - scan.position_W_C).squaredNorm())) {
        kept.push_back(observation);
      } else {
        ++counts_.out_of_range;
      }
    }
    counts_.new_points += kept.size();
    scan.observations = std::move(kept);
    return;
  }
  const std::vector<Candidate> candidates = nearestInVoxels(scan);
  kept.reserve(candidates.size());
  for (const Candidate& candidate : candidates) {
    const mesher::PointObservation& observation = scan.observations[candidate.index];
    const auto [slot, inserted] =
        points_.try_emplace(candidate.key, VoxelPoint{observation.position_W, 0});
    VoxelPoint& point = slot->second;
    if (!inserted && options_.max_views_per_point > 0 &&
        point.views >= options_.max_views_per_point) {
      ++counts_.over_view_cap;
      continue;
    }
    ++point.views;
    ++(inserted ? counts_.new_points : counts_.merged_views);
    kept.push_back({mesher::PointId{candidate.key}, point.position_W, observation.kind});
  }
  scan.observations = std::move(kept);
}

std::string LidarScanFilter::describe() const {
  std::ostringstream text;
  text << "LiDAR returns " << options_.min_range_m << "-" << options_.max_range_m
       << " m from the sensor";
  if (options_.voxel_size_m > 0) {
    text << ", one per " << options_.voxel_size_m
         << " m voxel and scan (the return nearest its centre), merged across scans into the "
            "voxel's point";
    if (options_.max_views_per_point > 0)
      text << " (at most " << options_.max_views_per_point << " views each)";
  } else {
    text << ", every return its own point";
  }
  const LidarScanCounts& c = counts_;
  text << ": " << c.returns << " returns of " << c.scans << " scans -> " << c.observations()
       << " observations (" << c.new_points << " new points, " << c.merged_views
       << " views of earlier points; dropped " << c.out_of_range << " out of range";
  if (options_.voxel_size_m > 0) {
    text << ", " << c.same_voxel << " sharing a voxel, " << c.over_view_cap << " over the view cap";
  }
  text << ")";
  return text.str();
}

}  // namespace terramesh::datasets
