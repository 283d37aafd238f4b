#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>

#include "mesher/mesher.h"

namespace terramesh::mesher {

/// Version of the checkpoint format written by saveCheckpoint; loadCheckpoint reads only this one.
/// 3: adds the ball pass's memory of refused balls at the end of the payload; 4: adds
/// MesherConfig::handle_min_rays to the configuration; 5: adds each point record's PointKind (SLAM
/// point or driven-ground sample); 8: adds MesherConfig::driven_cells_first to the configuration's
/// technique switches; 9: adds the Steiner grid's sparse flag and, when set, the lattice nodes it holds
/// (Mesher::releaseFarSteiner); 10: adds MesherConfig::steiner_global_phase after
/// steiner_origin_offset_m.
inline constexpr std::uint32_t kCheckpointFormatVersion = 11;

/// Writes the whole state of `mesher` to `out` (binary, little-endian; see docs/formats.md):
/// a header with the magic "TMCKPT01", the format version, the payload's size and its FNV-1a
/// 64-bit checksum, then the payload: the configuration, `app_data`, the Delaunay triangulation
/// with every vertex's and cell's data (O, weights, crossing counts, stamps), the Steiner grid,
/// the boundary hash, the rays with their paths and per-cell ray lists, the points and keyframes,
/// the surface history (so changesSince keeps working across a resume), and the manifold growing's
/// memory of refused balls (which balls its ball pass skips).
///
/// A mesher loaded from the result continues exactly as the saved one would: the same updates
/// give the same meshes, stats and surface deltas. O(map size). Does not change `mesher`.
/// @param app_data opaque bytes returned by loadCheckpoint (e.g. the caller's position in its
///        input stream); covered by the checksum.
/// @throw std::runtime_error if `out` fails while writing.
/// @throw std::logic_error if the triangulation is neither empty nor three-dimensional (never
///        the case between updates).
void saveCheckpoint(const Mesher& mesher, std::ostream& out, const std::string& app_data = {});

/// A mesher restored from a checkpoint, with the caller's data saved alongside.
struct LoadedCheckpoint {
  Mesher mesher;
  std::string app_data;
};

/// Reads a checkpoint written by saveCheckpoint. The file is read whole and its checksum verified
/// before anything is built; every count and index is checked against the data, so a truncated,
/// corrupted or foreign file is refused and nothing is half-loaded. O(file size).
/// @param file_name names the source in error messages.
/// @throw terramesh::InputError naming `file_name`, where (header field or byte offset and
///        section) and what was wrong: bad magic, unsupported version, truncated payload,
///        checksum mismatch, an invalid configuration or an inconsistent structure.
LoadedCheckpoint loadCheckpoint(std::istream& in, const std::string& file_name);

}  // namespace terramesh::mesher
