// What supports each face (its evidence and height uncertainty) and the class that follows from
// the layers and that evidence: lethal, uncertain or free, with the combined cost. Internal.
#include <algorithm>
#include <cmath>
#include <limits>

#include "face_projection.h"
#include "layer_computer.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability::internal {
namespace {

/// Steep faces up to this angle (vertical risers, slightly overhanging ones) may be step risers.
constexpr double kMaxRiserSlopeDeg = 95.0;
/// A face lies over a fold when their projections overlap by more than this (far more than
/// rounding; faces sharing a vertex or an edge touch).
constexpr double kFoldOverlapM = 1e-6;

double clamp01(double v) { return std::min(1.0, std::max(0.0, v)); }

}  // namespace

bool LayerComputer::onDrivenEdge(const StoredFace& f) const {
  if (f.driven_vertices != 2 || !(f.normal_L.z() >= cos_max_slope_) || f.max_z - f.min_z > profile_.max_step_m) {
    return false;
  }
  return f.drive_axis.squaredNorm() > 0 && std::abs(f.driveOffsetM()) <= sweptHalfWidthM();
}

bool LayerComputer::setEvidence(SurfaceStore& store, Slot s) const {
  StoredFace& f = store.face(s);
  const SampleGeometry& g = store.geometry(s);
  const EvidenceModel& m = profile_.evidence;
  Evidence evidence = Evidence::kInterpolated;
  double bound = std::numeric_limits<double>::infinity();
  double relief = bound;
  if (f.steiner) {
    // Closing geometry: nobody measured it; its height is unknown.
  } else if (f.driven_vertices == 3 || onDrivenEdge(f)) {
    // The robot stood there: the mounting's uncertainty, an offset shared by the whole patch.
    evidence = Evidence::kDriven;
    bound = m.driven_uncertainty_m;
    relief = 0;
  } else {
    // SLAM points: their noise, plus the relief the span between them can hide; less where rays
    // crossed the free space in front of the face (nothing stood above it on their way). A steep
    // face on a driven sample, or on the underside the drive put under one (a deck's slab), rising
    // more than a step is the mesh bridging the road the robot drove to something higher (whose
    // own faces show it): the drive contradicts the span, so it is no measured obstacle. (A lower
    // one may be a curb's riser, which the step judges.)
    const bool observed = f.front_crossings > 0;
    const bool on_drive = f.driven_vertices > 0 || f.underside_vertices > 0;
    const bool bridge = on_drive && !(f.normal_L.z() >= cos_max_slope_) &&
                        f.max_z - f.min_z > profile_.max_step_m;
    // Rays crossed the cell behind: the space the face closes off was seen free. The face is then
    // a membrane the 2-manifold keeps, not a measured surface: a level one is a lid (over a pit
    // whose rim and floor are both on the surface), and the ground beneath may be as deep as that
    // cell reaches; a steep one is a guessed wall, never a measured one.
    const bool seen_through = seenBehind(f);
    evidence = observed && !bridge && !seen_through ? Evidence::kMeasured : Evidence::kInterpolated;
    relief = g.span_m * (observed ? m.relief_per_m_observed : m.relief_per_m_unobserved);
    relief = std::max(relief, lidDepthM(f));
    // The void under a lid spanning a rim ends somewhere between the rim points and the ground
    // points beyond them: it may reach under every face around the lid's vertices as deep. The
    // free space under a fold hanging from one of the face's vertices reaches under the face where
    // the face lies over it (a crust over that space).
    store.forEachVertexNeighbour(s, [&](Slot t) {
      const StoredFace& around = store.face(t);
      relief = std::max(relief, rimVoidM(around));
      const double fold = foldVoidM(around);
      if (fold > relief && around.max_z <= f.max_z + m.point_noise_m &&
          projectionsOverlap(projectionOf(f), projectionOf(around), kFoldOverlapM)) {
        relief = fold;
      }
    });
    // A possible step (uncertain): its step may stand anywhere between its vertices.
    const double rise = f.max_z - f.min_z;
    if (rise > profile_.max_step_m && f.normal_L.z() >= cos_max_slope_ &&
        (!observed || !slopeSupport(store, s).rise_confirmed)) {
      relief = std::max(relief, rise);
    }
    bound = m.point_noise_m + relief;
  }
  const auto bound_f = static_cast<float>(bound);
  const bool changed = f.layers.evidence != evidence || f.layers.height_uncertainty_m != bound_f ||
                       g.relief_m != relief;
  f.layers.evidence = evidence;
  f.layers.height_uncertainty_m = bound_f;
  store.setSampleEvidence(s, evidence == Evidence::kInterpolated, evidence == Evidence::kDriven, relief);
  return changed;
}

LayerComputer::SlopeSupport LayerComputer::slopeSupport(const SurfaceStore& store, Slot s) const {
  const StoredFace& f = store.face(s);
  SlopeSupport out;
  const Eigen::Vector3d& n = f.normal_L;
  if (!(n.z() > LayerComputer::kMinGroundNormalZ)) return out;  // a wall: judged as one
  // The plane z = c.z + a x + b y and its direction of ascent.
  const Eigen::Vector2d gradient(-n.x() / n.z(), -n.y() / n.z());
  if (!(gradient.norm() > 0)) return out;  // level: no slope to doubt
  // A face within a step whose slope stays under the limit even over the shortest baseline
  // (slopeMayExceed) needs no neighbour: no extent changes its answers (1e-6: the float slope).
  const double shortest_worst = gradient.norm() + 2.0 * profile_.evidence.point_noise_m / short_side_m_;
  if (!(f.max_z - f.min_z > profile_.max_step_m) &&
      shortest_worst < std::tan(profile_.max_slope_deg * M_PI / 180.0) - 1e-6) {
    return out;
  }
  const Eigen::Vector2d up_slope = gradient.normalized();
  const Eigen::Vector3d& c = f.centroid_L;
  double lo = 0, hi = 0;
  for (const Eigen::Vector3d& p : f.p_L) {
    const double d = up_slope.dot(p.head<2>() - c.head<2>());
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  const double tolerance = 2.0 * profile_.evidence.point_noise_m + 0.01;
  // A point beyond the face confirms its plane only where the plane and level ground continuing
  // from the face's end differ by more than the tolerance: a point just past the foot of a face
  // from the road up to something beside it lies on both.
  const double informative_m = tolerance / gradient.norm();
  const double face_lo = lo, face_hi = hi;
  bool beyond = false;
  store.neighbours(s, neighbours_);
  for (Slot t : neighbours_) {
    const StoredFace& g = store.face(t);
    for (int i = 0; i < 3; ++i) {
      if (g.vertices[i].steiner || std::find(f.vertices.begin(), f.vertices.end(), g.vertices[i]) != f.vertices.end()) {
        continue;
      }
      const Eigen::Vector3d& p = g.p_L[i];
      const Eigen::Vector2d offset = p.head<2>() - c.head<2>();
      const double along = up_slope.dot(offset);
      const double extent = 1e-6 * (1.0 + hi - lo);
      if (along < hi + extent && along > lo - extent) continue;  // beside the face (or the part confirmed)
      if (std::abs(p.z() - (c.z() + gradient.dot(offset))) > tolerance) continue;
      beyond = beyond || along > face_hi + informative_m || along < face_lo - informative_m;
      lo = std::min(lo, along);
      hi = std::max(hi, along);
    }
  }
  out.rise_confirmed = !(f.max_z - f.min_z > profile_.max_step_m) || beyond;
  out.extent_m = hi - lo;
  return out;
}

std::uint16_t LayerComputer::lethalReasons(const StoredFace& face) const {
  const FaceLayers& l = face.layers;
  // A steep face no taller than max_step_m between level ground (at least half of its footprint
  // samples on faces no steeper than max_slope: not a steep ramp) is the riser of a step: the
  // step layer judges it, not the slope.
  const bool riser = l.slope_deg <= kMaxRiserSlopeDeg && face.max_z - face.min_z <= profile_.max_step_m &&
                     face.level_fraction >= 0.5f;
  const bool steep = !(l.slope_deg <= profile_.max_slope_deg);
  // Only measured (or driven) geometry is lethal by itself: an interpolated wall is a guess, and
  // whether a robot fits on a wall says nothing (uncertain judges it).
  if (steep && l.evidence == Evidence::kInterpolated) return 0;
  std::uint16_t reasons = 0;
  if (steep && !riser) reasons |= reason::kTooSteep;
  if (!face.footprint_fits) reasons |= reason::kNoHeadingFits;
  if (l.clearance_m < profile_.min_clearance_m) reasons |= reason::kLowClearance;
  return reasons;
}

bool LayerComputer::slopeMayExceed(const StoredFace& face) const {
  const FaceLayers& l = face.layers;
  if (l.evidence == Evidence::kDriven || !(l.slope_deg <= profile_.max_slope_deg)) return false;
  // Each point may be off by its noise: one end up and the other down tilts the plane by 2 noise
  // over the baseline, the extent along the slope on which measured points confirm the plane, but
  // at least the footprint's short side (the robot stands on a plane that spans its footprint).
  const double baseline_m = std::max(static_cast<double>(face.slope_extent_m), short_side_m_);
  const double gradient = std::tan(l.slope_deg * M_PI / 180.0) + 2.0 * profile_.evidence.point_noise_m / baseline_m;
  return gradient > std::tan(profile_.max_slope_deg * M_PI / 180.0);
}

std::uint16_t LayerComputer::uncertainReasons(const StoredFace& face) const {
  const FaceLayers& l = face.layers;
  const bool interpolated = l.evidence == Evidence::kInterpolated;
  const bool steep = !(l.slope_deg <= profile_.max_slope_deg);
  // A span that rises more than a step with nothing supporting its inside: a step may hide in
  // it, it is no ramp (unless driven, or the plane is confirmed beyond it along the slope).
  const bool possible_step = l.evidence != Evidence::kDriven && !steep &&
                             (interpolated ? face.max_z - face.min_z > profile_.max_step_m : !face.rise_confirmed);
  std::uint16_t reasons = 0;
  if (interpolated && steep) reasons |= reason::kGuessedWall;
  if (possible_step) reasons |= reason::kPossibleStep;
  if (slopeMayExceed(face)) reasons |= reason::kSlopeMayExceed;
  // Fits at no heading in the worst case; the causes where it fits as built (kWorstCaseRelief
  // when no heading fits as built either: the face is then lethal unless that is interpolation).
  if (!face.footprint_fits_worst) {
    reasons |= face.worst_case_reasons != 0 ? face.worst_case_reasons : reason::kWorstCaseRelief;
  }
  if (face.clearance_unknown_low) reasons |= reason::kUnknownLowClearance;
  // Every keyframe that saw its points lies behind its plane (the top of a slab seen from below):
  // the side it faces, where a robot would stand, was never observed. Not on driven ground.
  if (l.evidence != Evidence::kDriven && face.view_sides == mesher::view_side::kBehind) {
    reasons |= reason::kSeenFromBehind;
  }
  return reasons;
}

void LayerComputer::classify(StoredFace& face) const {
  FaceLayers& l = face.layers;
  const bool few_rays = l.rays < static_cast<std::uint32_t>(profile_.min_rays);
  if (face.steiner || few_rays) {
    l.face_class = FaceClass::kUnknown;
    l.cost = std::numeric_limits<float>::quiet_NaN();
    l.reasons = static_cast<std::uint16_t>((face.steiner ? reason::kClosingGeometry : 0) |
                                           (few_rays ? reason::kFewRays : 0));
    return;
  }
  l.reasons = lethalReasons(face);
  if (l.reasons != 0) {
    l.face_class = FaceClass::kLethal;
    l.cost = 1.0f;
    return;
  }
  const RobotProfile& p = profile_;
  const double inflation = profile_.inflationTerm(l.lethal_distance_m);
  l.reasons = uncertainReasons(face);
  if (l.reasons != 0) {
    l.face_class = FaceClass::kUncertain;
    l.cost = static_cast<float>(std::max(p.evidence.uncertain_cost, inflation));
    return;
  }
  const double slope = clamp01(l.slope_deg / p.max_slope_deg);
  const double step = p.max_step_m > 0 ? clamp01(l.step_m / p.max_step_m) : (l.step_m > 0 ? 1.0 : 0.0);
  const double rough = clamp01(l.roughness_m / p.max_roughness_m);
  // Step, roughness and this contact are the best heading's: the robot drives there turned so.
  const double fit_contact = face.heading_contact;
  const double contact =
      p.min_support < 1 ? clamp01((1.0 - fit_contact) / (1.0 - p.min_support)) : (fit_contact < 1 ? 1.0 : 0.0);
  const LayerWeights& w = p.weights;
  const double mean = (w.slope * slope + w.step * step + w.roughness * rough + w.contact * contact +
                       w.inflation * inflation) /
                      (w.slope + w.step + w.roughness + w.contact + w.inflation);
  // Nav2 combines layers by max: the inflation decay is never diluted by flat terrain.
  l.face_class = FaceClass::kFree;
  l.cost = static_cast<float>(std::max(mean, inflation));
}

}  // namespace terramesh::traversability::internal
