#pragma once

#include <queue>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "grid_key.h"
#include "map_state.h"
#include "mesher/update_stats.h"

namespace terramesh::mesher::internal {

class CheckpointAccess;

/// Manifold growing: carves free cells into O in order of decreasing weight (cells crossed by a ray
/// to a driven-ground sample first, the robot's body having passed there), adding a cell only if
/// the boundary stays a 2-manifold; then (proposed mode) the edge pass, which adds all free cells
/// around an edge of a refused cell at once; then the per-vertex pass that adds all cells around a
/// boundary vertex at once (which lets the surface change genus); then (proposed mode) the ball
/// pass, which adds a heavy refused cell with one free neighbour or with every free cell sharing a
/// vertex with it (issue 14: on the synthetic street it carves free space the single-cell, edge
/// and vertex tests all refuse; docs/accuracy.md). The edge and ball passes count their cells in
/// UpdateStats::edge_pass_cells and are switched off together (`edge_growing_pass`).
///
/// Handle control (`MesherConfig::handle_min_rays`, off at 0): a single cell that passes the vertex
/// test never adds a handle (its contact with O is a disc or all of it); a set added at once (the
/// edge, per-vertex and ball passes) can. Such a set is added only if some cell of it is crossed by
/// at least that many rays, so tunnels carved by few rays through thin matter stay closed
/// (docs/algorithms.md).
class Grower {
 public:
  explicit Grower(MapState& state) : state_(state) {}

  /// Grows from this update's candidates (cells that became free or were shrunk) and from the
  /// boundary near the change: the hashed vertices of `region` (proposed mode), or the whole
  /// boundary when `region` is null (baseline modes, which scan the boundary list).
  void grow(const std::unordered_set<GridKey, GridKeyHash>* region, UpdateStats& stats);

 private:
  friend class CheckpointAccess;  // saves and restores ball_refusals_ (kept between updates)

  struct QueueEntry {
    std::int64_t priority;
    std::uint32_t uid;
    CellHandle cell;
    bool operator<(const QueueEntry& other) const {
      return priority != other.priority ? priority < other.priority : uid < other.uid;
    }
  };

  bool adjacentToOutside(const CellHandle& cell) const;
  void push(const CellHandle& cell);
  void pushFreeNeighbours(const CellHandle& cell);
  void drainQueue(UpdateStats& stats);
  void genusPass(UpdateStats& stats);
  /// For each cell still refused, tries adding at once all free non-O cells around one of its
  /// edges; growing resumes after each success.
  void edgePass(UpdateStats& stats);
  void scanVertex(const VertexHandle& v);
  /// Adds all of `set` (at least two cells, none in O) if that keeps the boundary manifold, then
  /// resumes growing from them. Returns whether it did.
  bool tryAddSet(std::vector<CellHandle>& set, UpdateStats& stats);
  /// The second half of tryAddSet, for a set that passed the manifold test.
  bool addIfHandleRuleAllows(std::vector<CellHandle>& set, UpdateStats& stats);
  /// Tries `cell` together with one free face-neighbour, then with every free non-O cell sharing a
  /// vertex with it (its ball).
  bool tryAddBall(const CellHandle& cell, UpdateStats& stats);
  /// For each heavy cell still refused after the edge and per-vertex passes, tries its ball; a
  /// ball refused before is tried again only once the cell's neighbourhood changed, at most
  /// kMaxBallAttemptsPerGrow per update.
  void ballPass(UpdateStats& stats);
  std::uint64_t neighbourhoodSignature(const CellHandle& cell) const;
  /// For each cell the robot's body passed through (MesherConfig::driven_cells_first) still refused,
  /// tries its pocket: the free non-O cells connected to it, at most kMaxPocketCells, in
  /// breadth-first order from it. Where adding them all would leave a vertex irregular, the
  /// pocket's cell around that vertex found last is dropped, with the cells then no longer joined to
  /// O through the pocket, and the rest tried, at most kMaxPocketRounds times. At most
  /// kMaxPocketAttemptsPerGrow pockets per update.
  void drivenPocketPass(UpdateStats& stats);
  bool tryAddPocket(const CellHandle& cell, UpdateStats& stats);
  /// Keeps the cells of `set` joined, through face-neighbours in `set`, to a cell next to O.
  void keepJoinedToOutside(std::vector<CellHandle>& set);
  /// Change of V - E + F of dO if all of `set` (none in O, finite, no duplicates) joined O.
  /// Negative: the set closes a loop of O (genus + 1), joins two parts of O or fills a cavity.
  /// O(|set| * edge degree).
  /// `fills_cavity`: every facet of the set not shared by two of its cells is a facet of O.
  int boundaryEulerChange(const std::vector<CellHandle>& set, bool& fills_cavity);
  /// Whether `set` (which passed the manifold test) may be added under the handle rule: always
  /// when the rule is off, when the addition keeps V - E + F of dO, fills a cavity, or some cell of
  /// it is crossed by at least handle_min_rays rays.
  bool handleRuleAllows(const std::vector<CellHandle>& set);

  static constexpr std::size_t kMaxBallAttemptsPerGrow = 32;
  static constexpr std::size_t kMaxBallRefusalsRemembered = 1u << 16;
  static constexpr std::size_t kMaxPocketAttemptsPerGrow = 32;
  static constexpr std::size_t kMaxPocketCells = 64;
  static constexpr int kMaxPocketRounds = 32;

  MapState& state_;
  std::priority_queue<QueueEntry> queue_;
  std::vector<VertexHandle> touched_vertices_;
  std::vector<CellHandle> scratch_;
  /// Cells refused at the end of the drains of this grow, for the edge pass.
  std::vector<CellHandle> final_refused_;
  /// Cells the edge pass tried, for the ball pass.
  std::vector<CellHandle> ball_candidates_;
  std::vector<CellHandle> ball_;
  /// Refused cells the robot's body passed through, for the pocket pass.
  std::vector<CellHandle> driven_refused_;
  std::vector<CellHandle> pocket_;
  /// An edge of a cell of the set whose Euler change is computed: its ends (ordered) and where.
  struct SetEdge {
    const Delaunay::Vertex* a;
    const Delaunay::Vertex* b;
    CellHandle cell;
    int i;
    int j;
  };
  std::vector<SetEdge> euler_edges_;
  std::vector<VertexHandle> euler_vertices_;
  /// Cells whose ball was refused (by CellInfo::uid), with their neighbourhood signature then. The
  /// only Grower state kept from one update to the next (the rest is scratch), so it is part of
  /// checkpoints (checkpoint_records.cpp). Only looked up, never iterated: the passes do not depend
  /// on its hash order. Between updates it holds at most kMaxBallRefusalsRemembered entries.
  std::unordered_map<std::uint32_t, std::uint64_t> ball_refusals_;
};

}  // namespace terramesh::mesher::internal
