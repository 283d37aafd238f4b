#pragma once

// What the benchmarks share: the streams they mesh (the built-in KITTI-like street or a stream
// file), thread CPU time and quantiles. The machine's name: common/machine_info.h.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "datasets/slam_stream.h"

namespace terramesh::bench {

/// A SLAM stream to mesh and the map's up direction.
struct BenchStream {
  std::string name;
  datasets::SlamStream stream;
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
};

/// The KITTI-like stream (the paper's Table IV density) along a procedural street of `length_m`.
BenchStream builtinStreet(double length_m = 200.0);
/// A stream file (e.g. DIR/stream.tmstream of `terramesh generate`); up is read from the
/// `up_W x y z` line of DIR/generation.txt if there is one, else estimated from the cameras.
/// @throw as datasets::readAnyStream.
BenchStream fileStream(const std::filesystem::path& path);

/// CPU time of this thread, seconds: robust to other processes sharing the cores.
double threadCpuSeconds();
/// The q-quantile (0-1, nearest rank after rounding) of `values`; 0 when empty.
double percentile(std::vector<double> values, double q);

}  // namespace terramesh::bench
