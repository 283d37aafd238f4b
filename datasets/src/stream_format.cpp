#include "datasets/stream_format.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

#include "common/atomic_file.h"
#include "common/input_error.h"
#include "datasets/slam_json.h"

namespace terramesh::datasets {
namespace {

constexpr std::string_view kMagic = "terramesh_stream";
constexpr int kFormatVersion = 1;

/// Splits one line into whitespace-separated tokens; '#' starts a comment.
std::vector<std::string_view> tokenize(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

class StreamFileParser {
 public:
  StreamFileParser(std::string file, std::istream& in) : file_(std::move(file)), in_(in) {}

  SlamStream parse() {
    SlamStream stream;
    stream.description = file_;
    std::vector<std::string_view> tokens;
    if (!nextLine(tokens)) fail("empty file (expected the header \"terramesh_stream 1\")");
    if (tokens.size() != 2 || tokens[0] != kMagic) {
      fail("expected the header \"terramesh_stream 1\"");
    }
    if (parseInteger(tokens[1], "format version") != kFormatVersion) {
      fail("unsupported format version " + std::string(tokens[1]) + " (expected 1)");
    }
    while (nextLine(tokens)) {
      const std::string_view directive = tokens[0];
      if (directive == "metres_per_unit") {
        expectCount(tokens, 2, "metres_per_unit SCALE");
        stream.metres_per_unit = parseReal(tokens[1], "metres_per_unit");
        if (!(stream.metres_per_unit > 0)) fail("metres_per_unit must be positive");
        stream.scale_known = true;
      } else if (directive == "description") {
        const std::size_t start = line_.find("description") + std::string_view("description").size();
        stream.description = trim(line_.substr(start));
      } else if (directive == "keyframe") {
        stream.events.emplace_back(parseKeyframe(tokens));
      } else if (directive == "remove_points") {
        if (tokens.size() < 2) fail("expected \"remove_points N ID...\"");
        const std::uint64_t count = parseInteger(tokens[1], "point count");
        expectCount(tokens, 2 + count, "remove_points N followed by N point ids");
        PointRemoval removal;
        for (std::size_t i = 0; i < count; ++i) {
          removal.points.push_back({parseInteger(tokens[2 + i], "point id")});
        }
        stream.events.emplace_back(std::move(removal));
      } else if (directive == "remove_keyframe") {
        expectCount(tokens, 2, "remove_keyframe ID");
        stream.events.emplace_back(KeyframeRemoval{{parseInteger(tokens[1], "keyframe id")}});
      } else {
        fail("unknown record \"" + std::string(directive) +
             "\" (expected keyframe, remove_points, remove_keyframe, metres_per_unit or "
             "description)");
      }
    }
    return stream;
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(file_, lineLocation(line_number_), problem);
  }

  static std::string trim(const std::string& text) {
    const auto begin = text.find_first_not_of(" \t\r");
    if (begin == std::string::npos) return "";
    const auto end = text.find_last_not_of(" \t\r");
    return text.substr(begin, end - begin + 1);
  }

  bool nextLine(std::vector<std::string_view>& tokens) {
    while (std::getline(in_, line_)) {
      ++line_number_;
      tokens = tokenize(line_);
      if (!tokens.empty()) return true;
    }
    if (in_.bad()) fail("read error");
    return false;
  }

  void expectCount(const std::vector<std::string_view>& tokens, std::size_t count,
                   const char* syntax) const {
    if (tokens.size() != count) {
      fail("expected \"" + std::string(syntax) + "\" (" + std::to_string(count) + " fields, got " +
           std::to_string(tokens.size()) + ")");
    }
  }

  std::uint64_t parseInteger(std::string_view token, const char* what) const {
    std::uint64_t value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size()) {
      fail(std::string(what) + ": expected a non-negative integer, got \"" + std::string(token) +
           "\"");
    }
    return value;
  }

  double parseReal(std::string_view token, const char* what) const {
    // std::from_chars for double is not available in every libstdc++; strtod on a copy is exact.
    const std::string copy(token);
    char* end = nullptr;
    const double value = std::strtod(copy.c_str(), &end);
    if (end != copy.c_str() + copy.size() || copy.empty()) {
      fail(std::string(what) + ": expected a number, got \"" + copy + "\"");
    }
    if (!std::isfinite(value)) fail(std::string(what) + ": expected a finite number");
    return value;
  }

  mesher::Keyframe parseKeyframe(const std::vector<std::string_view>& tokens) {
    expectCount(tokens, 10, "keyframe ID CX CY CZ QW QX QY QZ N");
    mesher::Keyframe keyframe;
    keyframe.id.value = parseInteger(tokens[1], "keyframe id");
    for (int i = 0; i < 3; ++i) keyframe.position_W_C[i] = parseReal(tokens[2 + i], "camera centre");
    const Eigen::Vector4d q(parseReal(tokens[5], "quaternion w"), parseReal(tokens[6], "quaternion x"),
                            parseReal(tokens[7], "quaternion y"), parseReal(tokens[8], "quaternion z"));
    if (std::abs(q.norm() - 1.0) > 1e-3) fail("quaternion must have unit norm");
    keyframe.rotation_W_C = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    const std::uint64_t count = parseInteger(tokens[9], "observation count");
    const std::size_t keyframe_line = line_number_;
    keyframe.observations.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(count, 1u << 20)));
    std::vector<std::string_view> fields;
    for (std::uint64_t i = 0; i < count; ++i) {
      if (!nextLine(fields)) {
        fail("file ends inside the keyframe of line " + std::to_string(keyframe_line) + ": " +
             std::to_string(i) + " of " + std::to_string(count) + " observations read");
      }
      expectCount(fields, 4, "POINT_ID X Y Z");
      mesher::PointObservation observation;
      observation.point.value = parseInteger(fields[0], "point id");
      for (int k = 0; k < 3; ++k) observation.position_W[k] = parseReal(fields[1 + k], "point position");
      keyframe.observations.push_back(observation);
    }
    return keyframe;
  }

  std::string file_;
  std::istream& in_;
  std::string line_;
  std::size_t line_number_ = 0;
};

void writeReal(std::ostream& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.write(buffer, result.ptr - buffer);
}

}  // namespace

SlamStream readStreamFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  return StreamFileParser(path.string(), in).parse();
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

SlamStream readAnyStream(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  if (extension == ".json") return readSlamJson(path);
  if (extension == ".tmstream") return readStreamFile(path);
  throw InputError(path.string(), "",
                   "unknown stream format \"" + extension +
                       "\" (expected .json for the authors' format or .tmstream)");
}

}  // namespace terramesh::datasets
