#include "datasets/stream_format.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>
#include <unordered_map>

#include "common/atomic_file.h"
#include "text_lines.h"

namespace terramesh::datasets {
namespace {

constexpr std::string_view kMagic = "terramesh_stream";
constexpr int kFormatVersion = 1;

class StreamFileParser {
 public:
  explicit StreamFileParser(const std::filesystem::path& path) : lines_(path) {}

  SlamStream parse() {
    SlamStream stream;
    stream.description = lines_.file();
    std::vector<std::string_view> tokens;
    if (!lines_.nextTokens(tokens)) {
      lines_.fail("empty file (expected the header \"terramesh_stream 1\")");
    }
    if (tokens.size() != 2 || tokens[0] != kMagic) {
      lines_.fail("expected the header \"terramesh_stream 1\"");
    }
    if (lines_.integer(tokens[1], "format version") != kFormatVersion) {
      lines_.fail("unsupported format version " + std::string(tokens[1]) + " (expected 1)");
    }
    while (lines_.nextTokens(tokens)) {
      const std::string_view directive = tokens[0];
      if (directive == "metres_per_unit") {
        lines_.expectCount(tokens, 2, "metres_per_unit SCALE");
        stream.metres_per_unit = lines_.real(tokens[1], "metres_per_unit");
        if (!(stream.metres_per_unit > 0)) lines_.fail("metres_per_unit must be positive");
        stream.scale_known = true;
      } else if (directive == "max_camera_distance") {
        lines_.expectCount(tokens, 2, "max_camera_distance auto");
        if (tokens[1] != "auto") lines_.fail("max_camera_distance must be \"auto\"");
        stream.recommend_auto_max_distance = true;
      } else if (directive == "min_views") {
        lines_.expectCount(tokens, 2, "min_views N");
        const std::uint64_t views = lines_.integer(tokens[1], "min_views");
        if (views < 1 || views > 1000) lines_.fail("min_views must be within 1..1000");
        stream.recommended_min_views = static_cast<int>(views);
      } else if (directive == "steiner_step_m") {
        lines_.expectCount(tokens, 2, "steiner_step_m M");
        const double step = lines_.real(tokens[1], "steiner_step_m");
        if (!(step > 0) || !std::isfinite(step)) lines_.fail("steiner_step_m must be positive and finite");
        stream.recommended_steiner_step_m = step;
      } else if (directive == "sensor_up") {
        lines_.expectCount(tokens, 4, "sensor_up X Y Z");
        Eigen::Vector3d up;
        for (int k = 0; k < 3; ++k) up[k] = lines_.real(tokens[1 + static_cast<std::size_t>(k)], "sensor_up");
        if (!(up.norm() > 0)) lines_.fail("sensor_up must be a non-zero vector");
        stream.sensor_up_S = up.normalized();
      } else if (directive == "description") {
        const std::string& line = lines_.line();
        const std::size_t start = line.find("description") + std::string_view("description").size();
        stream.description = trim(line.substr(start));
      } else if (directive == "keyframe") {
        stream.events.emplace_back(parseKeyframe(tokens));
      } else if (directive == "remove_points") {
        if (tokens.size() < 2) lines_.fail("expected \"remove_points N ID...\"");
        const std::uint64_t count = lines_.integer(tokens[1], "point count");
        lines_.expectCount(tokens, 2 + count, "remove_points N followed by N point ids");
        PointRemoval removal;
        for (std::size_t i = 0; i < count; ++i) {
          removal.points.push_back({lines_.integer(tokens[2 + i], "point id")});
        }
        stream.events.emplace_back(std::move(removal));
      } else if (directive == "remove_keyframe") {
        lines_.expectCount(tokens, 2, "remove_keyframe ID");
        stream.events.emplace_back(KeyframeRemoval{{lines_.integer(tokens[1], "keyframe id")}});
      } else {
        lines_.fail("unknown record \"" + std::string(directive) +
                    "\" (expected keyframe, remove_points, remove_keyframe, metres_per_unit, "
                    "max_camera_distance, min_views, sensor_up or description)");
      }
    }
    return stream;
  }

 private:
  static std::string trim(const std::string& text) {
    const auto begin = text.find_first_not_of(" \t\r");
    if (begin == std::string::npos) return "";
    const auto end = text.find_last_not_of(" \t\r");
    return text.substr(begin, end - begin + 1);
  }

  mesher::Keyframe parseKeyframe(const std::vector<std::string_view>& tokens) {
    lines_.expectCount(tokens, 10, "keyframe ID CX CY CZ QW QX QY QZ N");
    mesher::Keyframe keyframe;
    keyframe.id.value = lines_.integer(tokens[1], "keyframe id");
    for (int i = 0; i < 3; ++i) {
      keyframe.position_W_C[i] = lines_.real(tokens[2 + i], "camera centre");
    }
    const Eigen::Vector4d q(
        lines_.real(tokens[5], "quaternion w"), lines_.real(tokens[6], "quaternion x"),
        lines_.real(tokens[7], "quaternion y"), lines_.real(tokens[8], "quaternion z"));
    if (std::abs(q.norm() - 1.0) > 1e-3) lines_.fail("quaternion must have unit norm");
    keyframe.rotation_W_C = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    const std::uint64_t count = lines_.integer(tokens[9], "observation count");
    const std::size_t keyframe_line = lines_.lineNumber();
    keyframe.observations.reserve(
        static_cast<std::size_t>(std::min<std::uint64_t>(count, 1u << 20)));
    // The mesher rejects a point listed twice; each line has its own position, so there is no
    // right one to keep.
    std::unordered_map<mesher::PointId, std::size_t> first_line;
    std::vector<std::string_view> fields;
    for (std::uint64_t i = 0; i < count; ++i) {
      if (!lines_.nextTokens(fields)) {
        lines_.fail("file ends inside the keyframe of line " + std::to_string(keyframe_line) +
                    ": " + std::to_string(i) + " of " + std::to_string(count) +
                    " observations read");
      }
      lines_.expectCount(fields, 4, "POINT_ID X Y Z");
      mesher::PointObservation observation;
      observation.point.value = lines_.integer(fields[0], "point id");
      const auto [first, inserted] = first_line.emplace(observation.point, lines_.lineNumber());
      if (!inserted) {
        lines_.fail("point " + std::to_string(observation.point.value) +
                    " is listed twice in the keyframe of line " + std::to_string(keyframe_line) +
                    " (first on line " + std::to_string(first->second) + ")");
      }
      for (int k = 0; k < 3; ++k) {
        observation.position_W[k] = lines_.real(fields[1 + k], "point position");
      }
      keyframe.observations.push_back(observation);
    }
    return keyframe;
  }

  internal::TextLineReader lines_;
};

void writeReal(std::ostream& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.write(buffer, result.ptr - buffer);
}

}  // namespace

SlamStream readStreamFile(const std::filesystem::path& path) {
  return StreamFileParser(path).parse();
}

void writeStreamFile(const std::filesystem::path& path, const SlamStream& stream) {
  writeFileAtomically(path, [&stream](std::ostream& out) {
    out << kMagic << ' ' << kFormatVersion << '\n';
    if (!stream.description.empty()) out << "description " << stream.description << '\n';
    if (stream.scale_known) {
      out << "metres_per_unit ";
      writeReal(out, stream.metres_per_unit);
      out << '\n';
    }
    // What the source advises for meshing, so that meshing the saved stream repeats the run.
    if (stream.recommend_auto_max_distance) out << "max_camera_distance auto\n";
    if (stream.recommended_min_views > 0) out << "min_views " << stream.recommended_min_views << '\n';
    if (stream.recommended_steiner_step_m > 0) {
      out << "steiner_step_m ";
      writeReal(out, stream.recommended_steiner_step_m);
      out << '\n';
    }
    if (stream.sensor_up_S != -Eigen::Vector3d::UnitY()) {
      out << "sensor_up";
      for (int k = 0; k < 3; ++k) {
        out << ' ';
        writeReal(out, stream.sensor_up_S[k]);
      }
      out << '\n';
    }
    for (const StreamEvent& event : stream.events) {
      if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
        const auto& c = keyframe->position_W_C;
        const auto& q = keyframe->rotation_W_C;
        out << "keyframe " << keyframe->id.value;
        for (double value : {c.x(), c.y(), c.z(), q.w(), q.x(), q.y(), q.z()}) {
          out << ' ';
          writeReal(out, value);
        }
        out << ' ' << keyframe->observations.size() << '\n';
        for (const auto& observation : keyframe->observations) {
          out << observation.point.value;
          for (int k = 0; k < 3; ++k) {
            out << ' ';
            writeReal(out, observation.position_W[k]);
          }
          out << '\n';
        }
      } else if (const auto* removal = std::get_if<PointRemoval>(&event)) {
        out << "remove_points " << removal->points.size();
        for (const auto& id : removal->points) out << ' ' << id.value;
        out << '\n';
      } else if (const auto* keyframe_removal = std::get_if<KeyframeRemoval>(&event)) {
        out << "remove_keyframe " << keyframe_removal->keyframe.value << '\n';
      }
    }
  });
}

}  // namespace terramesh::datasets
