#include "run_extras.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <variant>
#include <vector>

#include "common/atomic_file.h"
#include "common/input_error.h"

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

std::vector<TrajectoryRow> readTrajectoryCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  const std::string file = path.string();
  if (!in) throw InputError(file, "file", "cannot open it (expected trajectory.csv of terramesh mesh)");
  const char* const kHeader = "keyframe,id,x,y,z,qw,qx,qy,qz";
  std::string line;
  if (!std::getline(in, line) || line != kHeader) {
    throw InputError(file, lineLocation(1), std::string("expected the header `") + kHeader + "`");
  }
  std::vector<TrajectoryRow> rows;
  std::unordered_map<std::uint64_t, std::size_t> index;
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::vector<std::string> fields;
    std::stringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    if (fields.size() != 9) throw InputError(file, lineLocation(number), "expected 9 comma-separated fields");
    const auto where = [&](int k) { return lineLocation(number) + ", field " + std::to_string(k + 1); };
    double values[9];
    for (int k = 0; k < 9; ++k) {
      const std::string& field = fields[static_cast<std::size_t>(k)];
      char* end = nullptr;
      values[k] = std::strtod(field.c_str(), &end);
      if (field.empty() || *end != '\0' || !std::isfinite(values[k])) {
        throw InputError(file, where(k), "expected a finite number, got `" + field + "`");
      }
    }
    TrajectoryRow row;
    const std::string& id = fields[1];
    char* end = nullptr;
    errno = 0;
    row.id = std::strtoull(id.c_str(), &end, 10);
    if (id.empty() || id[0] == '-' || *end != '\0' || errno == ERANGE) {
      throw InputError(file, where(1), "expected a non-negative integer keyframe id, got `" + id + "`");
    }
    row.position_W = Eigen::Vector3d(values[2], values[3], values[4]);
    row.rotation_W_C = Eigen::Quaterniond(values[5], values[6], values[7], values[8]);
    if (std::abs(row.rotation_W_C.norm() - 1.0) > 1e-2) {
      throw InputError(file, lineLocation(number) + ", fields 6-9", "expected a unit quaternion qw,qx,qy,qz");
    }
    row.rotation_W_C.normalize();
    const auto [it, inserted] = index.try_emplace(row.id, rows.size());
    if (inserted) {
      rows.push_back(row);
    } else {
      rows[it->second] = row;
    }
  }
  if (rows.empty()) throw InputError(file, "rows", "expected at least one keyframe row");
  return rows;
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
