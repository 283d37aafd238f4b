#pragma once
// The per-face layers that depend on the geometry around one face (slope, step, roughness,
// contact, clearance, observedness), the lethal test and the combined cost. Internal.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "surface_store.h"
#include "traversability/robot_profile.h"
#include "unconfirmed_points.h"

namespace terramesh::traversability::internal {

/// Computes the local layers of faces of a SurfaceStore for one robot. Not thread-safe.
///
/// Footprint model (docs/traversability.md): samples on a square grid (spacing R/K, R the
/// footprint circumradius, K >= 5 and at least 4 spacings across a rectangle's width) within the
/// disc of radius R around the face centroid, in the horizontal plane. At each sample a vertical
/// ray finds the upward-facing surface closest to the face's plane (a horizontal plane through
/// the centroid for faces steeper than max_slope), within
/// [plane - max(min_clearance, 2 max_step), plane + min_clearance]: higher geometry is overhead,
/// lower is a drop.
///
/// The footprint is the disc (one heading), or the rectangle turned to each of contact_headings
/// headings over half a turn (its samples: the grid's samples inside it). Per heading:
/// - step: max - min of the residuals of the centroid and the found samples from the
///   least-squares plane of the face's level (the samples near the face's plane; a jump that
///   plane cannot explain, independent of the slope); for steep faces, max - min of the heights;
/// - roughness: RMS of the residuals from the plane fitted to all found samples;
/// - contact: the fraction of the samples whose surface lies within max_step_m +
///   contact_tolerance_m of the face's plane (a wheel or foot can reach it: a curb the robot may
///   climb still supports it, a ledge or hole does not), over the known samples but at least
///   kMinKnownSampleFraction of all. Samples find measured ground only: a sample whose band holds
///   only Steiner faces is unknown (no data: no ground, step, roughness or missing support);
/// - obstacles (the robot's body): the parts of measured faces that are not ground (steeper than
///   max_slope: walls, the sides of obstacles, undersides and ceilings) lying between max_step_m
///   and min_clearance_m above the face's reference plane, projected on the horizontal plane; the
///   footprint (the exact disc or rectangle, not its samples) meeting one collides. The step of
///   that heading is then at least the obstacle's top above the plane (capped at min_clearance_m),
///   so it does not fit. Interpolated faces (touching a Steiner vertex, or no ray in front of them)
///   and faces anchored on driven ground are only possible obstacles: never lethal, they make the
///   face uncertain (worst case, layer_evidence.cpp). Upward-facing ground rising inside the footprint is
///   judged by the step instead. A ground face larger than the footprint blocked (at every heading)
///   at its centroid counts as blocked only if it is also blocked at more than half of its
///   obstaclePoints.
/// The footprint fits at a heading if step, roughness and contact are within the robot's limits;
/// step and roughness are reported at the best heading (one that fits, else the closest to
/// fitting), contact at the worst and the best.
/// - clearance: vertical ray up from the centroid to the first face whose projection contains it.
class LayerComputer {
 public:
  explicit LayerComputer(const RobotProfile& profile);

  /// Horizontal reach of a face's local layers: a change farther than this (in the horizontal
  /// plane, from the face's centroid) cannot change them.
  double reachM() const { return radius_m_; }
  /// Horizontal reach of the footprint grown by `margin_m` as the obstacle test grows it (meets):
  /// a disc's radius plus the margin; a rectangle's half length and half width each plus the
  /// margin, to its corner (farther than the circumradius plus the margin).
  double footprintReachM(double margin_m) const;
  /// Horizontal reach of obstacles for the largest faces (judged at points up to reachM() from
  /// their centroid, see computeLocal), and of the possible extension of measured obstacles
  /// (EvidenceModel::max_obstacle_extension_m): no face's layers reach farther.
  double maxReachM() const { return radius_m_ + footprintReachM(profile_.evidence.max_obstacle_extension_m); }

  /// Fills slope, step, roughness, contact, clearance, rays and steiner of face `s`. Reads the
  /// evidence of the faces around it (setEvidence first) and the unconfirmed points around it
  /// (setUnconfirmedPoints; none if never set).
  void computeLocal(SurfaceStore& store, Slot s) const;

  /// The SLAM points not in the mesh, read by computeLocal as possible obstacles: a point inside a
  /// face's body (between max_step_m and min_clearance_m above its reference plane) stands for an
  /// obstacle of radius EvidenceModel::unconfirmed_point_extension_m that nobody confirmed (a rock
  /// seen from one keyframe). Kept by the caller, which must outlive this computer's use of it.
  void setUnconfirmedPoints(const UnconfirmedPoints* points) { unconfirmed_ = points; }
  /// The drive's sensor above the ground contact plane, metres (nullopt: unknown). Over driven
  /// ground, interpolated geometry counts only up to it: beside the strip no ray looks higher
  /// (rays run from the sensor down to the ground), so a lid there is where the carving stopped,
  /// not a sign that anything stands in the body; what stands on the ground shows below it.
  void setDriveSensorHeight(std::optional<double> height_m);
  /// Horizontal reach of an unconfirmed point: a face whose projection is farther from it cannot
  /// meet it (a robot may stand anywhere on a face).
  double unconfirmedReachM() const { return footprintReachM(profile_.evidence.unconfirmed_point_extension_m); }

  /// Sets the evidence and height uncertainty of face `s` (its layers and its sampling geometry)
  /// from the face: its vertices, its horizontal span and whether rays crossed the free space in
  /// front of it; and, for a possible step (a gentle face rising more than max_step_m, with
  /// nothing supporting its inside), its whole rise: the step may stand anywhere on it, so a
  /// footprint sampling it may meet the top. That reads its edge neighbours' vertices
  /// (slopeSupport), so TraversabilityMap sets it again when they change. Returns whether the
  /// evidence, the bound or the relief changed.
  bool setEvidence(SurfaceStore& store, Slot s) const;
  /// Two driven vertices and a third beside them, level within a step, its centroid within the
  /// footprint's half width of the drive: the edge of the strip the robot drove.
  bool onDrivenEdge(const StoredFace& f) const;
  /// Whether rays saw the space a face closes off as free: at least max(1, min_rays) rays crossed
  /// the cell behind it (fewer: a point's noise). The 2-manifold keeps such a face; it is no
  /// measured surface.
  bool seenBehind(const StoredFace& f) const {
    return f.back_crossings >= static_cast<std::uint32_t>(std::max(1, profile_.min_rays));
  }
  /// A lid: a face seen behind (seenBehind) no steeper than max_slope_deg.
  bool isLid(const StoredFace& f) const { return f.normal_L.z() >= cos_max_slope_ && seenBehind(f); }
  /// How deep the void under a lid may be (the depth of the cell behind it,
  /// StoredFace::back_depth_m); 0 for any other face.
  double lidDepthM(const StoredFace& f) const { return isLid(f) ? f.back_depth_m : 0.0; }
  /// How deep the void under a lid may reach under the faces around its vertices: its depth where
  /// the lid spans a rim at one level (it rises no more than max_step_m) over a drop the robot
  /// cannot step down (deeper than max_step_m); 0 otherwise (a lid rising more is a tent over
  /// whatever lies under its high side).
  double rimVoidM(const StoredFace& f) const {
    const double depth = lidDepthM(f);
    return f.max_z - f.min_z <= profile_.max_step_m && depth > profile_.max_step_m ? depth : 0.0;
  }
  /// How deep the free space under a fold may reach under the faces at its vertices that lie over
  /// it and that it hangs below (setEvidence). A fold is a face facing down (its normal more than
  /// 30 degrees below horizontal), dropping more than three sigmas of the points' noise from its
  /// top vertex, that rays crossed under (the cell in front of it) but no keyframe saw from below
  /// (no view on its front side: an underside seen from below, a deck's or a car's, has matter
  /// over it that was seen from both sides), and that does not hang down to the underside under
  /// driven ground (a deck's slab, put there by the drive: no camera saw it, and no ray crossed
  /// under the drive that was not meant to). Where it hangs from ground, rays from above reached
  /// under that ground: the ground over it is a crust over free space whose depth nothing
  /// measured, so the worst case takes it as deep as a footprint sample looks for ground
  /// (band_down_m_), or deeper if the fold shows it. 0 for any other face.
  double foldVoidM(const StoredFace& f) const {
    const double drop = f.max_z - f.min_z;
    const bool fold = !f.steiner && f.underside_vertices == 0 && f.front_crossings > 0 &&
                      f.normal_L.z() < kMaxFoldNormalZ && (f.view_sides & mesher::view_side::kFront) == 0 &&
                      drop > 3.0 * profile_.evidence.point_noise_m;
    return fold ? std::max(drop, band_down_m_) : 0.0;
  }
  /// What a face shows of a void under the faces around its vertices (rimVoidM, foldVoidM):
  /// TraversabilityMap sets their evidence again when it changes.
  double vertexVoidM(const StoredFace& f) const { return std::max(rimVoidM(f), foldVoidM(f)); }

  /// Whether setEvidence reads the face's edge neighbours: a measured, not driven, gentle face
  /// rising more than max_step_m (whose rise they may confirm).
  bool evidenceReadsNeighbours(const StoredFace& f) const {
    return !f.steiner && f.driven_vertices != 3 && f.front_crossings > 0 && f.max_z - f.min_z > profile_.max_step_m &&
           f.normal_L.z() >= cos_max_slope_;
  }

  /// The height window a face's ground candidates must reach (computeLocal's filter), from its
  /// centroid and normal only.
  struct GroundWindow {
    double z_lo = 0, z_hi = 0;
    /// How far from its centroid the face's obstacle test is judged (the farthest of the points of
    /// obstaclePoints and centreLinePoint): 0 for most faces.
    double spread_m = 0;
    /// Horizontal reach of the face's obstacle test from its centroid for obstacles that may extend
    /// the most (max_obstacle_extension_m): the footprint's reach grown by that, plus spread_m.
    double obstacle_reach_m = 0;
  };
  /// Horizontal reach of the obstacle test of a face with window `w` for obstacles that may extend
  /// `extension_m` (those of a face whose obstacleExtensionM is that): an obstacle part farther
  /// from the face's centroid meets no footprint the face is judged with, grown by its extension.
  double obstacleReachM(const GroundWindow& w, double extension_m) const {
    return footprintReachM(extension_m) + w.spread_m;
  }
  /// How far a measured obstacle part of a face whose longest horizontal edge is `span_m` may
  /// extend beyond it (EvidenceModel::obstacle_extension times the span, at most
  /// max_obstacle_extension_m); possible obstacles do not extend.
  double obstacleExtensionM(double span_m) const {
    return std::min(profile_.evidence.obstacle_extension * span_m, profile_.evidence.max_obstacle_extension_m);
  }
  /// obstacleReachM for the extension of a face whose longest horizontal edge is `span_m`, with
  /// the slack of the reach tests (far more than rounding): the window's own reach when the face
  /// may extend the most, as most faces of a camera-SLAM mesh may.
  double ownObstacleReachM(const GroundWindow& w, double span_m) const {
    const double e = obstacleExtensionM(span_m);
    const double reach = e >= profile_.evidence.max_obstacle_extension_m ? w.obstacle_reach_m : obstacleReachM(w, e);
    return reach * (1 + 1e-9) + 1e-6;
  }
  GroundWindow groundWindow(const StoredFace& face) const;
  /// Whether the unconfirmed point p (L) lies inside the body of face f: within
  /// unconfirmedReachM() of the face's horizontal projection, and between max_step_m and
  /// min_clearance_m above its reference plane (then it makes the face uncertain).
  bool unconfirmedInBody(const StoredFace& f, const Eigen::Vector3d& p) const;
  /// Whether a face t (its bounds and whether heightAt can sample it) can take part in the local
  /// layers of a face with centroid `c` and ground window `w`, as a ground candidate, an obstacle
  /// in its footprint or its ceiling, wherever t lies horizontally (the caller tests the reach). When false, adding or
  /// removing t changes no local layer of that face: computeLocal skips t in both searches.
  /// `distance_m`: the horizontal distance from c to t's projection.
  bool mayAffect(const Eigen::Vector3d& c, const GroundWindow& w, const FaceBounds& t, bool t_sampleable,
                 double t_span_m, double distance_m) const {
    // The three filters of computeLocal, on t's height range: obstacles (any measured face that
    // is not ground, sampleable or not, within the window and within the reach of its own
    // extension; t_span_m: its longest horizontal edge), ground and ceiling (both skip faces
    // heightAt cannot sample).
    if (mayObstruct(t) && !(t.max_z < w.z_lo || t.min_z > w.z_hi) &&
        distance_m <= ownObstacleReachM(w, t_span_m)) {
      return true;
    }
    if (!t_sampleable || distance_m > radius_m_ * (1 + 1e-9) + 1e-6) return false;
    if (!(t.normal_z <= kMinGroundNormalZ) && !(t.max_z < w.z_lo || t.min_z > w.z_hi)) return true;
    return !(c.x() < t.box_min.x() - kSliceToleranceM || c.x() > t.box_max.x() + kSliceToleranceM ||
             c.y() < t.box_min.y() - kSliceToleranceM || c.y() > t.box_max.y() + kSliceToleranceM ||
             t.max_z < c.z() + kMinClearanceGapM || t.min_z - c.z() > clearance_search_m_);
  }

  /// Whether driven ground t (sampleable, all vertices driven) can decide, for a driven face with
  /// ground window `w`, which obstacles in its footprint the drive contradicts (overDrivenGround):
  /// within its obstacle reach and its height window. `distance_m` as for mayAffect.
  bool readsDrivenGround(const StoredFace& face, const GroundWindow& w, const FaceBounds& t, double distance_m) const {
    // (addUnsweptParts reads the driven ground at most a box of half-side obstacle_reach_m away.)
    return face.layers.evidence == Evidence::kDriven && !(t.max_z < w.z_lo || t.min_z > w.z_hi) &&
           distance_m <= std::sqrt(2.0) * w.obstacle_reach_m * (1 + 1e-9) + 1e-6;
  }

  /// Whether face t (whether heightAt can sample it; `distance_m` as for mayAffect) can decide for
  /// a driven face whether a footprint sample lies in carved space (markUnseenColumns): at any
  /// height.
  bool readsColumns(const StoredFace& face, bool t_sampleable, double distance_m) const {
    return face.layers.evidence == Evidence::kDriven && t_sampleable && distance_m <= radius_m_ * (1 + 1e-9) + 1e-6;
  }

  /// Whether a face can be an obstacle inside a footprint (computeLocal's filter before its height
  /// window): not ground (steeper than max_slope, vertical or facing down). Measured faces are
  /// obstacles; interpolated ones (closing geometry, unobserved spans) only possible obstacles.
  bool mayObstruct(const FaceBounds& t) const { return t.normal_z < cos_max_slope_; }

  /// Faces whose normal has a smaller upward component are not ground (walls, ceilings).
  static constexpr double kMinGroundNormalZ = 1e-6;
  /// A face whose normal's up component is below this (more than 30 degrees below horizontal)
  /// faces down (foldVoidM).
  static constexpr double kMaxFoldNormalZ = -0.5;
  /// A face above the centroid closer than this is the face's own neighbourhood, not a ceiling.
  static constexpr double kMinClearanceGapM = 1e-4;
  /// Slices of projected triangles are widened by this much: far more than rounding, far less than
  /// the footprint sample spacing; so are face boxes in the clearance search.
  static constexpr double kSliceToleranceM = 1e-6;

  /// Whether known face layers make a face lethal: too steep (see docs for the step-riser rule)
  /// on measured evidence, too low a clearance, or the footprint fits at no heading.
  bool lethal(const StoredFace& face) const { return lethalReasons(face) != 0; }
  /// The reason:: bits of the lethal rules that hold for a known face (0: not lethal).
  std::uint16_t lethalReasons(const StoredFace& face) const;
  /// The reason:: bits of the uncertain rules that hold for a known face that is not lethal (0:
  /// not uncertain): the evidence cannot decide (an interpolated face too steep, a possible step,
  /// a slope that may exceed max_slope, a footprint that fits only as reconstructed, an unknown
  /// ceiling lower than the robot).
  std::uint16_t uncertainReasons(const StoredFace& face) const;
  /// Whether a face no steeper than max_slope could be steeper in the worst case: its slope with
  /// the points at either end off by their noise (evidence.point_noise_m) in opposite directions,
  /// over the extent along the slope that measured points confirm (slopeSupport), but at least
  /// the footprint's short side. Never for driven faces.
  bool slopeMayExceed(const StoredFace& face) const;
  /// Sets face_class and cost from the local layers and `lethal_distance_m`.
  void classify(StoredFace& face) const;

 private:
  /// A face's reference plane z = c.z + ref_a x + ref_b y and its ground window.
  struct Reference {
    float slope_deg = 0;
    bool steep = false;  ///< steeper than max_slope (or not facing up): horizontal reference
    double ref_a = 0, ref_b = 0;
    GroundWindow window;
  };
  Reference reference(const StoredFace& face) const;
  /// The same without the window: the slope and the reference plane only.
  Reference referencePlane(const StoredFace& face) const;
  /// The points (relative to the centroid, horizontal) where the obstacle test judges a face: a
  /// ground face whose horizontal projection is larger than the footprint at the centroids of its
  /// 1-to-9 split (each moved towards the centroid to within reachM() of it), any other face at
  /// its centroid only. Returns how many (1 or kObstaclePoints).
  int obstaclePoints(const StoredFace& face, bool steep, std::array<Eigen::Vector2d, 9>& points) const;
  static constexpr int kObstaclePoints = 9;
  /// For a face with a drive axis that reaches the drive's centre line (within
  /// kCentreLineToleranceM): the point of the face on that line nearest its centroid, relative to
  /// the centroid (horizontal); else zero. The drive put the robot there, at its heading of travel.
  Eigen::Vector2d centreLinePoint(const StoredFace& face) const;
  static constexpr double kCentreLineToleranceM = 0.02;

  /// The footprint layers at one heading.
  struct HeadingResult {
    double step_m = 0, roughness_m = 0, contact = 0;
    bool fits = false;    ///< step, roughness and contact within the robot's limits
    /// ... also in the worst case: every sample's height off by its face's uncertainty bound,
    /// unknown samples unsupported.
    bool fits_worst = false;
    double badness = 0;   ///< largest layer / limit ratio (smaller is better)
  };

  /// Most corners of an obstacle's shadow or its grown shape.
  static constexpr int kMaxObstacleCorners = 12;
  /// The horizontal shadow, relative to the centroid, of the part of a face inside the robot's
  /// body (between max_step_m and min_clearance_m above the reference plane), and the height of
  /// its top above the plane.
  struct Obstacle {
    /// Convex polygon: a triangle clipped by two planes, and over driven ground by the two sides
    /// of the swept strip.
    std::array<Eigen::Vector2d, kMaxObstacleCorners> p;
    int n = 0;
    double top_m = 0;
    /// From interpolated geometry: a possible obstacle (never lethal, never free).
    bool possible = false;
    /// How far a measured obstacle may extend beyond its face (EvidenceModel::obstacle_extension).
    double extension_m = 0;
    /// Where a measured steep face may extend (setExtension): along the face and behind it, and
    /// towards its front (the horizontal unit normal; zero: none, grown every way by
    /// extension_m) only ahead_m.
    Eigen::Vector2d front = Eigen::Vector2d::Zero();
    double ahead_m = 0;
    /// The part grown so (growAlongFace, when first asked; -1: not yet, 0: grown every way).
    mutable std::array<Eigen::Vector2d, kMaxObstacleCorners> grown;
    mutable int grown_n = -1;
    /// An unconfirmed SLAM point (collectUnconfirmed), grown by its extension.
    bool unconfirmed = false;
    /// A part beyond a side of the strip a drive swept (addUnsweptParts): it lies where
    /// side_normal . p >= side_offset (p relative to the centroid), and neither it nor its
    /// extension reaches a footprint that stays on the strip's side of that line (the drive shows
    /// nothing stood there).
    bool beyond_strip = false;
    Eigen::Vector2d side_normal = Eigen::Vector2d::Zero();
    double side_offset = 0;
  };
  /// Clips face t (its sampling geometry) to the body of the face with centroid c and reference
  /// plane slopes (ref_a, ref_b), up to `top_m` over that plane (at most min_clearance_m); false
  /// if no part of it lies there.
  bool clipToBody(const SampleGeometry& t, const Eigen::Vector3d& c, double ref_a, double ref_b, double top_m,
                  Obstacle& out) const;
  /// Over driven ground: the parts of face `t` inside the body that its measured vertices above
  /// the ground (higher than max_step_m over the reference plane) support, as measured obstacles:
  /// the corner triangles within evidence.obstacle_support_m of each such vertex along its edges.
  /// The rest of a long span is interpolated across the volume the robot's body swept: the drive
  /// contradicts it.
  /// Parts beyond the strip face f's drive swept are split off as for addUnsweptParts (with
  /// their extension); the part inside counts whole where the vertex stands inside the strip, and
  /// not at all from a vertex beyond it.
  void collectSupportedParts(const StoredFace& f, const SampleGeometry& t, const Eigen::Vector3d& c, double ref_a,
                             double ref_b) const;
  /// Per heading, the top of the highest measured obstacle (obstacles_) the footprint meets, 0 if
  /// none, for face f judged first at judged_at_ (its centroid, or for a driven face where the
  /// drive stood on it: centreLinePoint), then at its obstacle points (see obstaclePoints; rule in
  /// the .cpp); and in possible_, per heading, the reason:: bit of the first possible obstacle the
  /// footprint at judged_at_ meets (an interpolated one, the possible extension of a measured one,
  /// an unconfirmed point; 0: none).
  /// The reason:: bit of a possible obstacle (kUnconfirmedPoint, kPossibleObstacle or
  /// kObstacleExtension).
  static std::uint16_t causeOf(const Obstacle& o);
  /// Every reason:: bit of the possible obstacles the footprint at judged_at_ meets at `heading`
  /// (after obstacleTops; only asked for the faces that fit nowhere in the worst case).
  std::uint16_t possibleCauses(std::size_t heading) const;
  const std::vector<double>& obstacleTops(const StoredFace& f, bool steep,
                                          std::array<Eigen::Vector2d, kObstaclePoints>& points) const;
  /// Whether the footprint centred at `at` (relative to the centroid) at heading k, grown by
  /// `margin_m` on every side (a rectangle: its half-extents), meets the obstacle.
  bool meets(const Obstacle& o, std::size_t heading, const Eigen::Vector2d& at, double margin_m = 0) const;
  /// The same for `shape` (count points) in place of o's own polygon (o gives the strip's side).
  bool meetsShape(const Obstacle& o, const Eigen::Vector2d* shape, int count, std::size_t heading,
                  const Eigen::Vector2d& at, double margin_m) const;
  /// Whether the footprint centred at `at` at heading k, grown by `margin_m`, meets `shape`
  /// (count points), wherever the strip's sides lie.
  bool footprintMeets(const Eigen::Vector2d* shape, int count, std::size_t heading, const Eigen::Vector2d& at,
                      double margin_m) const;

  /// Whether every corner p[0..n) (relative to the centroid c) lies over driven ground within the
  /// height window [z_lo, z_hi].
  bool overDrivenGround(const SurfaceStore& store, const Eigen::Vector2d* p, int n, const Eigen::Vector3d& c,
                        double z_lo, double z_hi) const;
  /// Appends the rectangle turned by theta (radians from +x) to the headings.
  void addHeading(double theta) const;
  /// The profile's headings, and for a rectangle on driven ground with a drive axis, that one.
  void setDriveHeading(const StoredFace& f) const;
  /// Over driven face f: adds obstacle part o (relative to f's centroid) of a face slanted through
  /// the body's volume, less what the drive contradicts: the part inside the strip the body swept
  /// (sweptHalfWidthM() about f.drive_centre along f.drive_axis) that lies over driven ground.
  /// Without a drive axis the strip is unknown and the drive contradicts all of it.
  void addUnsweptParts(const SurfaceStore& store, const StoredFace& f, const Obstacle& o, double z_lo,
                       double z_hi, double reach_m) const;
  /// Over driven face f with a drive axis: adds to obstacles_ the parts of o beyond either side of
  /// the strip the drive swept (beyond_strip), sets `inside` to the part between the sides (n 0:
  /// none) and returns true. Without a drive axis: adds nothing and returns false.
  bool pushBeyondStrip(const StoredFace& f, const Obstacle& o, Obstacle& inside) const;
  /// For a part beyond a side of the swept strip (shadow.beyond_strip): whether the footprint's
  /// part beyond that side (a disc's: its bounding box there), centred at `at` and turned to
  /// `heading`, comes within margin_m of `shape` (count points: the part, or its grown shape).
  bool beyondSideWithin(const Obstacle& shadow, const Eigen::Vector2d* shape, int count, std::size_t heading,
                        const Eigen::Vector2d& at, double margin_m) const;
  /// Half the width of the strip the body sweeps: a rectangle's half width, a disc's radius.
  double sweptHalfWidthM() const {
    return profile_.footprint == FootprintShape::kDisc ? profile_.footprint_radius_m : 0.5 * profile_.footprint_width_m;
  }
  /// Collects, for face s, its ground candidates (candidates_) and the parts of non-ground faces
  /// inside its body (obstacles_), measured or possible, with their possible extension.
  void collectNearby(const SurfaceStore& store, Slot s, const Reference& reference_plane, bool driven) const;
  /// Adds to obstacles_ the unconfirmed points inside the body of face f (reference plane slopes
  /// ref_a, ref_b), as possible obstacles with their extension, each relative to the point of the
  /// face closest to it.
  void collectUnconfirmed(const StoredFace& f, double ref_a, double ref_b) const;
  /// unconfirmedInBody with the reference plane given; `offset`: p less the closest point.
  bool unconfirmedInBody(const StoredFace& f, double ref_a, double ref_b, const Eigen::Vector3d& p,
                         Eigen::Vector2d& offset) const;
  /// Sets the clearance of face s (clearance_m, clearance_unknown_low): the first face above its
  /// centroid; over driven ground, faces the drive contradicts do not count.
  void computeClearance(SurfaceStore& store, Slot s, bool driven) const;
  /// Finds, for every footprint sample of the face with centroid c, the ground closest to the
  /// sample's reference height (z_ and level_ scratch; NaN where none).
  /// With `driven_only` (a driven face: the robot stood there, its footprint on driven ground),
  /// only driven faces are ground; elsewhere the samples are unknown, not missing.
  void sampleGround(const SurfaceStore& store, const Eigen::Vector3d& c, bool driven_only) const;
  /// Marks the samples with no ground whose reference point lies in space nobody carved: no face
  /// above it in its column, or the first one faces up (kNoDataGround).
  void markUnseenColumns(const SurfaceStore& store, const Eigen::Vector3d& c) const;
  /// Fills terms_ from the sampled ground (z_, ref_) of the face with centroid c.
  void prepareSamples(const Eigen::Vector3d& c, bool steep) const;
  /// Judges the footprint made of `samples` (indices in offsets_) from the sampled ground (terms_);
  /// the face's reference plane is z = c.z + ref_a x + ref_b y; `steep`: the face is steeper than
  /// max_slope.
  /// `own_relief_m`: the relief the face itself may hide (its centroid is a sample too). With
  /// `driven`, the worst case counts support over the known samples as the nominal contact does
  /// (the robot stood there).
  HeadingResult judgeHeading(const std::vector<int>& samples, double ref_a, double ref_b, bool steep,
                             double own_relief_m, bool driven) const;
  /// Whether obstacle face t lies within the reach of its own extension (obstacleReachM) of the
  /// face with centroid c and window w, by its box: farther, no part of it can count there.
  bool withinOwnReach(const SampleGeometry& t, const Eigen::Vector3d& c, const GroundWindow& w) const {
    const double reach = ownObstacleReachM(w, t.span_m);
    const Eigen::Vector2d gap = (t.box_min - c.head<2>()).cwiseMax(c.head<2>() - t.box_max).cwiseMax(0.0);
    return gap.squaredNorm() <= reach * reach;
  }
  /// How far the measured obstacle face t may extend beyond what was measured of it.
  double obstacleExtensionM(const SampleGeometry& t) const { return obstacleExtensionM(t.span_m); }
  /// Sets the extension of o, a measured obstacle part of face t relative to centroid c:
  /// obstacleExtensionM(t), and for a face steeper than 30 degrees (kMinFrontNormalXy), or than 10
  /// degrees and descending below the body towards its front (kMinSlantFrontNormalXy), its front
  /// and how far ahead of the part the face reaches (Obstacle::front, ahead_m).
  void setExtension(Obstacle& o, const SampleGeometry& t, const Eigen::Vector3d& c) const;
  /// Sets o.grown: o grown along its face and behind it, and ahead_m in front.
  static void growAlongFace(const Obstacle& o);
  /// Whether the footprint centred at `at` at heading k meets where o may extend (o itself, grown
  /// by its extension).
  bool meetsExtension(const Obstacle& o, std::size_t heading, const Eigen::Vector2d& at) const;
  /// What supports face s's slope: whether it rises no more than max_step_m between its vertices
  /// or its plane is confirmed beyond it along its slope (a measured vertex of an edge neighbour,
  /// farther up or down the slope than the face's own vertices, within the point noise of the
  /// plane, and far enough beyond to tell the plane from level ground going on from the face's
  /// end), and the extent along the slope that its own vertices and those confirming ones span
  /// (infinite for walls and level faces). Reads only s and its edge neighbours (which
  /// TraversabilityMap re-judges with it).
  struct SlopeSupport {
    bool rise_confirmed = true;
    double extent_m = std::numeric_limits<double>::infinity();
  };
  SlopeSupport slopeSupport(const SurfaceStore& store, Slot s) const;

  /// Per footprint offset (x, y): the products its row (x, y, 1) adds to a plane fit's normal
  /// matrix (x x, x y, x, y y, y; the 1 is added as 1).
  struct OffsetTerms {
    double xx, xy, x, yy, y;
  };
  /// Per sample of the current face: dz = ground - centroid height, x dz, y dz and flags.
  struct SampleTerms {
    double dz = 0, x_dz = 0, y_dz = 0;
    double relief_m = 0;  ///< the relief the face the sample found may hide
    char flags = 0;
  };
  static constexpr char kFound = 1;      ///< the sample found ground
  static constexpr char kInLevel = 2;    ///< ... within the face's level band (not steep faces)
  static constexpr char kSupported = 4;  ///< ... within max_step + contact_tolerance of the plane
  static constexpr char kUnknown = 8;    ///< no measured ground, only Steiner faces, in its band
  static constexpr char kSupportedWorst = 16;  ///< ... supported even off by its face's relief
  static constexpr char kNoData = 32;  ///< unknown: in space nobody carved (driven faces only)
  /// Contact is the supported share of the known samples, but of at least this share of all
  /// samples: a footprint over more unknown than this counts the excess as unsupported.
  static constexpr double kMinKnownSampleFraction = 0.5;

  RobotProfile profile_;
  double radius_m_;
  int k_;  ///< samples per circumradius along each grid axis
  double spacing_m_ = 0;
  std::vector<Eigen::Vector2d> offsets_;
  /// Index in offsets_ of grid node (i, j), i and j in [-K, K], at (i + K) * (2K + 1) + j + K; -1
  /// outside the disc.
  std::vector<int> offset_index_;
  /// Per heading, the indices of offsets_ inside the footprint: the profile's headings
  /// (fixed_headings_ of them), then for a driven face with a drive axis that one (setDriveHeading).
  mutable std::vector<std::vector<int>> heading_samples_;
  std::size_t fixed_headings_ = 1;
  std::vector<OffsetTerms> offset_terms_;
  /// Per heading, the rectangle's axes along and across it (unused for a disc).
  mutable std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> heading_axes_;
  double band_down_m_;
  double clearance_search_m_;
  double cos_max_slope_;
  double short_side_m_;  ///< the footprint's shorter extent (a disc's diameter), metres
  double footprint_area_m2_;
  /// Scratch (computeLocal is not thread-safe): ground candidates; per sample the reference
  /// height, the best ground height (NaN: none) and whether that ground is level.
  mutable std::vector<Slot> candidates_;
  mutable std::vector<double> ref_;
  mutable std::vector<double> z_;
  mutable std::vector<double> z_relief_;  ///< the relief of the face each sample found
  mutable std::vector<char> level_;
  mutable std::vector<SampleTerms> terms_;
  mutable std::vector<Obstacle> obstacles_;
  mutable std::vector<double> tops_;
  mutable std::vector<std::uint16_t> possible_;
  /// Where the obstacle test judges the face being computed, relative to its centroid: zero, or
  /// for a driven face centreLinePoint (where the drive stood on it).
  mutable Eigen::Vector2d judged_at_ = Eigen::Vector2d::Zero();
  /// The headings of the face being computed that fit as reconstructed but meet a possible obstacle.
  mutable std::vector<std::size_t> fitting_possible_;
  mutable std::vector<Slot> neighbours_;
  const UnconfirmedPoints* unconfirmed_ = nullptr;
  /// How high interpolated geometry counts over driven ground (setDriveSensorHeight).
  double interpolated_top_m_ = 0;
};

}  // namespace terramesh::traversability::internal
