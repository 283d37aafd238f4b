#include "baselines/octomap_baseline.h"

#include "common/atomic_file.h"
#include "common/plan_frame.h"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <limits>
#include <octomap/OcTree.h>
#include <sstream>
#include <stdexcept>

namespace terramesh::baselines {

void OctomapConfig::validate() const {
  std::ostringstream problems;
  if (!(resolution_m > 0) || !std::isfinite(resolution_m)) problems << " resolution_m: " << resolution_m << " (expected > 0);";
  if (!std::isfinite(max_range_m)) problems << " max_range_m: " << max_range_m << " (expected finite; <= 0 for none);";
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    problems << " metres_per_unit: " << metres_per_unit << " (expected > 0);";
  }
  if (!up_W.allFinite() || up_W.norm() == 0) problems << " up_W: not a non-zero finite vector;";
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("OctomapConfig:" + text);
}

struct OctomapBaseline::Impl {
  explicit Impl(const OctomapConfig& c)
      : config(c),
        tree(c.resolution_m),
        R_G_W(geometry::rotationUpToZ(c.up_W)) {}
  octomap::point3d toG(const Eigen::Vector3d& p_W) const {
    const Eigen::Vector3d p = R_G_W * p_W * config.metres_per_unit;
    return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
  }
  OctomapConfig config;
  octomap::OcTree tree;
  Eigen::Matrix3d R_G_W;
  OctomapStats stats;
};

OctomapBaseline::OctomapBaseline(const OctomapConfig& config) {
  config.validate();
  impl_ = std::make_unique<Impl>(config);
}
OctomapBaseline::~OctomapBaseline() = default;
OctomapBaseline::OctomapBaseline(OctomapBaseline&&) noexcept = default;
OctomapBaseline& OctomapBaseline::operator=(OctomapBaseline&&) noexcept = default;

void OctomapBaseline::insertKeyframe(const mesher::Keyframe& keyframe) {
  const auto started = std::chrono::steady_clock::now();
  octomap::Pointcloud cloud;
  cloud.reserve(keyframe.observations.size());
  for (const mesher::PointObservation& observation : keyframe.observations) {
    if (observation.position_W.allFinite()) cloud.push_back(impl_->toG(observation.position_W));
  }
  impl_->tree.insertPointCloud(cloud, impl_->toG(keyframe.position_W_C), impl_->config.max_range_m);
  impl_->stats.keyframes += 1;
  impl_->stats.points += cloud.size();
  impl_->stats.build_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

void OctomapBaseline::writeBinary(const std::filesystem::path& path) const {
  // Atomically (temporary file + rename): an interrupted write leaves the previous .bt whole.
  writeFileAtomically(path, [this, &path](std::ostream& out) {
    if (!impl_->tree.writeBinaryConst(out)) throw std::runtime_error("cannot write " + path.string());
  });
}

OctomapStats OctomapBaseline::stats() const {
  OctomapStats stats = impl_->stats;
  stats.memory_bytes = impl_->tree.memoryUsage();
  stats.leaves = impl_->tree.getNumLeafNodes();
  for (auto it = impl_->tree.begin_leafs(); it != impl_->tree.end_leafs(); ++it) {
    if (impl_->tree.isNodeOccupied(*it)) ++stats.occupied_leaves;
  }
  return stats;
}

HeightGrid OctomapBaseline::heightGrid(const GridRobotConfig& robot) const {
  const octomap::OcTree& tree = impl_->tree;
  const double res = impl_->config.resolution_m;
  HeightGrid grid;
  grid.resolution_m = res;
  grid.R_G_W = impl_->R_G_W;
  grid.metres_per_unit = impl_->config.metres_per_unit;
  if (tree.size() == 0) {
    grid.classify(robot);
    return grid;
  }
  double min_x, min_y, min_z, max_x, max_y, max_z;
  tree.getMetricMin(min_x, min_y, min_z);
  tree.getMetricMax(max_x, max_y, max_z);
  const int nx = static_cast<int>(std::ceil((max_x - min_x) / res)) + 1;
  const int ny = static_cast<int>(std::ceil((max_y - min_y) / res)) + 1;
  const int nz = static_cast<int>(std::ceil((max_z - min_z) / res)) + 1;
  // Voxel states: 0 unknown, 1 free, 2 occupied.
  std::vector<std::uint8_t> state(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz), 0);
  auto at = [&](int i, int j, int k) {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(ny) + static_cast<std::size_t>(j)) * static_cast<std::size_t>(nx) +
           static_cast<std::size_t>(i);
  };
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    const std::uint8_t value = tree.isNodeOccupied(*it) ? 2 : 1;
    const double size = it.getSize();
    const int cells = std::max(1, static_cast<int>(std::lround(size / res)));
    const double x0 = it.getX() - size / 2 + res / 2, y0 = it.getY() - size / 2 + res / 2, z0 = it.getZ() - size / 2 + res / 2;
    for (int a = 0; a < cells; ++a) {
      for (int b = 0; b < cells; ++b) {
        for (int c = 0; c < cells; ++c) {
          const int i = static_cast<int>(std::floor((x0 + a * res - min_x) / res));
          const int j = static_cast<int>(std::floor((y0 + b * res - min_y) / res));
          const int k = static_cast<int>(std::floor((z0 + c * res - min_z) / res));
          if (i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz) state[at(i, j, k)] = value;
        }
      }
    }
  }
  grid.origin_x_m = min_x;
  grid.origin_y_m = min_y;
  grid.width = nx;
  grid.height = ny;
  const std::size_t n = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  grid.ground_z_m.assign(n, std::numeric_limits<float>::quiet_NaN());
  grid.clearance_m.assign(n, std::numeric_limits<float>::infinity());
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      for (int k = nz - 2; k >= 0; --k) {
        if (state[at(i, j, k)] != 2 || state[at(i, j, k + 1)] != 1) continue;
        grid.ground_z_m[grid.index(i, j)] = static_cast<float>(min_z + (k + 1) * res);
        for (int above = k + 2; above < nz; ++above) {
          if (state[at(i, j, above)] == 2) {
            grid.clearance_m[grid.index(i, j)] = static_cast<float>((above - k - 1) * res);
            break;
          }
        }
        break;
      }
    }
  }
  grid.classify(robot);
  return grid;
}

}  // namespace terramesh::baselines
