#pragma once

// Checkpoints of `terramesh mesh` (--checkpoint-every K, --resume FILE): the mesher's whole state
// (mesher/checkpoint.h) plus where the run stands in its input stream, written atomically.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "datasets/slam_stream.h"
#include "mesher/mesher.h"
#include "mesher/update_stats.h"

namespace terramesh::cli {

/// Name of the checkpoint file in the output directory.
inline constexpr const char* kCheckpointFileName = "checkpoint.tmckpt";

/// Where a `terramesh mesh` run stands; saved beside the mesher in every checkpoint.
struct MeshRunState {
  std::uint64_t stream_fingerprint = 0;  ///< streamFingerprint of the input
  std::size_t events = 0;                ///< events in the input stream
  std::size_t next_event = 0;            ///< index of the first event not applied yet
  std::size_t keyframes = 0;             ///< keyframe events applied
  mesher::UpdateStats totals;            ///< summed over the applied events
  std::string csv;                       ///< keyframes.csv so far, header included
  /// TrajectoryEvidenceRun::settings() of the run ("off" or the height and layout of the samples).
  std::string trajectory_evidence = "off";
  /// With --freeze-radius-m: MeshFreeze::settings() and MeshFreeze::state() ("off" and "" without).
  std::string freeze_settings = "off";
  std::string freeze_state;
};

/// FNV-1a over every event's kind, ids, poses and observations: tells whether a resume reads the
/// stream the checkpoint was made from. O(stream size).
std::uint64_t streamFingerprint(const datasets::SlamStream& stream);

/// Writes the mesher and the run state to `path` atomically (temporary file + rename): the
/// previous checkpoint stays whole until the new one is complete.
/// @throw std::runtime_error naming the path if it cannot be written.
void writeMeshCheckpoint(const std::filesystem::path& path, const mesher::Mesher& mesher, const MeshRunState& state);

struct ResumedMeshRun {
  mesher::Mesher mesher;
  MeshRunState state;
};

/// Reads a checkpoint written by writeMeshCheckpoint and checks that it belongs to `stream`.
/// @throw terramesh::InputError naming `path` if it cannot be read, is truncated or corrupted, was
///        written by another build, or was made from another stream.
ResumedMeshRun readMeshCheckpoint(const std::filesystem::path& path, const datasets::SlamStream& stream);

}  // namespace terramesh::cli
