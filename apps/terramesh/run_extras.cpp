#include "run_extras.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <unordered_map>
#include <variant>
#include <vector>

#include "common/atomic_file.h"

namespace terramesh::cli {
namespace {

struct PointRecord {
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  std::uint32_t first_keyframe = 0;
  std::size_t order = 0;
  bool removed = false;
};

template <class T>
void appendLittleEndian(std::string& out, T value) {
  static_assert(sizeof(T) == 4, "4-byte fields only");
  unsigned char bytes[4];
  std::memcpy(bytes, &value, 4);
  std::uint32_t word = 0;
  for (int i = 3; i >= 0; --i) word = (word << 8) | bytes[i];
  // Written byte by byte so the file is little endian on any host.
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((word >> (8 * i)) & 0xFFu));
}

}  // namespace

std::string trajectoryCsv(const datasets::SlamStream& stream) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "keyframe,id,x,y,z,qw,qx,qy,qz\n";
  std::size_t keyframes = 0;
  for (const datasets::StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (!keyframe) continue;
    ++keyframes;
    const Eigen::Vector3d& p = keyframe->position_W_C;
    const Eigen::Quaterniond& q = keyframe->rotation_W_C;
    csv << keyframes << ',' << keyframe->id.value << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << q.w()
        << ',' << q.x() << ',' << q.y() << ',' << q.z() << '\n';
  }
  return csv.str();
}

std::string pointsPly(const datasets::SlamStream& stream) {
  std::unordered_map<std::uint64_t, PointRecord> points;
  std::uint32_t keyframes = 0;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      ++keyframes;
      for (const mesher::PointObservation& observation : keyframe->observations) {
        auto [it, inserted] = points.try_emplace(observation.point.value);
        if (inserted || it->second.removed) {
          it->second.first_keyframe = keyframes;
          it->second.order = points.size();
          it->second.removed = false;
        }
        it->second.position_W = observation.position_W;
      }
    } else if (const auto* removal = std::get_if<datasets::PointRemoval>(&event)) {
      for (const mesher::PointId id : removal->points) {
        const auto it = points.find(id.value);
        if (it != points.end()) it->second.removed = true;
      }
    }
  }
  std::vector<const PointRecord*> kept;
  for (const auto& entry : points) {
    if (!entry.second.removed) kept.push_back(&entry.second);
  }
  std::sort(kept.begin(), kept.end(), [](const PointRecord* a, const PointRecord* b) { return a->order < b->order; });
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment terramesh SLAM points (docs/viewer.md)\nelement vertex " +
                    std::to_string(kept.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nproperty uint first_keyframe\nend_header\n";
  out.reserve(out.size() + 16 * kept.size());
  for (const PointRecord* point : kept) {
    for (int k = 0; k < 3; ++k) appendLittleEndian(out, static_cast<float>(point->position_W[k]));
    appendLittleEndian(out, point->first_keyframe);
  }
  return out;
}

void writeRunExtras(const datasets::SlamStream& stream, const std::filesystem::path& output) {
  writeFileAtomically(output / "trajectory.csv", trajectoryCsv(stream));
  writeFileAtomically(output / "points.ply", pointsPly(stream));
}

}  // namespace terramesh::cli
