#include "reader_test_util.h"

#include <fstream>
#include <set>
#include <sstream>

namespace terramesh::test {

std::filesystem::path sharedData(const std::string& relative) {
  return std::filesystem::path(TERRAMESH_SHARED_DIR) / "data" / relative;
}

StreamCounts countStream(const datasets::SlamStream& stream) {
  StreamCounts counts;
  std::set<std::uint64_t> keyframes;
  std::set<std::uint64_t> points;
  for (const mesher::Keyframe& keyframe : keyframesOf(stream)) {
    ++counts.keyframe_events;
    keyframes.insert(keyframe.id.value);
    counts.observations += keyframe.observations.size();
    for (const auto& observation : keyframe.observations) points.insert(observation.point.value);
  }
  counts.distinct_keyframes = keyframes.size();
  counts.distinct_points = points.size();
  return counts;
}

std::vector<mesher::Keyframe> keyframesOf(const datasets::SlamStream& stream) {
  std::vector<mesher::Keyframe> keyframes;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event))
      keyframes.push_back(*keyframe);
  }
  return keyframes;
}

namespace {

bool close(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double tolerance) {
  return tolerance == 0.0 ? a == b : (a - b).cwiseAbs().maxCoeff() <= tolerance;
}

}  // namespace

::testing::AssertionResult sameStreams(const datasets::SlamStream& a, const datasets::SlamStream& b,
                                       double tolerance) {
  if (a.events.size() != b.events.size()) {
    return ::testing::AssertionFailure() << a.events.size() << " events vs " << b.events.size();
  }
  if (a.keyframe_names != b.keyframe_names) return ::testing::AssertionFailure() << "names differ";
  const auto ka = keyframesOf(a);
  const auto kb = keyframesOf(b);
  if (ka.size() != kb.size()) return ::testing::AssertionFailure() << "keyframe counts differ";
  for (std::size_t k = 0; k < ka.size(); ++k) {
    const mesher::Keyframe& x = ka[k];
    const mesher::Keyframe& y = kb[k];
    if (x.id != y.id) return ::testing::AssertionFailure() << "event " << k << ": ids differ";
    if (!close(x.position_W_C, y.position_W_C, tolerance) ||
        !close(x.rotation_W_C.toRotationMatrix(), y.rotation_W_C.toRotationMatrix(), tolerance)) {
      return ::testing::AssertionFailure() << "keyframe " << x.id.value << ": poses differ";
    }
    if (x.observations.size() != y.observations.size()) {
      return ::testing::AssertionFailure()
             << "keyframe " << x.id.value << ": " << x.observations.size() << " vs "
             << y.observations.size() << " observations";
    }
    for (std::size_t o = 0; o < x.observations.size(); ++o) {
      if (x.observations[o].point != y.observations[o].point ||
          !close(x.observations[o].position_W, y.observations[o].position_W, tolerance)) {
        return ::testing::AssertionFailure()
               << "keyframe " << x.id.value << ": observation " << o << " differs";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

InputError expectInputError(const std::function<void()>& read) {
  try {
    read();
  } catch (const InputError& error) {
    return error;
  } catch (const std::exception& error) {
    ADD_FAILURE() << "expected an InputError, got: " << error.what();
    return InputError("", "", "");
  }
  ADD_FAILURE() << "expected an InputError, nothing was thrown";
  return InputError("", "", "");
}

void expectErrorAt(const InputError& error, const std::filesystem::path& file,
                   const std::string& where_part, const std::string& problem_part) {
  EXPECT_EQ(error.file(), file.string()) << error.what();
  EXPECT_NE(error.where().find(where_part), std::string::npos) << error.what();
  EXPECT_NE(error.problem().find(problem_part), std::string::npos) << error.what();
  EXPECT_NE(std::string(error.what()).find(file.string()), std::string::npos) << error.what();
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

void writeFile(const std::filesystem::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void patchFile(const std::filesystem::path& path, std::size_t offset, const void* bytes,
               std::size_t size) {
  std::string content = readFile(path);
  if (offset + size > content.size()) throw std::out_of_range("patchFile: past the end");
  content.replace(offset, size, static_cast<const char*>(bytes), size);
  writeFile(path, content);
}

void copyFiles(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::filesystem::create_directories(to);
  for (const auto& entry : std::filesystem::directory_iterator(from)) {
    if (entry.is_regular_file()) writeFile(to / entry.path().filename(), readFile(entry.path()));
  }
}

void replaceLine(const std::filesystem::path& path, std::size_t line_number,
                 const std::string& line) {
  std::istringstream in(readFile(path));
  std::ostringstream out;
  std::string current;
  for (std::size_t n = 1; std::getline(in, current); ++n) {
    out << (n == line_number ? line : current) << '\n';
  }
  writeFile(path, out.str());
}

}  // namespace terramesh::test
