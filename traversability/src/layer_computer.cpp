#include "layer_computer.h"
#include "footprint_samples.h"
#include "traversability/layer_registry.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace terramesh::traversability::internal {
namespace {

constexpr double kMinGroundNormalZ = LayerComputer::kMinGroundNormalZ;
constexpr double kMinClearanceGapM = LayerComputer::kMinClearanceGapM;
constexpr double kSliceToleranceM = LayerComputer::kSliceToleranceM;
/// Non-ground faces less steep than this (normal z above cos 70 deg) are bridges, not walls, where
/// the robot's body swept the space (driven ground).
const double kMaxBridgeNormalZ = std::cos(70.0 * M_PI / 180.0);

constexpr double kRadToDeg = 180.0 / M_PI;
/// Footprint samples per circumradius along each axis of the sample grid (at least).
constexpr int kSamplesPerRadius = 5;
/// Sample spacings across a rectangle's width (at least): the outermost samples fall within a
/// quarter of the width of its sides (the car: 0.05 m inside).
constexpr int kSamplesPerWidth = 4;

/// A least-squares plane z = a x + b y + d through points added one by one: the six distinct sums
/// of its symmetric normal matrix and its right-hand side, the origin (0, 0, 0) counted.
struct PlaneSums {
  double m00 = 0, m01 = 0, m02 = 0, m11 = 0, m12 = 0, m22 = 1.0;
  double r0 = 0, r1 = 0, r2 = 0;
  int used = 1;
  /// A point (x, y, z) by its products: xx, xy, x, yy, y, x z, y z, z.
  void add(double xx, double xy, double x, double yy, double y, double x_z, double y_z, double z) {
    m00 += xx;
    m01 += xy;
    m02 += x;
    m11 += yy;
    m12 += y;
    m22 += 1.0;
    r0 += x_z;
    r1 += y_z;
    r2 += z;
    ++used;
  }
  /// (a, b, d), or nullopt if the points do not span a plane.
  std::optional<Eigen::Vector3d> solve() const {
    if (used < 3) return std::nullopt;
    Eigen::Matrix3d m;
    m << m00, m01, m02, m01, m11, m12, m02, m12, m22;
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(m);
    if (lu.rank() < 3) return std::nullopt;
    return Eigen::Vector3d(lu.solve(Eigen::Vector3d(r0, r1, r2)));
  }
};

}  // namespace

LayerComputer::LayerComputer(const RobotProfile& profile)
    : profile_(profile),
      radius_m_(profile.footprintCircumradiusM()),
      k_(kSamplesPerRadius),
      band_down_m_(std::max(profile.min_clearance_m, 2.0 * profile.max_step_m)),
      clearance_search_m_(std::max(3.0 * profile.min_clearance_m, 5.0)),
      cos_max_slope_(std::cos(profile.max_slope_deg * M_PI / 180.0)),
      short_side_m_(profile.footprint == FootprintShape::kDisc
                        ? 2.0 * profile.footprint_radius_m
                        : std::min(profile.footprint_length_m, profile.footprint_width_m)),
      footprint_area_m2_(profile.footprint == FootprintShape::kDisc
                             ? M_PI * profile.footprint_radius_m * profile.footprint_radius_m
                             : profile.footprint_length_m * profile.footprint_width_m) {
  if (profile.footprint == FootprintShape::kRectangle) {
    const double narrow = std::min(profile.footprint_length_m, profile.footprint_width_m);
    k_ = std::max(k_, ceilInt(kSamplesPerWidth * radius_m_ / narrow - 1e-9));
  }
  spacing_m_ = radius_m_ / k_;
  setDriveSensorHeight(std::nullopt);
  for (int i = -k_; i <= k_; ++i) {
    for (int j = -k_; j <= k_; ++j) {
      const bool inside = i * i + j * j <= k_ * k_;
      offset_index_.push_back(inside ? static_cast<int>(offsets_.size()) : -1);
      if (inside) offsets_.emplace_back(i * spacing_m_, j * spacing_m_);
    }
  }
  for (const Eigen::Vector2d& o : offsets_) {
    offset_terms_.push_back({o.x() * o.x(), o.x() * o.y(), o.x(), o.y() * o.y(), o.y()});
  }
  if (profile.footprint == FootprintShape::kDisc) {
    std::vector<int> all(offsets_.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    heading_samples_.push_back(all);
    return;
  }
  // Over half a turn: the rectangle turned by 180 degrees covers the same samples.
  for (int k = 0; k < profile.contact_headings; ++k) addHeading(M_PI * k / profile.contact_headings);
  fixed_headings_ = heading_samples_.size();
}

double LayerComputer::footprintReachM(double margin_m) const {
  if (profile_.footprint == FootprintShape::kDisc) return radius_m_ + margin_m;
  // By sqrt: std::hypot is far slower, and the obstacle test asks this per pair of faces.
  const double a = 0.5 * profile_.footprint_length_m + margin_m, b = 0.5 * profile_.footprint_width_m + margin_m;
  return std::sqrt(a * a + b * b);
}

void LayerComputer::addHeading(double theta) const {
  const double eps = 1e-9 * radius_m_;
  const double c = std::cos(theta), s = std::sin(theta);
  heading_axes_.emplace_back(Eigen::Vector2d(c, s), Eigen::Vector2d(-s, c));
  std::vector<int> inside;
  for (std::size_t i = 0; i < offsets_.size(); ++i) {
    const Eigen::Vector2d& o = offsets_[i];
    const double along = c * o.x() + s * o.y();
    const double across = -s * o.x() + c * o.y();
    if (std::abs(along) <= 0.5 * profile_.footprint_length_m + eps &&
        std::abs(across) <= 0.5 * profile_.footprint_width_m + eps) {
      inside.push_back(static_cast<int>(i));
    }
  }
  heading_samples_.push_back(std::move(inside));
}

void LayerComputer::setDriveSensorHeight(std::optional<double> height_m) {
  interpolated_top_m_ = height_m ? std::min(*height_m, profile_.min_clearance_m) : profile_.min_clearance_m;
}

void LayerComputer::setDriveHeading(const StoredFace& f) const {
  heading_samples_.resize(fixed_headings_);
  if (profile_.footprint != FootprintShape::kRectangle) return;
  heading_axes_.resize(fixed_headings_);
  if (f.layers.evidence != Evidence::kDriven || !(f.drive_axis.squaredNorm() > 0)) return;
  addHeading(std::atan2(f.drive_axis.y(), f.drive_axis.x()));
}

void LayerComputer::prepareSamples(const Eigen::Vector3d& c, bool steep) const {
  const double level_band = std::max(profile_.contact_tolerance_m, 0.5 * profile_.max_step_m);
  const double reach = profile_.max_step_m + profile_.contact_tolerance_m;
  terms_.resize(offsets_.size());
  for (std::size_t i = 0; i < offsets_.size(); ++i) {
    SampleTerms& t = terms_[i];
    t.flags = level_[i] == kUnknownGround ? kUnknown : level_[i] == kNoDataGround ? kUnknown | kNoData : 0;
    if (std::isnan(z_[i])) continue;
    t.dz = z_[i] - c.z();
    t.x_dz = offsets_[i].x() * t.dz;
    t.y_dz = offsets_[i].y() * t.dz;
    t.relief_m = z_relief_[i];
    const double off = std::abs(z_[i] - ref_[i]);
    const int in_level = !steep && off <= level_band ? kInLevel : 0;
    const int worst = off + t.relief_m <= reach ? kSupportedWorst : 0;
    t.flags = static_cast<char>(kFound | in_level | (off <= reach ? kSupported : 0) | worst);
  }
}

LayerComputer::HeadingResult LayerComputer::judgeHeading(const std::vector<int>& samples, double ref_a, double ref_b,
                                                        bool steep, double own_relief_m, bool driven) const {
  // Least-squares planes z - c.z = a x + b y + d over the centroid and the found samples: all of
  // them, and those of the face's level (near the face's plane: a fit over both levels of a step
  // would tilt towards the upper one and hide part of the jump). Both in one pass. The normal
  // matrices are symmetric: their six distinct sums are accumulated (sample by sample, in order,
  // the same additions as the full matrices'), from the per-sample terms of prepareSamples.
  PlaneSums all, level;  // the centroid itself, (0, 0, 0), counted in both
  for (int i : samples) {
    const SampleTerms& t = terms_[static_cast<std::size_t>(i)];
    if (!(t.flags & kFound)) continue;
    const OffsetTerms& o = offset_terms_[static_cast<std::size_t>(i)];
    all.add(o.xx, o.xy, o.x, o.yy, o.y, t.x_dz, t.y_dz, t.dz);
    if (t.flags & kInLevel) level.add(o.xx, o.xy, o.x, o.yy, o.y, t.x_dz, t.y_dz, t.dz);
  }
  HeadingResult out;
  const Eigen::Vector3d all_plane = all.solve().value_or(Eigen::Vector3d(ref_a, ref_b, 0.0));
  // The step from the level's plane (degenerate levels: the plane over all samples). Steep faces
  // (the risers of steps) measure the height range around them.
  const Eigen::Vector3d level_plane =
      steep ? Eigen::Vector3d::Zero() : level.solve().value_or(all_plane);
  // Residuals of the centroid and every found sample: RMS against the plane over all samples,
  // range against the level's plane; and the supported samples.
  double sum_sq = all_plane.z() * all_plane.z(), step_min = -level_plane.z(), step_max = -level_plane.z();
  // The same range with every height off by the relief its face may hide (the worst case).
  double worst_min = step_min - own_relief_m, worst_max = step_max + own_relief_m;
  int n = 1, supported = 0, unknown = 0, no_data = 0, supported_worst = 0;
  for (int i : samples) {
    const SampleTerms& t = terms_[static_cast<std::size_t>(i)];
    unknown += (t.flags & kUnknown) ? 1 : 0;
    no_data += (t.flags & kNoData) ? 1 : 0;
    if (!(t.flags & kFound)) continue;
    const Eigen::Vector2d& o = offsets_[static_cast<std::size_t>(i)];
    const double dz = t.dz;
    const double e_all = dz - (all_plane.x() * o.x() + all_plane.y() * o.y() + all_plane.z());
    const double e_level = dz - (level_plane.x() * o.x() + level_plane.y() * o.y() + level_plane.z());
    sum_sq += e_all * e_all;
    ++n;
    step_min = std::min(step_min, e_level);
    step_max = std::max(step_max, e_level);
    worst_min = std::min(worst_min, e_level - t.relief_m);
    worst_max = std::max(worst_max, e_level + t.relief_m);
    if (t.flags & kSupported) ++supported;
    if (t.flags & kSupportedWorst) ++supported_worst;
  }
  out.roughness_m = std::sqrt(sum_sq / n);
  out.step_m = step_max - step_min;
  // Support over the known samples (unknown ones neither support nor fail to), but over at least
  // kMinKnownSampleFraction of the footprint: a footprint mostly over unknown is not supported.
  // On driven ground the robot stood there: the drive supports the part nobody measured beside
  // it, so the footprint is what remains, but not the part beyond the map (no_data: where the
  // drive began, the footprint of a face behind the first pose reaches where nobody was).
  const double total = static_cast<double>(samples.size()) - (driven ? unknown - no_data : 0);
  const double known = std::max(total - (driven ? no_data : unknown), kMinKnownSampleFraction * total);
  out.contact = known > 0 ? std::min(1.0, static_cast<double>(supported) / known) : 0.0;
  const RobotProfile& p = profile_;
  out.fits = out.step_m <= p.max_step_m && out.roughness_m <= p.max_roughness_m && out.contact >= p.min_support;
  // The worst case: unknown samples count as unsupported, over the whole footprint.
  const double contact_worst = total > 0 ? std::min(1.0, static_cast<double>(supported_worst) / total) : 0.0;
  out.fits_worst = out.fits && worst_max - worst_min <= p.max_step_m && contact_worst >= p.min_support;
  const auto ratio = [](double value, double limit) {
    return limit > 0 ? value / limit : (value > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  };
  out.badness = std::max({ratio(out.step_m, p.max_step_m), ratio(out.roughness_m, p.max_roughness_m),
                          ratio(1.0 - out.contact, 1.0 - p.min_support)});
  return out;
}

LayerComputer::Reference LayerComputer::referencePlane(const StoredFace& f) const {
  const Eigen::Vector3d& n = f.normal_L;
  Reference r;
  r.slope_deg =
      n.squaredNorm() > 0 ? static_cast<float>(std::acos(std::clamp(n.z(), -1.0, 1.0)) * kRadToDeg) : 90.0f;
  r.steep = !(r.slope_deg <= profile_.max_slope_deg) || n.z() <= kMinGroundNormalZ;
  // Reference plane z = c.z + a x + b y (x, y relative to the centroid).
  r.ref_a = r.steep ? 0.0 : -n.x() / n.z();
  r.ref_b = r.steep ? 0.0 : -n.y() / n.z();
  return r;
}

LayerComputer::Reference LayerComputer::reference(const StoredFace& f) const {
  const Eigen::Vector3d& c = f.centroid_L;
  Reference r = referencePlane(f);
  // Only faces reaching the samples' height band can be ground: the reference plane stays within
  // |grad| R of the centroid over the footprint (widened far beyond rounding).
  // Faces judged at several points: their obstacles lie within reachM() of any of them.
  std::array<Eigen::Vector2d, kObstaclePoints> points;
  const int n_points = obstaclePoints(f, r.steep, points);
  double spread = 0;
  for (int i = 0; i < n_points; ++i) spread = std::max(spread, points[static_cast<std::size_t>(i)].norm());
  // A face the drive crossed is judged on its centre line once its evidence is driven, which may
  // change after this window is set: the window holds that point whatever the evidence.
  spread = std::max(spread, centreLinePoint(f).norm());
  // Measured obstacles may extend up to max_obstacle_extension_m beyond their faces.
  r.window.spread_m = spread;
  r.window.obstacle_reach_m = footprintReachM(profile_.evidence.max_obstacle_extension_m) + spread;
  const double reach = r.window.obstacle_reach_m;
  const double ref_spread = std::hypot(r.ref_a, r.ref_b) * reach + 1e-6 * (1.0 + reach);
  r.window.z_lo = c.z() - ref_spread - band_down_m_;
  r.window.z_hi = c.z() + ref_spread + profile_.min_clearance_m;
  return r;
}

LayerComputer::GroundWindow LayerComputer::groundWindow(const StoredFace& face) const {
  return reference(face).window;
}

void LayerComputer::collectNearby(const SurfaceStore& store, Slot s, const Reference& reference_plane,
                                  bool driven) const {
  const Eigen::Vector3d& c = store.face(s).centroid_L;
  const double ref_a = reference_plane.ref_a, ref_b = reference_plane.ref_b;
  // Ground candidates: upward-facing faces whose projection's box meets the footprint's box.
  const Eigen::Vector2d lo = c.head<2>() - Eigen::Vector2d(radius_m_, radius_m_);
  const Eigen::Vector2d hi = c.head<2>() + Eigen::Vector2d(radius_m_, radius_m_);
  const double obstacle_reach = reference_plane.window.obstacle_reach_m;
  const Eigen::Vector2d obstacle_lo = c.head<2>() - Eigen::Vector2d(obstacle_reach, obstacle_reach);
  const Eigen::Vector2d obstacle_hi = c.head<2>() + Eigen::Vector2d(obstacle_reach, obstacle_reach);
  std::vector<Slot>& candidates = candidates_;
  candidates.clear();
  const double z_lo = reference_plane.window.z_lo, z_hi = reference_plane.window.z_hi;
  // Obstacles: the parts inside the robot's body of measured faces that are not ground (the same
  // window; the box of all the points the face is judged at; see mayAffect). The face itself is
  // not in its own way.
  obstacles_.clear();
  store.forEachInBox(obstacle_lo, obstacle_hi, [&](Slot t) {
    const FaceBounds& g = store.bounds(t);
    if (!g.alive || g.max_z < z_lo || g.min_z > z_hi) return;
    if ((g.box_min.array() > obstacle_hi.array()).any() || (g.box_max.array() < obstacle_lo.array()).any()) return;
    if (t != s && mayObstruct(g) && withinOwnReach(store.geometry(t), c, reference_plane.window)) {
      Obstacle o;
      const SampleGeometry& tg = store.geometry(t);
      // Under driven ground the robot's body swept the volume above. A non-ground face anchored on
      // driven ground (a bridge the mesh drew from the road to something higher; that thing's own
      // faces show it) is contradicted by the drive. A face slanted through the volume is
      // contradicted where the body swept it: inside the strip along the drive's centre line,
      // over driven ground (addUnsweptParts); a footprint centred off that line reaches beyond
      // the strip, where nobody drove. So is interpolated geometry of any slope (a guessed wall, a
      // closing face): nothing measured stands inside the strip. Measured near-vertical faces
      // still count: an obstacle placed later (a parked car) stands on the road with vertical
      // sides, where its points support them (collectSupportedParts); beyond the strip, what they
      // support may extend as anywhere, but not into the strip. Elsewhere a face anchored on
      // driven ground is only a possible obstacle. Interpolated geometry beyond the strip counts
      // up to the drive's sensor only (setDriveSensorHeight): no ray looked higher.
      const bool anchored = driven && tg.touches_driven;
      const bool slanted = driven && !anchored && tg.normal_z > kMaxBridgeNormalZ;
      const bool unmeasured = driven && !anchored && tg.interpolated;
      if (driven && !anchored && !slanted && !tg.interpolated) {
        collectSupportedParts(store.face(s), tg, c, ref_a, ref_b);
      } else if (!anchored &&
                 clipToBody(tg, c, ref_a, ref_b, unmeasured ? interpolated_top_m_ : profile_.min_clearance_m, o)) {
        o.possible = tg.interpolated || tg.touches_driven;
        if (!o.possible) setExtension(o, tg, c);
        if (slanted || unmeasured) {
          addUnsweptParts(store, store.face(s), o, z_lo, z_hi, obstacle_reach);
        } else {
          obstacles_.push_back(o);
        }
      }
    }
    if (g.normal_z <= kMinGroundNormalZ) return;
    if ((g.box_min.array() > hi.array()).any() || (g.box_max.array() < lo.array()).any()) return;
    candidates.push_back(t);
  });
  // Over driven ground the robot's body swept the volume: an unconfirmed point there is
  // contradicted by the drive (a confirmed one, inserted later, wins: later obstacles).
  if (!driven) collectUnconfirmed(store.face(s), ref_a, ref_b);
}

void LayerComputer::computeClearance(SurfaceStore& store, Slot s, bool driven) const {
  StoredFace& f = store.face(s);
  FaceLayers& layers = f.layers;
  const Eigen::Vector3d& c = f.centroid_L;
  double above = std::numeric_limits<double>::infinity();
  bool above_steiner = false;
  store.forEachAt(c.x(), c.y(), [&](Slot t) {
    if (t == s) return;
    // Faces whose box (widened far beyond heightAt's rounding tolerance) misses the centroid
    // cannot be above it.
    const FaceBounds& b = store.bounds(t);
    if (!b.alive || c.x() < b.box_min.x() - kSliceToleranceM || c.x() > b.box_max.x() + kSliceToleranceM ||
        c.y() < b.box_min.y() - kSliceToleranceM || c.y() > b.box_max.y() + kSliceToleranceM ||
        b.max_z < c.z() + kMinClearanceGapM || b.min_z - c.z() > clearance_search_m_) {
      return;
    }
    const SampleGeometry& g = store.geometry(t);
    if (!g.sampleable) return;
    // Above driven ground the robot's body passed: a face anchored on the drive or a slanted
    // bridge there is contradicted (a ceiling, facing down, still counts).
    if (driven && (g.touches_driven || (g.normal_z > kMaxBridgeNormalZ && g.normal_z < cos_max_slope_))) return;
    const std::optional<double> h = g.heightAt(c.x(), c.y());
    if (!h || *h < c.z() + kMinClearanceGapM || *h - c.z() > clearance_search_m_) return;
    if (*h < above || (*h == above && g.steiner)) {
      above = *h;
      above_steiner = g.steiner;
    }
  });
  f.clearance_unknown_low = above_steiner && above - c.z() < profile_.min_clearance_m;
  if (std::isinf(above)) {
    layers.clearance_m = std::numeric_limits<float>::infinity();
  } else {
    layers.clearance_m = above_steiner ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(above - c.z());
  }
}

void LayerComputer::computeLocal(SurfaceStore& store, Slot s) const {
  StoredFace& f = store.face(s);
  FaceLayers& layers = f.layers;
  const Eigen::Vector3d& c = f.centroid_L;
  const Reference reference_plane = reference(f);
  layers.slope_deg = reference_plane.slope_deg;
  const bool steep = reference_plane.steep;
  const double ref_a = reference_plane.ref_a;
  const double ref_b = reference_plane.ref_b;

  const std::size_t count = offsets_.size();
  const bool driven = f.layers.evidence == Evidence::kDriven;
  setDriveHeading(f);
  collectNearby(store, s, reference_plane, driven);
  std::array<Eigen::Vector2d, kObstaclePoints> points;
  const std::vector<double>& tops = obstacleTops(f, reference_plane.steep, points);
  ref_.resize(count);
  for (std::size_t i = 0; i < count; ++i) ref_[i] = c.z() + ref_a * offsets_[i].x() + ref_b * offsets_[i].y();
  sampleGround(store, c, driven);
  int found_samples = 0, level_samples = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (level_[i] == kNoGround || level_[i] == kUnknownGround || level_[i] == kNoDataGround) continue;
    ++found_samples;
    level_samples += level_[i] == kLevelGround ? 1 : 0;
  }
  f.level_fraction = found_samples ? static_cast<float>(level_samples) / static_cast<float>(found_samples) : 0.0f;
  // Each heading's footprint is judged on its own samples; the face is reported at the best one.
  prepareSamples(c, steep);
  HeadingResult best;
  double worst_contact = 1.0, best_contact = 0.0;
  bool first = true;
  bool fits_worst = false;
  std::uint32_t heading_fits = 0;
  std::uint16_t worst_case_reasons = 0;
  fitting_possible_.clear();
  for (std::size_t k = 0; k < heading_samples_.size(); ++k) {
    HeadingResult h = judgeHeading(heading_samples_[k], ref_a, ref_b, steep, store.geometry(s).relief_m, driven);
    // An obstacle inside the footprint: the body collides, the heading does not fit; its top
    // above the plane counts as a step (the highest the robot would have to climb there).
    const double top = tops[k];
    // What fails the worst case where the robot fits as reconstructed.
    if (h.fits && top <= 0) {
      if (!h.fits_worst) worst_case_reasons |= reason::kWorstCaseRelief;
      if (possible_[k] != 0) fitting_possible_.push_back(k);
    }
    h.fits_worst = h.fits_worst && top <= 0 && possible_[k] == 0;
    fits_worst = fits_worst || h.fits_worst;
    if (h.fits_worst && k < fixed_headings_) heading_fits |= 1u << k;
    if (top > 0) {
      h.fits = false;
      h.step_m = std::max(h.step_m, top);
      h.badness = std::max(h.badness, profile_.max_step_m > 0 ? top / profile_.max_step_m
                                                               : std::numeric_limits<double>::infinity());
    }
    worst_contact = std::min(worst_contact, h.contact);
    best_contact = std::max(best_contact, h.contact);
    // The best heading: one that fits, then the smallest badness, then the first.
    if (first || (h.fits && !best.fits) || (h.fits == best.fits && h.badness < best.badness)) best = h;
    first = false;
  }
  f.footprint_fits = best.fits;
  f.footprint_fits_worst = fits_worst;
  if (!fits_worst) {
    for (std::size_t k : fitting_possible_) worst_case_reasons |= possibleCauses(k);
  }
  f.worst_case_reasons = fits_worst ? 0 : worst_case_reasons;
  const SlopeSupport support = slopeSupport(store, s);
  f.rise_confirmed = support.rise_confirmed;
  f.slope_extent_m = static_cast<float>(support.extent_m);
  f.heading_contact = static_cast<float>(best.contact);
  layers.step_m = static_cast<float>(best.step_m);
  layers.roughness_m = static_cast<float>(best.roughness_m);
  layers.contact = static_cast<float>(worst_contact);
  layers.contact_best = static_cast<float>(best_contact);
  layers.heading_fits = heading_fits;

  computeClearance(store, s, driven);
  layers.rays = f.rays;
  layers.steiner = f.steiner;
}

}  // namespace terramesh::traversability::internal
