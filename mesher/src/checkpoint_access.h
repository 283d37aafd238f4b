#pragma once
// The mesher's state to and from checkpoint bytes. A friend of Mesher, Mesher::Impl and the
// internal structures whose private members make up the state.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "checkpoint_bytes.h"
#include "map_state.h"
#include "mesher/mesher.h"

namespace terramesh::mesher::internal {

class Grower;

class CheckpointAccess {
 public:
  /// Appends the whole state of `mesher` (not its config) to `out`.
  static void write(const Mesher& mesher, ByteWriter& out);
  /// Restores a state written by `write` into `mesher`, freshly built from the saved config.
  /// @throw terramesh::InputError (from `in`) on any inconsistency.
  static void read(Mesher& mesher, ByteReader& in);

 private:
  /// Handles numbered in the containers' iteration order.
  struct Numbering {
    std::unordered_map<const Delaunay::Vertex*, std::uint32_t> vertices;
    std::unordered_map<const Delaunay::Cell*, std::uint32_t> cells;
    std::uint32_t vertex(const VertexHandle& v) const { return v == VertexHandle() ? kNone : vertices.at(&*v); }
    std::uint32_t cell(const CellHandle& c) const { return c == CellHandle() ? kNone : cells.at(&*c); }
  };
  struct Handles {
    std::vector<VertexHandle> vertices;
    std::vector<CellHandle> cells;
    VertexHandle vertex(ByteReader& in, const char* what, bool allow_none = false) const;
    CellHandle cell(ByteReader& in, const char* what, bool allow_none = false) const;
  };

  static void writeTriangulation(const MapState& state, ByteWriter& out, Numbering& numbering);
  static void readTriangulation(MapState& state, ByteReader& in, Handles& handles);
  static void writeGridAndHash(const MapState& state, ByteWriter& out, const Numbering& numbering);
  static void readGridAndHash(MapState& state, ByteReader& in, const Handles& handles);
  static void writeRays(const RayStore& rays, ByteWriter& out, const Numbering& numbering);
  static void readRays(RayStore& rays, ByteReader& in, const Handles& handles);
  static void writeRegistry(const PointRegistry& registry, const MapState& state, ByteWriter& out,
                            const Numbering& numbering);
  static void readRegistry(PointRegistry& registry, ByteReader& in, const Handles& handles);
  /// The keyframes' free boxes (FreeBoxIndex), by keyframe slot.
  static void writeFreeBoxes(const MapState& state, ByteWriter& out);
  /// @throw terramesh::InputError (from `in`) for a slot that is no live keyframe, a slot listed
  ///        twice, or a box whose centre, rotation or half extents are not finite and positive.
  static void readFreeBoxes(MapState& state, ByteReader& in);
  static void writeSurfaceLog(const SurfaceLog& log, ByteWriter& out);
  static void readSurfaceLog(SurfaceLog& log, ByteReader& in);
  /// The ball pass's memory of refused balls (Grower::ball_refusals_), sorted by cell uid.
  static void writeBallRefusals(const Grower& grower, ByteWriter& out);
  /// @throw terramesh::InputError (from `in`) for a uid not below `state.next_uid`, uids not
  ///        strictly increasing, more entries than the grower keeps, or entries with the pass
  ///        switched off.
  static void readBallRefusals(Grower& grower, ByteReader& in, const MapState& state);
};

}  // namespace terramesh::mesher::internal
