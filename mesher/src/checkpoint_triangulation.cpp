// Checkpoint of the triangulation with its vertex and cell data, the Steiner grid, the boundary
// hash and the mesher's own fields. Handles are written as indices in the containers' iteration
// order and restored in that order, so the restored triangulation iterates, walks and allocates
// uids exactly as the saved one.
#include <algorithm>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "checkpoint_access.h"
#include "mesher_impl.h"

namespace terramesh::mesher::internal {
namespace {

void writePoint(ByteWriter& out, const Point& p) {
  out.f64(p.x());
  out.f64(p.y());
  out.f64(p.z());
}

void writeKey(ByteWriter& out, const GridKey& key) {
  out.pod(key.i);
  out.pod(key.j);
  out.pod(key.k);
}

GridKey readKey(ByteReader& in) {
  GridKey key;
  key.i = in.pod<std::int32_t>();
  key.j = in.pod<std::int32_t>();
  key.k = in.pod<std::int32_t>();
  return key;
}

void writeVertexInfo(ByteWriter& out, const VertexInfo& info) {
  out.u64(info.key);
  out.u32(info.point);
  out.pod(info.outside_cells);
  out.pod(info.degree);
  out.u8(info.steiner ? 1 : 0);
  out.u8(info.key_cached ? 1 : 0);
}

void readVertexInfo(ByteReader& in, VertexInfo& info) {
  info.key = in.u64();
  info.point = in.u32();
  info.outside_cells = in.pod<std::uint16_t>();
  info.degree = in.pod<std::uint16_t>();
  info.steiner = in.flag();
  info.key_cached = in.flag();
  info.hash_slot = kNone;  // set when the boundary hash is rebuilt
  info.mark = 0;           // scratch marks restart with fresh epochs
}

void writeCellInfo(ByteWriter& out, const CellInfo& info) {
  out.pod(info.weight);
  out.u32(info.crossings);
  out.u32(info.spreading);
  out.u32(info.driven_crossings);
  out.u32(info.uid);
  out.u32(info.ray_list);
  out.u8(info.flags);
  out.u8(info.next_facet);
}

void readCellInfo(ByteReader& in, CellInfo& info) {
  info.weight = in.pod<std::int32_t>();
  info.crossings = in.u32();
  info.spreading = in.u32();
  info.driven_crossings = in.u32();
  info.uid = in.u32();
  info.ray_list = in.u32();
  info.flags = in.u8();
  info.next_facet = in.u8();
  info.mark = 0;
  if (info.next_facet > 4) in.fail("a next-facet cache entry in 0..4");
  constexpr std::uint8_t kPersistent = kCellOutside;
  if (info.flags & ~kPersistent) in.fail("cell flags without scratch bits (saved between updates)");
}

constexpr std::size_t kVertexRecordBytes = 3 * 8 + 8 + 4 + 2 + 2 + 1 + 1 + 4;
constexpr std::size_t kCellRecordBytes = 8 * 4 + 4 * 5 + 4 + 2;

}  // namespace

VertexHandle CheckpointAccess::Handles::vertex(ByteReader& in, const char* what, bool allow_none) const {
  const std::uint32_t i = in.index(vertices.size(), what, allow_none);
  return i == kNone ? VertexHandle() : vertices[i];
}

CellHandle CheckpointAccess::Handles::cell(ByteReader& in, const char* what, bool allow_none) const {
  const std::uint32_t i = in.index(cells.size(), what, allow_none);
  return i == kNone ? CellHandle() : cells[i];
}

void CheckpointAccess::writeTriangulation(const MapState& state, ByteWriter& out, Numbering& numbering) {
  const Delaunay& tri = state.tri;
  const bool empty = tri.number_of_vertices() == 0;
  if (!empty && tri.dimension() != 3) {
    throw std::logic_error("saveCheckpoint: the triangulation is neither empty nor three-dimensional");
  }
  out.u8(empty ? 0 : 3);
  if (empty) return;
  for (auto v = tri.all_vertices_begin(); v != tri.all_vertices_end(); ++v) {
    numbering.vertices.emplace(&*v, static_cast<std::uint32_t>(numbering.vertices.size()));
  }
  for (auto c = tri.all_cells_begin(); c != tri.all_cells_end(); ++c) {
    numbering.cells.emplace(&*c, static_cast<std::uint32_t>(numbering.cells.size()));
  }
  out.u64(numbering.vertices.size());
  out.u64(numbering.cells.size());
  out.u32(numbering.vertex(tri.infinite_vertex()));
  for (auto v = tri.all_vertices_begin(); v != tri.all_vertices_end(); ++v) {
    writePoint(out, tri.is_infinite(v) ? Point(0, 0, 0) : v->point());
    writeVertexInfo(out, v->info());
    out.u32(numbering.cell(v->cell()));
  }
  for (auto c = tri.all_cells_begin(); c != tri.all_cells_end(); ++c) {
    for (int i = 0; i < 4; ++i) out.u32(numbering.vertex(c->vertex(i)));
    for (int i = 0; i < 4; ++i) out.u32(numbering.cell(c->neighbor(i)));
    writeCellInfo(out, c->info());
  }
}

void CheckpointAccess::readTriangulation(MapState& state, ByteReader& in, Handles& handles) {
  in.section("triangulation");
  const std::uint8_t dimension = in.u8();
  if (dimension == 0) return;  // empty: the fresh triangulation is right as it is
  if (dimension != 3) in.fail("dimension 0 (empty) or 3, got " + std::to_string(dimension));
  const std::size_t vertex_count = in.count(kVertexRecordBytes);
  const std::size_t cell_count = in.count(kCellRecordBytes);
  if (vertex_count < 5 || cell_count < 4 || vertex_count > kNone || cell_count > kNone) {
    in.fail("a 3D triangulation (at least 5 vertices and 4 cells)");
  }
  auto& tds = state.tri.tds();
  tds.clear();
  handles.vertices.reserve(vertex_count);
  handles.cells.reserve(cell_count);
  for (std::size_t i = 0; i < vertex_count; ++i) handles.vertices.push_back(tds.create_vertex());
  for (std::size_t i = 0; i < cell_count; ++i) handles.cells.push_back(tds.create_cell());
  tds.set_dimension(3);
  state.tri.set_infinite_vertex(handles.vertex(in, "infinite vertex"));
  for (const VertexHandle& v : handles.vertices) {
    const double x = in.f64();
    const double y = in.f64();
    const double z = in.f64();
    v->set_point(Point(x, y, z));
    readVertexInfo(in, v->info());
    v->set_cell(handles.cell(in, "vertex's cell"));
  }
  for (const CellHandle& c : handles.cells) {
    for (int i = 0; i < 4; ++i) c->set_vertex(i, handles.vertex(in, "cell vertex"));
    for (int i = 0; i < 4; ++i) c->set_neighbor(i, handles.cell(in, "cell neighbour"));
    readCellInfo(in, c->info());
  }
  if (!state.tri.is_valid(false)) in.fail("a valid Delaunay triangulation");
}

void CheckpointAccess::writeGridAndHash(const MapState& state, ByteWriter& out, const Numbering& numbering) {
  const SteinerGrid& grid = state.grid;
  out.f64(grid.step_);
  out.f64(grid.origin_.x());
  out.f64(grid.origin_.y());
  out.f64(grid.origin_.z());
  out.u8(grid.initialized_ ? 1 : 0);
  writeKey(out, grid.lo_);
  writeKey(out, grid.hi_);
  // A sparse lattice (the online freeze let nodes go): the nodes it holds, sorted, for equal bytes.
  out.u8(grid.sparse_ ? 1 : 0);
  if (grid.sparse_) {
    std::vector<GridKey> present(grid.present_.begin(), grid.present_.end());
    std::sort(present.begin(), present.end(), [](const GridKey& a, const GridKey& b) {
      return std::tie(a.i, a.j, a.k) < std::tie(b.i, b.j, b.k);
    });
    out.u64(present.size());
    for (const GridKey& key : present) writeKey(out, key);
  }

  const BoundaryHash& hash = state.hash;
  out.u8(hash.spatial_ ? 1 : 0);
  out.u64(hash.size_);
  out.u64(hash.buckets_.bucket_count());
  out.u64(hash.buckets_.size());
  for (const auto& [key, vertices] : hash.buckets_) {
    writeKey(out, key);
    out.u64(vertices.size());
    for (const VertexHandle& v : vertices) out.u32(numbering.vertex(v));
  }
  out.u64(state.outside.size_);
  // Only looked up, never iterated: saved sorted by key, so equal maps give equal bytes.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> nodes;
  nodes.reserve(state.steiner_nodes.size());
  for (const auto& [key, v] : state.steiner_nodes) nodes.emplace_back(key, numbering.vertex(v));
  std::sort(nodes.begin(), nodes.end());
  out.u64(nodes.size());
  for (const auto& [key, v] : nodes) {
    out.u64(key);
    out.u32(v);
  }
}

void CheckpointAccess::readGridAndHash(MapState& state, ByteReader& in, const Handles& handles) {
  in.section("Steiner grid");
  SteinerGrid& grid = state.grid;
  const double step = in.f64();
  if (step != grid.step_) in.fail("the Steiner step of the saved configuration");
  grid.origin_.x() = in.f64();
  grid.origin_.y() = in.f64();
  grid.origin_.z() = in.f64();
  grid.initialized_ = in.flag();
  grid.lo_ = readKey(in);
  grid.hi_ = readKey(in);
  if (!grid.origin_.allFinite()) in.fail("a finite grid origin");
  grid.sparse_ = in.flag();
  grid.present_.clear();
  if (grid.sparse_) {
    const std::size_t count = in.count(12);
    grid.present_.reserve(count);
    for (std::size_t n = 0; n < count; ++n) {
      const GridKey key = readKey(in);
      const bool inside = key.i >= grid.lo_.i && key.i <= grid.hi_.i && key.j >= grid.lo_.j && key.j <= grid.hi_.j &&
                          key.k >= grid.lo_.k && key.k <= grid.hi_.k;
      if (!inside || !grid.present_.insert(key).second) in.fail("each lattice node once, within the grid's bounds");
    }
  }

  in.section("boundary hash");
  BoundaryHash& hash = state.hash;
  if (in.flag() != hash.spatial_) in.fail("the boundary-hash mode of the saved configuration");
  const std::uint64_t size = in.u64();
  const std::uint64_t bucket_count = in.u64();
  std::vector<std::pair<GridKey, std::vector<VertexHandle>>> buckets(in.count(12 + 8));
  std::uint64_t total = 0;
  for (auto& [key, vertices] : buckets) {
    key = readKey(in);
    vertices.resize(in.count(4));
    for (VertexHandle& v : vertices) {
      v = handles.vertex(in, "hashed vertex");
      if (v->info().hash_slot != kNone) in.fail("each vertex hashed once");
      v->info().hash_slot = static_cast<std::uint32_t>(&v - vertices.data());
    }
    total += vertices.size();
  }
  if (total != size) in.fail("a hash size equal to its vertices");
  // Same bucket count, inserted in reverse: each insertion goes to the front of its bucket's run,
  // so the table iterates in the saved order.
  hash.buckets_.clear();
  if (bucket_count > hash.buckets_.bucket_count()) hash.buckets_.rehash(static_cast<std::size_t>(bucket_count));
  for (auto it = buckets.rbegin(); it != buckets.rend(); ++it) {
    if (!hash.buckets_.emplace(it->first, std::move(it->second)).second) in.fail("distinct bucket keys");
  }
  hash.size_ = static_cast<std::size_t>(size);

  in.section("outside set");
  state.outside.size_ = static_cast<std::size_t>(in.u64());
  in.section("Steiner nodes");
  const std::size_t nodes = in.count(12);
  std::vector<std::pair<std::uint64_t, VertexHandle>> entries(nodes);
  for (auto& [key, v] : entries) {
    key = in.u64();
    v = handles.vertex(in, "Steiner vertex");
  }
  state.steiner_nodes.clear();
  state.steiner_nodes.reserve(nodes);
  for (const auto& [key, v] : entries) {
    if (!state.steiner_nodes.emplace(key, v).second) in.fail("distinct Steiner node keys");
  }
}

void CheckpointAccess::write(const Mesher& mesher, ByteWriter& out) {
  const Mesher::Impl& impl = *mesher.impl_;
  const MapState& state = impl.state_;
  Numbering numbering;
  writeTriangulation(state, out, numbering);
  writeGridAndHash(state, out, numbering);
  out.u32(state.next_uid);
  out.u64(state.steiner_vertices);
  const CellHandle hint = impl.editor_.hint_;
  const bool hint_alive = hint != CellHandle() && state.tri.tds().cells().is_used(hint);
  out.u32(hint_alive ? numbering.cell(hint) : kNone);
  writeRays(state.rays, out, numbering);
  writeRegistry(state.registry, state, out, numbering);
  writeFreeBoxes(state, out);
  writeSurfaceLog(state.surface_log, out);
  out.vector(impl.pending_removals_);
  writeBallRefusals(impl.grower_, out);
}

void CheckpointAccess::read(Mesher& mesher, ByteReader& in) {
  Mesher::Impl& impl = *mesher.impl_;
  MapState& state = impl.state_;
  Handles handles;
  readTriangulation(state, in, handles);
  readGridAndHash(state, in, handles);
  in.section("mesher");
  state.next_uid = in.u32();
  state.steiner_vertices = static_cast<std::size_t>(in.u64());
  impl.editor_.hint_ = handles.cell(in, "editor hint", true);
  readRays(state.rays, in, handles);
  readRegistry(state.registry, in, handles);
  readFreeBoxes(state, in);
  readSurfaceLog(state.surface_log, in);
  in.section("pending removals");
  impl.pending_removals_ = in.vector<std::uint32_t>();
  for (std::uint32_t index : impl.pending_removals_) {
    if (index >= state.registry.pointSlots()) in.fail("a pending removal naming a point slot");
  }
  readBallRefusals(impl.grower_, in, state);
  // Cross-references between sections.
  in.section("cross-references");
  for (const VertexHandle& v : handles.vertices) {
    if (v->info().point != kNone && v->info().point >= state.registry.pointSlots()) {
      in.fail("a vertex's point index below " + std::to_string(state.registry.pointSlots()));
    }
  }
  for (const CellHandle& c : handles.cells) {
    if (c->info().ray_list != kNone && c->info().ray_list >= state.rays.lists_.size()) {
      in.fail("a cell's ray list below " + std::to_string(state.rays.lists_.size()));
    }
  }
  if (!in.atEnd()) in.fail("the end of the payload");
}

}  // namespace terramesh::mesher::internal
