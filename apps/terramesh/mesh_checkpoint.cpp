#include "mesh_checkpoint.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <type_traits>
#include <variant>

#include "common/atomic_file.h"
#include "common/input_error.h"
#include "mesher/checkpoint.h"

namespace terramesh::cli {
namespace {

// The run state travels as the checkpoint's application data: "key value" lines, the totals as
// raw bytes in hex (their layout is this build's: a checkpoint is resumed by the build that wrote
// it), the trajectory evidence settings (TrajectoryEvidenceRun::settings), the freeze's settings
// and state (MeshFreeze), then the CSV after a "csv" line.
constexpr const char* kStateTag = "terramesh-mesh-run 4";
static_assert(std::is_trivially_copyable_v<mesher::UpdateStats>);

class Fnv {
 public:
  template <class T>
  void add(const T& value) {
    static_assert(std::is_arithmetic_v<T>);
    const auto* bytes = reinterpret_cast<const unsigned char*>(&value);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      hash_ ^= bytes[i];
      hash_ *= 0x100000001b3ull;
    }
  }
  void add(const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) add(v[i]);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

std::string toHex(const void* data, std::size_t size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text;
  for (std::size_t i = 0; i < size; ++i) {
    const unsigned char byte = static_cast<const unsigned char*>(data)[i];
    text += kDigits[byte >> 4];
    text += kDigits[byte & 15];
  }
  return text;
}

bool fromHex(const std::string& text, void* data, std::size_t size) {
  if (text.size() != 2 * size) return false;
  auto digit = [](char c) { return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1; };
  for (std::size_t i = 0; i < size; ++i) {
    const int hi = digit(text[2 * i]);
    const int lo = digit(text[2 * i + 1]);
    if (hi < 0 || lo < 0) return false;
    static_cast<unsigned char*>(data)[i] = static_cast<unsigned char>(hi * 16 + lo);
  }
  return true;
}

std::string encode(const MeshRunState& state) {
  std::ostringstream out;
  out << kStateTag << "\nfingerprint " << state.stream_fingerprint << "\nevents " << state.events << "\nnext_event "
      << state.next_event << "\nkeyframes " << state.keyframes << "\ntotals " << sizeof(state.totals) << ' '
      << toHex(&state.totals, sizeof(state.totals)) << "\ntrajectory_evidence " << state.trajectory_evidence
      << "\nfreeze_settings " << state.freeze_settings << "\nfreeze_state " << state.freeze_state << "\ncsv\n"
      << state.csv;
  return out.str();
}

MeshRunState decode(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  MeshRunState state;
  std::string line;
  auto field = [&](const char* name) {
    std::string key;
    if (!(in >> key) || key != name) throw InputError(file, "run state", std::string("expected field \"") + name + "\"");
  };
  if (!std::getline(in, line) || line != kStateTag) {
    throw InputError(file, "run state", "not a checkpoint of `terramesh mesh` (expected \"" + std::string(kStateTag) + "\")");
  }
  std::size_t totals_size = 0;
  std::string totals_hex;
  field("fingerprint");
  in >> state.stream_fingerprint;
  field("events");
  in >> state.events;
  field("next_event");
  in >> state.next_event;
  field("keyframes");
  in >> state.keyframes;
  field("totals");
  in >> totals_size >> totals_hex;
  if (!in || totals_size != sizeof(state.totals) || !fromHex(totals_hex, &state.totals, sizeof(state.totals))) {
    throw InputError(file, "run state.totals", "statistics of another terramesh build; resume with the build that wrote it");
  }
  in.ignore(1);
  field("trajectory_evidence");
  in.ignore(1);
  if (!std::getline(in, state.trajectory_evidence) || state.trajectory_evidence.empty()) {
    throw InputError(file, "run state.trajectory_evidence", "expected the trajectory evidence settings");
  }
  for (auto [name, value] : {std::pair<const char*, std::string*>{"freeze_settings", &state.freeze_settings},
                             std::pair<const char*, std::string*>{"freeze_state", &state.freeze_state}}) {
    field(name);
    in.ignore(1);
    if (!std::getline(in, *value)) throw InputError(file, std::string("run state.") + name, "expected a line");
  }
  if (!std::getline(in, line) || line != "csv") throw InputError(file, "run state", "expected the \"csv\" line");
  state.csv.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (state.next_event > state.events) throw InputError(file, "run state.next_event", "an event index within the stream");
  return state;
}

}  // namespace

std::uint64_t streamFingerprint(const datasets::SlamStream& stream) {
  Fnv fnv;
  fnv.add(stream.events.size());
  for (const datasets::StreamEvent& event : stream.events) {
    fnv.add(event.index());
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      fnv.add(keyframe->id.value);
      fnv.add(keyframe->position_W_C);
      fnv.add(keyframe->rotation_W_C.coeffs().x());
      fnv.add(keyframe->rotation_W_C.coeffs().y());
      fnv.add(keyframe->rotation_W_C.coeffs().z());
      fnv.add(keyframe->rotation_W_C.coeffs().w());
      fnv.add(keyframe->observations.size());
      for (const mesher::PointObservation& observation : keyframe->observations) {
        fnv.add(observation.point.value);
        fnv.add(observation.position_W);
      }
    } else if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
      fnv.add(removal->keyframe.value);
    } else {
      const auto& points = std::get<datasets::PointRemoval>(event).points;
      fnv.add(points.size());
      for (const mesher::PointId& id : points) fnv.add(id.value);
    }
  }
  return fnv.value();
}

void writeMeshCheckpoint(const std::filesystem::path& path, const mesher::Mesher& mesher, const MeshRunState& state) {
  const std::string app_data = encode(state);
  writeFileAtomically(path, [&](std::ostream& out) { mesher::saveCheckpoint(mesher, out, app_data); });
}

ResumedMeshRun readMeshCheckpoint(const std::filesystem::path& path, const datasets::SlamStream& stream) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "file", "cannot open the checkpoint");
  mesher::LoadedCheckpoint loaded = mesher::loadCheckpoint(in, path.string());
  MeshRunState state = decode(loaded.app_data, path.string());
  if (state.events != stream.events.size() || state.stream_fingerprint != streamFingerprint(stream)) {
    std::ostringstream problem;
    problem << "made from another input stream (" << state.events << " events, fingerprint " << std::hex
            << state.stream_fingerprint << "; this input has " << std::dec << stream.events.size()
            << " events); resume with the stream and options of the interrupted run";
    throw InputError(path.string(), "run state.fingerprint", problem.str());
  }
  return ResumedMeshRun{std::move(loaded.mesher), std::move(state)};
}

}  // namespace terramesh::cli
