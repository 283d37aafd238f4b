#include "datasets/kitti_sequence_writer.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "common/atomic_file.h"
#include "datasets/kitti_trajectory.h"

namespace terramesh::datasets {
namespace {

/// Appends `value` to `bytes` as IEEE float32, little-endian on any host.
void appendLittleEndian(std::string& bytes, float value) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof(bits));
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((bits >> (8 * i)) & 0xFFu));
}

/// A 3x4 rigid transform by rows, full double precision, numbers separated by spaces.
std::string matrixRow3x4(const Eigen::Isometry3d& transform) {
  std::string text;
  char number[32];
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col) {
      std::snprintf(number, sizeof(number), "%.17g", transform.matrix()(row, col));
      if (!text.empty()) text += ' ';
      text += number;
    }
  }
  return text;
}

/// The frame number of `velodyne/NNNNNN.bin`, or -1 for any other name.
long long frameOfScanFile(const std::filesystem::path& path) {
  const std::string stem = path.stem().string();
  if (path.extension() != ".bin" || stem.empty() || stem.size() > 9 ||
      stem.find_first_not_of("0123456789") != std::string::npos) {
    return -1;
  }
  return std::stoll(stem);
}

}  // namespace

Eigen::Isometry3d kittiLikeVelodyneToCam0() {
  Eigen::Isometry3d T_cam0_S = Eigen::Isometry3d::Identity();
  T_cam0_S.linear() << 0, -1, 0,  //
      0, 0, -1,                   //
      1, 0, 0;
  // The sensor's origin in cam0: 0.01 m left of, 0.05 m above and 0.29 m behind the camera.
  T_cam0_S.translation() = Eigen::Vector3d(-0.01, -0.05, -0.29);
  return T_cam0_S;
}

void writeVelodyneScan(const std::filesystem::path& path,
                       const std::vector<VelodyneReturn>& returns_S) {
  std::string bytes;
  bytes.reserve(16 * returns_S.size());
  for (const VelodyneReturn& point : returns_S) {
    for (int k = 0; k < 3; ++k) appendLittleEndian(bytes, point.position_S[k]);
    appendLittleEndian(bytes, point.reflectance);
  }
  writeFileAtomically(path, bytes);
}

KittiSequenceWriter::KittiSequenceWriter(std::filesystem::path directory,
                                         const Eigen::Isometry3d& T_cam0_S)
    : directory_(std::move(directory)), T_cam0_S_(T_cam0_S) {
  std::filesystem::create_directories(directory_ / "velodyne");
  // An earlier sequence here stops being one until finish() has written the new one completely.
  std::filesystem::remove(directory_ / "calib.txt");
}

std::filesystem::path KittiSequenceWriter::scanFileName(std::size_t frame) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06zu.bin", frame);
  return std::filesystem::path("velodyne") / name;
}

void KittiSequenceWriter::addScan(const std::vector<VelodyneReturn>& returns_S,
                                  const Eigen::Isometry3d& T_W_S, double time_s) {
  if (finished_) throw std::logic_error("KittiSequenceWriter::addScan after finish()");
  writeVelodyneScan(directory_ / scanFileName(poses_T_W_cam0_.size()), returns_S);
  poses_T_W_cam0_.push_back(T_W_S * T_cam0_S_.inverse());
  times_s_.push_back(time_s);
}

void KittiSequenceWriter::removeStaleScans() const {
  std::vector<std::filesystem::path> stale;
  for (const auto& entry : std::filesystem::directory_iterator(directory_ / "velodyne")) {
    const long long frame = frameOfScanFile(entry.path());
    if (frame >= 0 && static_cast<std::size_t>(frame) >= poses_T_W_cam0_.size())
      stale.push_back(entry.path());
  }
  for (const std::filesystem::path& path : stale) std::filesystem::remove(path);
}

void KittiSequenceWriter::finish() {
  if (finished_) throw std::logic_error("KittiSequenceWriter::finish called twice");
  if (poses_T_W_cam0_.empty()) throw std::logic_error("KittiSequenceWriter::finish without a scan");
  finished_ = true;
  removeStaleScans();
  writeKittiPoses(directory_ / "poses.txt", poses_T_W_cam0_);
  writeFileAtomically(directory_ / "times.txt", [this](std::ostream& out) {
    char number[32];
    for (const double time_s : times_s_) {
      std::snprintf(number, sizeof(number), "%.6e", time_s);
      out << number << '\n';
    }
  });
  writeFileAtomically(directory_ / "calib.txt", "Tr: " + matrixRow3x4(T_cam0_S_) + "\n");
}

}  // namespace terramesh::datasets
