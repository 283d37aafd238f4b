#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "traversability/layered_mesh.h"
#include "traversability/robot_profile.h"

namespace terramesh::planning {

/// Which faces a robot may stand on and how much driving over them costs.
struct WalkabilityConfig {
  /// A free face closer than this (geodesic `lethal_distance_m` layer) to a lethal face is not
  /// walkable: the robot's footprint would touch it. Use the footprint's inscribed radius.
  double min_lethal_distance_m = 0.3;
  /// Cost weight w in the per-metre multiplier 1 + w * cost (cost in [0, 1], see docs/planning.md).
  double cost_weight = 4.0;
  /// A face whose normal is more than this from "up" is never walkable, whatever its class says
  /// (guards against walls or ceilings classed free by a wrong up vector).
  double max_face_tilt_deg = 60.0;
  /// Nav2's `allow_unknown`: unknown faces (touching a Steiner vertex, or seen by fewer than the
  /// robot's min_rays) are walkable too, under the same tilt and lethal-distance rules as free
  /// faces, at cost `unknown_cost`. Lethal faces never are. Off by default: on our maps such
  /// paths leave the measured surface (docs/planning.md, "Crossing unknown faces").
  bool allow_unknown = false;
  /// The cost in [0, 1] of an unknown face when allow_unknown: its per-metre multiplier is
  /// 1 + cost_weight * unknown_cost. 1 = as dear as the dearest free face (Nav2's NavFn gives an
  /// unknown cell COST_OBS - 1, at least the cost of every free cell).
  double unknown_cost = 1.0;
  /// Uncertain faces (measured, but the evidence cannot decide: FaceClass::kUncertain) are walkable
  /// too, at their own cost (the profile's evidence.uncertain_cost), under the same rules as free
  /// faces. Off by default: a path there may meet a step or an obstacle the map could not exclude.
  bool allow_uncertain = false;
  /// A rectangular robot's contact_headings (RobotProfile): the direction of travel over a face
  /// must fit its `heading_fits` layer (FaceGraph::headingFits). 0: no heading test (a disc).
  int heading_count = 0;
  /// With heading_count > 0: the body keeps a heading of its own (MotionModel::kOmni), which the
  /// faces it stands on must fit, instead of facing its direction of travel. It turns on the spot
  /// one judged heading at a time, on a face that fits both.
  bool omni = false;
  /// The cost of turning an omni body on the spot, metres of travel per radian.
  double turn_cost_m_per_rad = 0.1;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// The walkability of a robot profile's robot: free faces at least its inscribed radius from a
/// lethal face, and a rectangle's headings (of travel, or of its body with MotionModel::kOmni) kept to
/// those its footprint fits at.
WalkabilityConfig walkabilityFor(const traversability::RobotProfile& profile);

/// A point on the surface: a face and a position on it (map frame, map units).
struct SurfaceLocation {
  /// The face, or FaceGraph::kNoFace for a point of a path planned on another map (the OctoMap
  /// baseline's grid).
  std::uint32_t face = 0;
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();
};

/// Why a surface walk stopped before its target.
enum class WalkStop {
  kReached,      ///< arrived at the target
  kBlocked,      ///< entered a face that is not walkable (lethal, unknown, too close to lethal)
  kBoundary,     ///< met an edge of the mesh with no face across it
  kStuck,        ///< the target is not ahead along the surface (another floor, behind a fold)
  kTooLong,      ///< walked farther than the allowed detour
};

/// The polyline a walk followed: the start, every edge crossing, the end. Each point's face is
/// the face the next piece lies on. Lengths in metres.
struct SurfaceWalk {
  WalkStop stop = WalkStop::kReached;
  std::vector<SurfaceLocation> points;
  double length_m = 0;
  /// Integral of (1 + w * cost) along the polyline, in metres.
  double cost = 0;
  bool reached() const { return stop == WalkStop::kReached; }
};

/// The turn of a body that keeps its own heading (WalkabilityConfig::omni) over a walk: from
/// heading `from_W` (horizontal direction) by `turn_rad` about up, counter-clockwise from above.
struct BodyTurn {
  Eigen::Vector3d from_W = Eigen::Vector3d::UnitX();
  double turn_rad = 0;
};

/// A path over the face graph: a polyline from the start point to the goal point through points
/// on shared edges; piece i (points i to i+1) lies on face faces[i].
struct GraphPath {
  bool found = false;
  std::vector<Eigen::Vector3d> points_W;
  std::vector<std::uint32_t> faces;
  /// WalkabilityConfig::omni: per point, the horizontal unit direction the body faces (a turn on the
  /// spot repeats the point with the new heading). Empty when the body faces its travel.
  std::vector<Eigen::Vector3d> body_headings_W;
  double length_m = 0;
  double cost = 0;  ///< same formula as SurfaceWalk::cost
  std::size_t expanded = 0;  ///< nodes popped from the queue
};

/// The mesh of a traversability map prepared for planning: per-face normal, area, neighbours
/// across edges, walkability and walkable components, the surface walk, snapping and the
/// Dijkstra/A* baseline over the face graph.
///
/// Built once (O(F log F)); all const members are thread-safe (no mutable state), as OMPL's
/// validity checkers and motion validators require.
class FaceGraph {
 public:
  static constexpr std::uint32_t kNoFace = std::numeric_limits<std::uint32_t>::max();

  /// Copies what it needs from `map`.
  /// @throw std::invalid_argument if the config does not validate, the layers do not match the
  ///        faces, a face indexes a missing vertex, or metres_per_unit is not > 0.
  FaceGraph(const traversability::LayeredMesh& map, const WalkabilityConfig& config);

  std::size_t faceCount() const { return faces_.size(); }
  const std::array<std::uint32_t, 3>& face(std::uint32_t f) const { return faces_[f]; }
  const Eigen::Vector3d& vertex(std::uint32_t v) const { return vertices_[v]; }
  const Eigen::Vector3d& normal(std::uint32_t f) const { return normals_[f]; }
  Eigen::Vector3d centroid(std::uint32_t f) const;
  /// Face area in map units squared.
  double area(std::uint32_t f) const { return areas_[f]; }
  /// The face across edge e (vertices e, e+1 mod 3) of f, or kNoFace (boundary or non-manifold).
  std::uint32_t neighbour(std::uint32_t f, int e) const { return neighbours_[f][static_cast<std::size_t>(e)]; }
  bool walkable(std::uint32_t f) const { return walkable_[f] != 0; }
  /// Per-metre cost multiplier 1 + w * cost of a walkable face.
  double costMultiplier(std::uint32_t f) const { return multipliers_[f]; }
  /// The cost in [0, 1] the planner uses for a walkable face: its layer cost, or
  /// WalkabilityConfig::unknown_cost for an unknown face (allow_unknown); NaN if not walkable.
  double plannedCost(std::uint32_t f) const;
  /// Whether a walkable face is walkable only because unknown faces are allowed.
  bool walkableUnknown(std::uint32_t f) const {
    return walkable_[f] != 0 && layers_[f].face_class == traversability::FaceClass::kUnknown;
  }
  /// Walkable component id (faces joined across shared edges), or kNoFace if not walkable.
  std::uint32_t component(std::uint32_t f) const { return components_[f]; }
  std::size_t componentCount() const { return component_areas_.size(); }
  /// Area of a component, map units squared.
  double componentArea(std::uint32_t c) const { return component_areas_[c]; }
  std::size_t walkableFaceCount() const { return walkable_faces_.size(); }
  /// Walkable faces in index order.
  const std::vector<std::uint32_t>& walkableFaces() const { return walkable_faces_; }
  double metresPerUnit() const { return metres_per_unit_; }
  const Eigen::Vector3d& up() const { return up_W_; }
  const WalkabilityConfig& config() const { return config_; }
  /// Whether the body keeps a heading of its own (WalkabilityConfig::omni, with judged headings).
  bool keepsOwnHeading() const { return config_.omni && config_.heading_count > 0; }
  const traversability::FaceLayers& layers(std::uint32_t f) const { return layers_[f]; }

  /// Whether the robot may cross walkable face f travelling along `direction_W` (its horizontal
  /// part), the heading kept to those the footprint fits at in the worst case: with
  /// WalkabilityConfig::heading_count N > 0 and a face whose `heading_fits` has a bit set, the
  /// heading's two neighbours among the N judged ones (k x 180 / N deg from the first axis of
  /// geometry::planFrame(up)) must both fit, or the one it lies on. True otherwise (a disc; a face
  /// no judged heading fits but that is free all the same: driven ground, along its drive).
  bool headingFits(std::uint32_t f, const Eigen::Vector3d& direction_W) const;
  /// Whether a body on walkable face f fits while it turns from heading `from_W` (its horizontal
  /// part) by `turn_rad` about up (counter-clockwise seen from above): every judged heading the
  /// turn passes, and the two around each end, must fit (a rectangle turned by 180 deg is the
  /// same). headingFits(f, d) is turnFits(f, d, 0). True where headingFits is true for every
  /// heading, and for a direction without horizontal part.
  bool turnFits(std::uint32_t f, const Eigen::Vector3d& from_W, double turn_rad) const;
  /// Whether judged heading k of WalkabilityConfig::heading_count fits face f (true for a disc
  /// and for a face no judged heading fits, as headingFits).
  bool judgedHeadingFits(std::uint32_t f, int k) const;
  /// Judged heading k: the horizontal unit direction k x 180 / heading_count deg about up from the
  /// plan frame's first axis.
  Eigen::Vector3d judgedHeading(int k) const;

  /// The nearest point on a walkable face within `radius_m` (metres) of `query_W`, or nothing.
  /// O(F). Ties go to the lowest face index.
  std::optional<SurfaceLocation> snap(const Eigen::Vector3d& query_W, double radius_m) const;

  /// Walks over the surface from `from` towards `to`: on each face along the straight line to
  /// the target projected into the face's plane, crossing shared edges to the next face, until
  /// the target face is reached. With `to.face == kNoFace` the walk ends where the projected
  /// target lies inside the current face. With `require_walkable` it stops at the first face that
  /// is not walkable. Stops when the walked length exceeds `max_detour` times the straight
  /// distance (plus one metre), or after 16 edge crossings in a row that make no progress
  /// (round a vertex, back and forth over a ridge). O(faces crossed).
  /// With `body` (WalkabilityConfig::omni), the body turns from `body->from_W` by
  /// `body->turn_rad` over the walk, and each face must fit that whole turn (turnFits) instead of
  /// the heading of travel.
  SurfaceWalk walk(const SurfaceLocation& from, const SurfaceLocation& to, bool require_walkable,
                   double max_detour = 3.0, const std::optional<BodyTurn>& body = std::nullopt) const;

  /// A* over the walkable faces with `points_per_edge` evenly spaced nodes on every edge (plus
  /// start and goal): every two nodes of a walkable face are joined by the straight piece across
  /// it, weighted by length times the face's cost multiplier; heuristic: straight distance
  /// (admissible, multipliers >= 1). The classic Steiner-point approximation of the weighted
  /// shortest path on the surface (it converges to it as points_per_edge grows): the graph
  /// optimum the sampling planners are judged against. The crossings are then slid along their
  /// edges to the cheapest polyline through the same edge sequence (convex; coordinate descent).
  /// `found` is false if the goal is not in the start's component. O(F k^2 log(F k)) for k
  /// points per edge. With WalkabilityConfig::omni the nodes carry the body's judged heading too
  /// (N of them): a piece keeps it, and the body turns on the spot by one heading at a time at
  /// turn_cost_m_per_rad, on a face that fits both. O(N F k^2 log(N F k)).
  /// @throw std::invalid_argument if points_per_edge < 1.
  GraphPath shortestPath(const SurfaceLocation& start, const SurfaceLocation& goal, int points_per_edge = 4) const;

 private:
  void computeWalkability(const traversability::LayeredMesh& map);
  void computeNeighbours();
  void computeComponents();
  /// shortestPath's search over (node, body heading) for WalkabilityConfig::omni.
  GraphPath omniShortestPath(const SurfaceLocation& start, const SurfaceLocation& goal, std::uint32_t k) const;
  /// The end points of the edge node `node` lies on, of shortestPath's nodes (k per edge; the
  /// start and goal nodes after them lie at `start_W` and `goal_W`).
  std::array<Eigen::Vector3d, 2> nodeEdge(std::uint32_t node, std::uint32_t k, const Eigen::Vector3d& start_W,
                                          const Eigen::Vector3d& goal_W) const;
  /// The position of shortestPath's node `node`.
  Eigen::Vector3d nodePosition(std::uint32_t node, std::uint32_t k, const Eigen::Vector3d& start_W,
                               const Eigen::Vector3d& goal_W) const;
  /// Slides the crossings of a found path along their edges and fills its length and cost.
  void finishPath(GraphPath& path, const std::vector<std::array<Eigen::Vector3d, 2>>& ends) const;
  /// The point of the edge (or vertex) shared by faces a and b on the shortest way from `from`
  /// to `to` through it.
  Eigen::Vector3d sharedCrossing(const std::array<std::uint32_t, 3>& a, const std::array<std::uint32_t, 3>& b,
                                 const Eigen::Vector3d& from, const Eigen::Vector3d& to) const;

  WalkabilityConfig config_;
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<std::uint32_t, 3>> faces_;
  std::vector<traversability::FaceLayers> layers_;
  std::vector<Eigen::Vector3d> normals_;
  std::vector<double> areas_;
  std::vector<std::array<std::uint32_t, 3>> neighbours_;
  /// Undirected edge id of each face edge; per edge its two vertices.
  std::vector<std::array<std::uint32_t, 3>> face_edges_;
  std::vector<std::array<std::uint32_t, 2>> edge_vertices_;
  /// The faces joined by each edge (the second is kNoFace on boundary or non-manifold edges).
  std::vector<std::array<std::uint32_t, 2>> edge_faces_;
  std::vector<std::uint8_t> walkable_;
  std::vector<double> multipliers_;
  std::vector<std::uint32_t> components_;
  std::vector<double> component_areas_;
  std::vector<std::uint32_t> walkable_faces_;
  Eigen::Vector3d up_W_ = Eigen::Vector3d::UnitZ();
  /// The plan frame's first two axes, which the judged headings are measured from.
  Eigen::Vector3d heading_e1_ = Eigen::Vector3d::UnitX();
  Eigen::Vector3d heading_e2_ = Eigen::Vector3d::UnitY();
  double metres_per_unit_ = 1.0;
};

/// Lower-case name of a walk stop ("reached", "blocked", ...).
const char* toString(WalkStop stop);

}  // namespace terramesh::planning
