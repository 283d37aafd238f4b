// saveCheckpoint / loadCheckpoint: the header (magic, version, payload size, checksum), the
// configuration, the caller's data, and the mesher's state (checkpoint_access.h).
#include <array>
#include <cstring>
#include <stdexcept>

#include "checkpoint_access.h"
#include "mesher/checkpoint.h"

namespace terramesh::mesher {
namespace {

using internal::ByteReader;
using internal::ByteWriter;

constexpr std::array<char, 8> kMagic = {'T', 'M', 'C', 'K', 'P', 'T', '0', '1'};
constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 8;

void writeConfig(const MesherConfig& c, ByteWriter& out) {
  out.u8(static_cast<std::uint8_t>(c.mode()));
  out.f64(c.metres_per_unit);
  out.pod(c.min_views);
  out.f64(c.max_camera_distance_m);
  out.f64(c.steiner_step_m);
  out.pod(c.enclosing_radius_cells);
  out.pod(c.camera_enclosing_radius_cells);
  out.pod(c.steiner_margin_cells);
  for (int i = 0; i < 3; ++i) out.f64(c.steiner_origin_offset_m[i]);
  out.u8(c.steiner_global_phase ? 1 : 0);
  out.f64(c.steiner_clearance_steps);
  out.f64(c.weight_crossed);
  out.f64(c.weight_neighbour);
  out.f64(c.weight_second_neighbour);
  out.pod(c.spread_cap);
  out.f64(c.free_threshold);
  out.f64(c.move_threshold_m);
  for (int i = 0; i < 3; ++i) out.f64(c.driven_ground_up_W[i]);
  out.f64(c.driven_underside_depth_m);
  out.u8(static_cast<std::uint8_t>(c.point_policy));
  for (bool flag : {c.incremental_steiner_grid, c.local_enclosing_set, c.boundary_hash, c.next_cell_cache,
                    c.ray_scheduler, c.edge_growing_pass, c.driven_cells_first}) {
    out.u8(flag ? 1 : 0);
  }
  out.f64(c.edge_pass_min_weight);
  out.pod(c.handle_min_rays);
  out.u64(c.surface_history_max_bytes);
  out.u8(c.fixed_grid_bounds_W ? 1 : 0);
  if (c.fixed_grid_bounds_W) {
    for (int i = 0; i < 3; ++i) out.f64(c.fixed_grid_bounds_W->min_W[i]);
    for (int i = 0; i < 3; ++i) out.f64(c.fixed_grid_bounds_W->max_W[i]);
  }
}

MesherConfig readConfig(ByteReader& in) {
  in.section("configuration");
  MesherConfig c;
  const std::uint8_t mode = in.u8();
  if (mode > static_cast<std::uint8_t>(MesherMode::kRomanoni15)) in.fail("a mesher mode 0..2");
  c.setMode(static_cast<MesherMode>(mode));  // first: it resets the mode's settings
  c.metres_per_unit = in.f64();
  c.min_views = in.pod<int>();
  c.max_camera_distance_m = in.f64();
  c.steiner_step_m = in.f64();
  c.enclosing_radius_cells = in.pod<int>();
  c.camera_enclosing_radius_cells = in.pod<int>();
  c.steiner_margin_cells = in.pod<int>();
  for (int i = 0; i < 3; ++i) c.steiner_origin_offset_m[i] = in.f64();
  c.steiner_global_phase = in.flag();
  c.steiner_clearance_steps = in.f64();
  c.weight_crossed = in.f64();
  c.weight_neighbour = in.f64();
  c.weight_second_neighbour = in.f64();
  c.spread_cap = in.pod<int>();
  c.free_threshold = in.f64();
  c.move_threshold_m = in.f64();
  for (int i = 0; i < 3; ++i) c.driven_ground_up_W[i] = in.f64();
  c.driven_underside_depth_m = in.f64();
  const std::uint8_t policy = in.u8();
  if (policy > static_cast<std::uint8_t>(PointPolicy::kFixedPosition)) in.fail("a point policy 0..1");
  c.point_policy = static_cast<PointPolicy>(policy);
  for (bool* flag : {&c.incremental_steiner_grid, &c.local_enclosing_set, &c.boundary_hash, &c.next_cell_cache,
                     &c.ray_scheduler, &c.edge_growing_pass, &c.driven_cells_first}) {
    *flag = in.flag();
  }
  c.edge_pass_min_weight = in.f64();
  c.handle_min_rays = in.pod<int>();
  c.surface_history_max_bytes = static_cast<std::size_t>(in.u64());
  if (in.flag()) {
    AxisAlignedBox box;
    for (int i = 0; i < 3; ++i) box.min_W[i] = in.f64();
    for (int i = 0; i < 3; ++i) box.max_W[i] = in.f64();
    c.fixed_grid_bounds_W = box;
  }
  const std::vector<std::string> problems = c.problems();
  if (!problems.empty()) in.fail("a valid mesher configuration (" + problems.front() + ")");
  return c;
}

template <class T>
void putHeaderField(std::string& header, const T& value) {
  header.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T>
T headerField(const char* header, std::size_t offset) {
  T value;
  std::memcpy(&value, header + offset, sizeof(T));
  return value;
}

/// Reads exactly `size` bytes (in chunks, so a corrupt size cannot allocate more than the file
/// holds); false if the stream ends first.
bool readExactly(std::istream& in, std::string& out, std::uint64_t size) {
  constexpr std::size_t kChunk = std::size_t{1} << 24;
  out.clear();
  while (out.size() < size) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, size - out.size()));
    const std::size_t at = out.size();
    out.resize(at + n);
    in.read(&out[at], static_cast<std::streamsize>(n));
    if (static_cast<std::size_t>(in.gcount()) != n) {
      out.resize(at + static_cast<std::size_t>(in.gcount()));
      return false;
    }
  }
  return true;
}

}  // namespace

void saveCheckpoint(const Mesher& mesher, std::ostream& out, const std::string& app_data) {
  ByteWriter payload;
  writeConfig(mesher.config(), payload);
  payload.string(app_data);
  internal::CheckpointAccess::write(mesher, payload);
  const std::string& bytes = payload.buffer();
  std::string header(kMagic.begin(), kMagic.end());
  putHeaderField(header, kCheckpointFormatVersion);
  putHeaderField(header, static_cast<std::uint64_t>(bytes.size()));
  putHeaderField(header, internal::fnv1a64(bytes.data(), bytes.size()));
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("saveCheckpoint: the output stream failed");
}

LoadedCheckpoint loadCheckpoint(std::istream& in, const std::string& file_name) {
  std::string header;
  if (!readExactly(in, header, kHeaderBytes)) {
    throw InputError(file_name, "header", "truncated checkpoint: " + std::to_string(header.size()) + " of " +
                                              std::to_string(kHeaderBytes) + " header bytes");
  }
  if (std::memcmp(header.data(), kMagic.data(), kMagic.size()) != 0) {
    throw InputError(file_name, "header.magic", "not a terramesh checkpoint (expected \"TMCKPT01\")");
  }
  const auto version = headerField<std::uint32_t>(header.data(), 8);
  if (version != kCheckpointFormatVersion) {
    throw InputError(file_name, "header.version",
                     "checkpoint format version " + std::to_string(version) + ", this build reads version " +
                         std::to_string(kCheckpointFormatVersion));
  }
  const auto size = headerField<std::uint64_t>(header.data(), 12);
  const auto checksum = headerField<std::uint64_t>(header.data(), 20);
  std::string payload;
  if (!readExactly(in, payload, size)) {
    throw InputError(file_name, "payload",
                     "truncated checkpoint: " + std::to_string(payload.size()) + " of " + std::to_string(size) +
                         " payload bytes");
  }
  if (in.peek() != std::char_traits<char>::eof()) {
    throw InputError(file_name, "byte " + std::to_string(kHeaderBytes + size),
                     "unexpected data after the checkpoint payload");
  }
  if (internal::fnv1a64(payload.data(), payload.size()) != checksum) {
    throw InputError(file_name, "payload", "checksum mismatch: the checkpoint is corrupted");
  }
  ByteReader reader(payload, file_name, kHeaderBytes);
  const MesherConfig config = readConfig(reader);
  reader.section("application data");
  std::string app_data = reader.string();
  Mesher mesher(config);
  internal::CheckpointAccess::read(mesher, reader);
  return LoadedCheckpoint{std::move(mesher), std::move(app_data)};
}

}  // namespace terramesh::mesher
