// The robot's body against the obstacles in its footprint (LayerComputer's obstacle test): the
// parts of non-ground faces inside the body, whether a footprint meets them, and the points a
// large face is judged at. Internal.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>

#include "face_projection.h"
#include "layer_computer.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability::internal {
namespace {

/// Surface must reach this far above max_step_m (far more than rounding) to be inside the body.
constexpr double kBodyToleranceM = 1e-9;
/// A part must reach this far across a side of the swept strip to lie beyond it (far more than
/// rounding).
constexpr double kSweptSideToleranceM = 1e-6;
/// A face whose normal's horizontal part is at least this long (steeper than 30 degrees) has a
/// front: where it may extend is along it and behind it.
constexpr double kMinFrontNormalXy = 0.5;
/// A slanted face steeper than this (10 degrees: every obstacle face of a shipped profile is) has a
/// front too where it descends below the body towards it, as a ramp up to a rock's top does: the
/// rays that measured it crossed the space over it down to its foot. A tilted top wholly in the
/// body ends where its points end, and what holds it up may stand past that edge.
constexpr double kMinSlantFrontNormalXy = 0.17;
/// A slanted face reaches this far ahead of its part in the body where it descends below the body
/// (far more than rounding).
constexpr double kMinAheadM = 1e-6;

/// Sutherland-Hodgman: the part of convex polygon `in` (n points) where normal . p >= bound, into
/// `out` (room for n + 1 points); 0 if it only touches the line (a footprint touching the line
/// meets it).
int clipToHalfPlane(const Eigen::Vector2d* in, int n, const Eigen::Vector2d& normal, double bound,
                    Eigen::Vector2d* out) {
  int m = 0;
  double reach = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = in[i];
    const Eigen::Vector2d& q = in[(i + 1) % n];
    const double dp = normal.dot(p) - bound, dq = normal.dot(q) - bound;
    if (dp >= 0) out[m++] = p;
    if ((dp >= 0) != (dq >= 0)) out[m++] = p + (q - p) * (dp / (dp - dq));
    reach = std::max(reach, dp);
  }
  return reach > kSweptSideToleranceM ? m : 0;
}

/// Whether convex polygons a (na points) and b (nb points; either may be a segment or a point)
/// come within d of each other (touching counts).
bool withinDistance(const Eigen::Vector2d* a, int na, const Eigen::Vector2d* b, int nb, double d) {
  // Overlap: no edge normal of either separates them (touching counts).
  const double gap = separatingGap(a, na, b, nb);
  if (gap > -std::numeric_limits<double>::infinity() && !(gap > 0)) return true;
  // Apart: the nearest points are a vertex of one and an edge (or the point) of the other.
  for (const auto& [p, n, q, m] : {std::tuple(a, na, b, nb), std::tuple(b, nb, a, na)}) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < m; ++j) {
        if ((closestPointOnSegment(p[i], q[j], q[(j + 1) % m]) - p[i]).norm() <= d) return true;
      }
    }
  }
  return false;
}

}  // namespace

bool LayerComputer::clipToBody(const SampleGeometry& t, const Eigen::Vector3d& c, double ref_a, double ref_b,
                               double top_m, Obstacle& out) const {
  // Corners relative to the centroid: (x, y, height above the reference plane).
  using Corner = Eigen::Vector3d;
  const auto corner = [&](double x, double y, double z) {
    const double px = x - c.x(), py = y - c.y();
    return Corner(px, py, z - c.z() - ref_a * px - ref_b * py);
  };
  std::array<Corner, 6> a{corner(t.x0, t.y0, t.z0), corner(t.x0 + t.bx, t.y0 + t.by, t.z1),
                          corner(t.x0 + t.cx, t.y0 + t.cy, t.z2)};
  std::array<Corner, 6> b{};
  int n = 3;
  // Sutherland-Hodgman against h >= lo (sign +1) and h <= hi (sign -1): a convex polygon stays
  // convex, each plane adds at most one corner.
  const auto clip = [](const std::array<Corner, 6>& in, int count, std::array<Corner, 6>& result, double bound,
                       double sign) {
    int m = 0;
    for (int i = 0; i < count; ++i) {
      const Corner& p = in[static_cast<std::size_t>(i)];
      const Corner& q = in[static_cast<std::size_t>((i + 1) % count)];
      const double dp = sign * (p.z() - bound), dq = sign * (q.z() - bound);
      if (dp >= 0) result[static_cast<std::size_t>(m++)] = p;
      if ((dp >= 0) != (dq >= 0)) result[static_cast<std::size_t>(m++)] = p + (q - p) * (dp / (dp - dq));
    }
    return m;
  };
  const double lo = profile_.max_step_m, hi = std::min(top_m, profile_.min_clearance_m);
  n = clip(a, n, b, lo, 1.0);
  n = clip(b, n, a, hi, -1.0);
  if (n == 0) return false;
  double top = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) top = std::max(top, a[static_cast<std::size_t>(i)].z());
  // Surface reaching no higher than max_step (up to rounding) is a step the robot climbs.
  if (!(top > lo + kBodyToleranceM)) return false;
  out.n = std::min(n, static_cast<int>(out.p.size()));
  for (int i = 0; i < out.n; ++i) out.p[static_cast<std::size_t>(i)] = a[static_cast<std::size_t>(i)].head<2>();
  out.top_m = std::min(top, hi);
  return true;
}

void LayerComputer::collectSupportedParts(const StoredFace& f, const SampleGeometry& t, const Eigen::Vector3d& c,
                                          double ref_a, double ref_b) const {
  const Eigen::Vector3d v[3] = {{t.x0, t.y0, t.z0}, {t.x0 + t.bx, t.y0 + t.by, t.z1}, {t.x0 + t.cx, t.y0 + t.cy, t.z2}};
  const double support = profile_.evidence.obstacle_support_m;
  for (int i = 0; i < 3; ++i) {
    // A vertex on the ground says where the ground is, not that an obstacle rises from it.
    const Eigen::Vector3d& a = v[i];
    const double dx = a.x() - c.x(), dy = a.y() - c.y();
    if (!(a.z() - c.z() - ref_a * dx - ref_b * dy > profile_.max_step_m)) continue;
    // The corner triangle at vertex i: along each edge, as far as the support reaches.
    const Eigen::Vector3d& b = v[(i + 1) % 3];
    const Eigen::Vector3d& d = v[(i + 2) % 3];
    const auto reach = [&](const Eigen::Vector3d& to) {
      const double length = (to - a).norm();
      return length > support ? a + (to - a) * (support / length) : to;
    };
    const Eigen::Vector3d b2 = reach(b), d2 = reach(d);
    SampleGeometry corner = t;
    corner.x0 = a.x();
    corner.y0 = a.y();
    corner.z0 = a.z();
    corner.bx = b2.x() - a.x();
    corner.by = b2.y() - a.y();
    corner.z1 = b2.z();
    corner.cx = d2.x() - a.x();
    corner.cy = d2.y() - a.y();
    corner.z2 = d2.z();
    Obstacle o;
    if (!clipToBody(corner, c, ref_a, ref_b, profile_.min_clearance_m, o)) continue;
    o.possible = false;
    setExtension(o, t, c);
    // Beyond the strip the body swept it may extend as anywhere; its extension into the strip is
    // contradicted by the drive. A part inside the strip counts whole, with its extension, where
    // its vertex stands inside too (something placed later; the evidence withdraws a drive only
    // for the points in the body). From a vertex beyond the strip the support into it is inferred
    // as the extension is, over the volume the body swept: the drive contradicts it.
    Obstacle inside;
    if (!pushBeyondStrip(f, o, inside)) {
      obstacles_.push_back(o);
      continue;
    }
    const double vertex_across_m = f.driveNormal().dot(a.head<2>() - c.head<2>()) - f.driveOffsetM();
    if (inside.n > 0 && !(std::abs(vertex_across_m) > sweptHalfWidthM())) obstacles_.push_back(inside);
  }
}

bool LayerComputer::pushBeyondStrip(const StoredFace& f, const Obstacle& o, Obstacle& inside) const {
  if (!(f.drive_axis.squaredNorm() > 0)) return false;
  // The strip |across| <= half width about the drive's centre line, across = n . p - offset
  // (p relative to the centroid).
  const Eigen::Vector2d n = f.driveNormal();
  const double offset = f.driveOffsetM();
  const double half = sweptHalfWidthM();
  // Beyond either side nobody drove: those parts count whole.
  for (const double sign : {1.0, -1.0}) {
    Obstacle beyond = o;
    beyond.n = clipToHalfPlane(o.p.data(), o.n, sign * n, half + sign * offset, beyond.p.data());
    if (beyond.n == 0) continue;
    beyond.beyond_strip = true;
    beyond.side_normal = sign * n;
    beyond.side_offset = half + sign * offset;
    obstacles_.push_back(beyond);
  }
  Obstacle half_strip = o;
  inside = o;
  half_strip.n = clipToHalfPlane(o.p.data(), o.n, n, offset - half, half_strip.p.data());
  inside.n = clipToHalfPlane(half_strip.p.data(), half_strip.n, -n, -(offset + half), inside.p.data());
  return true;
}

void LayerComputer::addUnsweptParts(const SurfaceStore& store, const StoredFace& f, const Obstacle& o, double z_lo,
                                    double z_hi, double reach_m) const {
  // Without the drive's centre line the strip is unknown: the drive contradicts the part whole.
  Obstacle inside;
  if (!pushBeyondStrip(f, o, inside) || inside.n == 0) return;
  // Inside, the part not over driven ground: the strip ends where the drive began or stopped.
  // That is judged along the drive, at the centre line's points abreast of the corners of what
  // lies within the footprints' reach (a box reach_m about the centroid): corners farther away
  // could not change what a footprint meets. Not at the corners themselves: the driven faces need
  // not reach the strip's sides, where a SLAM point on the road may hold the mesh's own faces.
  std::array<Eigen::Vector2d, 12> a, b;
  std::copy(inside.p.begin(), inside.p.begin() + inside.n, a.begin());
  int m = inside.n;
  for (const Eigen::Vector2d& axis : {Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)}) {
    m = clipToHalfPlane(a.data(), m, axis, -reach_m, b.data());
    m = clipToHalfPlane(b.data(), m, -axis, -reach_m, a.data());
  }
  const Eigen::Vector2d n = f.driveNormal();
  const double offset = f.driveOffsetM();
  for (int i = 0; i < m; ++i) {
    Eigen::Vector2d& corner = a[static_cast<std::size_t>(i)];
    corner -= (n.dot(corner) - offset) * n;
  }
  if (m > 0 && !overDrivenGround(store, a.data(), m, f.centroid_L, z_lo, z_hi)) obstacles_.push_back(inside);
}

bool LayerComputer::unconfirmedInBody(const StoredFace& f, double ref_a, double ref_b, const Eigen::Vector3d& p,
                                      Eigen::Vector2d& offset) const {
  const Eigen::Vector2d d = p.head<2>() - f.centroid_L.head<2>();
  const double height = p.z() - f.centroid_L.z() - ref_a * d.x() - ref_b * d.y();
  // A point over the step is in the body; a lower one that stands proud of the ground belongs to
  // something whose top may be (EvidenceModel::proud_point_rise_m).
  const double lowest = std::min(profile_.max_step_m, profile_.evidence.proud_point_rise_m);
  if (!(height > lowest + kBodyToleranceM && height <= profile_.min_clearance_m)) return false;
  // Where the robot stands on the face closest to the point: a planner may put it anywhere on it.
  const Eigen::Vector2d at = closestPoint(p.head<2>(), projectionOf(f));
  offset = p.head<2>() - at;
  return offset.norm() <= unconfirmedReachM();
}

bool LayerComputer::unconfirmedInBody(const StoredFace& f, const Eigen::Vector3d& p) const {
  const Reference r = referencePlane(f);
  Eigen::Vector2d offset;
  return unconfirmedInBody(f, r.ref_a, r.ref_b, p, offset);
}

void LayerComputer::collectUnconfirmed(const StoredFace& f, double ref_a, double ref_b) const {
  if (unconfirmed_ == nullptr || unconfirmed_->size() == 0) return;
  const Eigen::Vector2d reach(unconfirmedReachM(), unconfirmedReachM());
  unconfirmed_->forEachInBox(f.box_min - reach, f.box_max + reach, [&](const Eigen::Vector3d& p) {
    Obstacle o;
    o.p.fill(Eigen::Vector2d::Zero());
    if (!unconfirmedInBody(f, ref_a, ref_b, p, o.p[0])) return;
    // A point, relative to the footprint's centre where the face comes closest to it.
    o.n = 1;
    o.top_m = std::min(p.z() - f.centroid_L.z(), profile_.min_clearance_m);
    o.possible = true;
    o.unconfirmed = true;
    o.extension_m = profile_.evidence.unconfirmed_point_extension_m;
    obstacles_.push_back(o);
  });
}

bool LayerComputer::beyondSideWithin(const Obstacle& shadow, const Eigen::Vector2d* shape, int count,
                                    std::size_t heading, const Eigen::Vector2d& at, double margin_m) const {
  const Eigen::Vector2d& n = shadow.side_normal;
  std::array<Eigen::Vector2d, 4> footprint;
  if (profile_.footprint == FootprintShape::kDisc) {
    // The disc's segment beyond the side, within its bounding box (so never less).
    const Eigen::Vector2d t(-n.y(), n.x());
    const double r = radius_m_, far = n.dot(at) + r, width = far - shadow.side_offset;
    const double chord = width < r ? std::sqrt(std::max(0.0, r * r - (r - width) * (r - width))) : r;
    const double mid = t.dot(at);
    footprint = {n * shadow.side_offset + t * (mid - chord), n * far + t * (mid - chord), n * far + t * (mid + chord),
                 n * shadow.side_offset + t * (mid + chord)};
  } else {
    const Eigen::Vector2d u = heading_axes_[heading].first * (0.5 * profile_.footprint_length_m);
    const Eigen::Vector2d v = heading_axes_[heading].second * (0.5 * profile_.footprint_width_m);
    footprint = {at + u + v, at - u + v, at - u - v, at + u - v};
  }
  std::array<Eigen::Vector2d, 5> beyond;
  const int m = clipToHalfPlane(footprint.data(), 4, n, shadow.side_offset, beyond.data());
  return m > 0 && withinDistance(beyond.data(), m, shape, count, margin_m);
}

void LayerComputer::setExtension(Obstacle& o, const SampleGeometry& t, const Eigen::Vector3d& c) const {
  o.extension_m = obstacleExtensionM(t);
  const double front_length = t.normal_xy.norm();
  if (!(o.extension_m > 0) || !(front_length >= kMinSlantFrontNormalXy) || o.n == 0) return;
  // In front, as far as the face itself reaches below the body (that span is interpolated too).
  const Eigen::Vector2d front = t.normal_xy / front_length;
  double part_front = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < o.n; ++i) part_front = std::max(part_front, front.dot(o.p[static_cast<std::size_t>(i)]));
  const Eigen::Vector2d v0(t.x0 - c.x(), t.y0 - c.y());
  const double face_front = std::max({front.dot(v0), front.dot(v0 + Eigen::Vector2d(t.bx, t.by)),
                                      front.dot(v0 + Eigen::Vector2d(t.cx, t.cy))});
  const double ahead = face_front - part_front;
  if (front_length < kMinFrontNormalXy && !(ahead > kMinAheadM)) return;  // a tilted top: every way
  o.front = front;
  o.ahead_m = std::clamp(ahead, 0.0, o.extension_m);
}

void LayerComputer::growAlongFace(const Obstacle& o) {
  // The part grown by the half disc of radius e behind the face (its diameter along the face),
  // within the half octagon about it, and by ahead_m in front: the Minkowski sum's convex hull
  // (Andrew's monotone chain). (The parts a part is split into grow to the same union.)
  const Eigen::Vector2d& front = o.front;
  const Eigen::Vector2d along(-front.y(), front.x());
  const double e = o.extension_m, k = e * std::tan(M_PI / 8), ahead = o.ahead_m;
  const std::array<Eigen::Vector2d, 6> offsets{along * e + front * ahead, -along * e + front * ahead,
                                               along * e - front * k,     -along * e - front * k,
                                               along * k - front * e,     -along * k - front * e};
  std::array<Eigen::Vector2d, 6 * kMaxObstacleCorners> points;
  int count = 0;
  for (int i = 0; i < o.n; ++i) {
    for (const Eigen::Vector2d& d : offsets) points[static_cast<std::size_t>(count++)] = o.p[static_cast<std::size_t>(i)] + d;
  }
  std::sort(points.begin(), points.begin() + count,
            [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  std::array<Eigen::Vector2d, 6 * kMaxObstacleCorners + 1> hull;
  int h = 0;
  const auto cross = [](const Eigen::Vector2d& o2, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o2.x()) * (b.y() - o2.y()) - (a.y() - o2.y()) * (b.x() - o2.x());
  };
  for (int pass = 0; pass < 2; ++pass) {
    const int start = h;
    for (int j = 0; j < count; ++j) {
      const Eigen::Vector2d& q = points[static_cast<std::size_t>(pass == 0 ? j : count - 1 - j)];
      while (h >= start + 2 && cross(hull[static_cast<std::size_t>(h - 2)], hull[static_cast<std::size_t>(h - 1)], q) <= 0) --h;
      hull[static_cast<std::size_t>(h++)] = q;
    }
    --h;  // the last point of each chain starts the other
  }
  // (At most o.n + 6 corners in exact arithmetic; more: judged as grown every way.)
  o.grown_n = h <= kMaxObstacleCorners ? h : 0;
  std::copy(hull.begin(), hull.begin() + o.grown_n, o.grown.begin());
}

bool LayerComputer::meetsExtension(const Obstacle& o, std::size_t heading, const Eigen::Vector2d& at) const {
  // The grown shape is within the footprint grown by the extension every way (up to the half
  // octagon's corners): both must meet it.
  if (!meets(o, heading, at, o.extension_m)) return false;
  if (!(o.front.squaredNorm() > 0)) return true;
  if (o.grown_n < 0) growAlongFace(o);
  return o.grown_n == 0 || meetsShape(o, o.grown.data(), o.grown_n, heading, at, 0.0);
}

bool LayerComputer::meets(const Obstacle& shadow, std::size_t heading, const Eigen::Vector2d& at,
                          double margin_m) const {
  return meetsShape(shadow, shadow.p.data(), shadow.n, heading, at, margin_m);
}

bool LayerComputer::meetsShape(const Obstacle& shadow, const Eigen::Vector2d* shape, int count, std::size_t heading,
                               const Eigen::Vector2d& at, double margin_m) const {
  if (shadow.beyond_strip) {
    // The footprint's farthest reach across the strip's side.
    const Eigen::Vector2d& n = shadow.side_normal;
    const double extent = profile_.footprint == FootprintShape::kDisc
                              ? radius_m_
                              : 0.5 * profile_.footprint_length_m * std::abs(n.dot(heading_axes_[heading].first)) +
                                    0.5 * profile_.footprint_width_m * std::abs(n.dot(heading_axes_[heading].second));
    if (!(n.dot(at) + extent > shadow.side_offset + kSweptSideToleranceM)) return false;
  }
  if (!footprintMeets(shape, count, heading, at, margin_m)) return false;
  // Beyond the strip, its extension reaches only the footprint's part beyond the side (the drive
  // swept the rest): the dearer test, so the last.
  return !shadow.beyond_strip || (!(margin_m > 0) && shape == shadow.p.data()) ||
         beyondSideWithin(shadow, shape, count, heading, at, margin_m);
}

bool LayerComputer::footprintMeets(const Eigen::Vector2d* shape, int count, std::size_t heading,
                                   const Eigen::Vector2d& at, double margin_m) const {
  // The shape relative to the footprint's centre `at`.
  std::array<Eigen::Vector2d, kMaxObstacleCorners> rel;
  const int n = std::min(count, kMaxObstacleCorners);
  for (int i = 0; i < n; ++i) rel[static_cast<std::size_t>(i)] = shape[i] - at;
  if (profile_.footprint == FootprintShape::kDisc) {
    // Inside the polygon (strictly: a degenerate one has no inside) or within R of an edge.
    const double r2 = (radius_m_ + margin_m) * (radius_m_ + margin_m);
    bool positive = true, negative = true;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d& p = rel[static_cast<std::size_t>(i)];
      const Eigen::Vector2d& q = rel[static_cast<std::size_t>((i + 1) % n)];
      const Eigen::Vector2d e = q - p;
      const double len2 = e.squaredNorm();
      const double t = len2 > 0 ? std::clamp(-p.dot(e) / len2, 0.0, 1.0) : 0.0;
      if ((p + t * e).squaredNorm() <= r2) return true;
      const double cross = e.x() * (-p.y()) - e.y() * (-p.x());
      positive = positive && cross > 0;
      negative = negative && cross < 0;
    }
    return n >= 3 && (positive || negative);
  }
  // Separating axes: the rectangle's two and the polygon's edge normals (touching counts).
  const Eigen::Vector2d& u = heading_axes_[heading].first;
  const Eigen::Vector2d& v = heading_axes_[heading].second;
  const double half_a = 0.5 * profile_.footprint_length_m + margin_m, half_b = 0.5 * profile_.footprint_width_m + margin_m;
  const auto separated = [&](const Eigen::Vector2d& axis, double half) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i = 0; i < n; ++i) {
      const double d = rel[static_cast<std::size_t>(i)].dot(axis);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    return hi < -half || lo > half;
  };
  if (separated(u, half_a) || separated(v, half_b)) return false;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d e = rel[static_cast<std::size_t>((i + 1) % n)] - rel[static_cast<std::size_t>(i)];
    if (!(e.squaredNorm() > 0)) continue;
    const Eigen::Vector2d normal(-e.y(), e.x());
    if (separated(normal, half_a * std::abs(normal.dot(u)) + half_b * std::abs(normal.dot(v)))) return false;
  }
  return true;
}

std::uint16_t LayerComputer::causeOf(const Obstacle& o) {
  return o.unconfirmed ? reason::kUnconfirmedPoint : o.possible ? reason::kPossibleObstacle : reason::kObstacleExtension;
}

std::uint16_t LayerComputer::possibleCauses(std::size_t heading) const {
  std::uint16_t causes = 0;
  for (const Obstacle& o : obstacles_) {
    const std::uint16_t cause = causeOf(o);
    if (!(causes & cause) && meetsExtension(o, heading, judged_at_)) causes |= cause;
  }
  return causes;
}

const std::vector<double>& LayerComputer::obstacleTops(const StoredFace& f, bool steep,
                                                       std::array<Eigen::Vector2d, kObstaclePoints>& points) const {
  const std::size_t headings = heading_samples_.size();
  tops_.assign(headings, 0.0);
  possible_.assign(headings, 0);
  // The highest measured obstacle the footprint at point j and heading k meets (0: none).
  const auto topAt = [&](const Eigen::Vector2d& at, std::size_t k) {
    double top = 0;
    for (const Obstacle& o : obstacles_) {
      if (!o.possible && o.top_m > top && meets(o, k, at)) top = o.top_m;
    }
    return top;
  };
  const int n = obstaclePoints(f, steep, points);
  judged_at_ = f.layers.evidence == Evidence::kDriven ? centreLinePoint(f) : Eigen::Vector2d::Zero();
  // Possible obstacles where the face is judged (its centroid, or where the drive stood on it):
  // interpolated ones, and where measured ones may extend (the first one met per heading;
  // possibleCauses lists them all where that is asked).
  for (const Obstacle& o : obstacles_) {
    for (std::size_t k = 0; k < headings; ++k) {
      if (!possible_[k] && meetsExtension(o, k, judged_at_)) possible_[k] = causeOf(o);
    }
  }
  // There, heading by heading (a heading that collides there does not fit).
  bool blocked_there = true;
  for (std::size_t k = 0; k < headings; ++k) {
    tops_[k] = topAt(judged_at_, k);
    blocked_there = blocked_there && tops_[k] > 0;
  }
  if (n == 1 || !blocked_there) return tops_;
  // A face larger than the footprint, blocked where it is judged: blocked only if the robot also
  // collides (at every heading) at most (more than half) of its points, else the obstacles do not
  // count. A face free at its centroid stays as it was: the points only ever waive a collision.
  int blocked = 0;
  for (int j = 0; j < n; ++j) {
    bool all = true;
    for (std::size_t k = 0; k < headings && all; ++k) all = topAt(points[static_cast<std::size_t>(j)], k) > 0;
    blocked += all ? 1 : 0;
  }
  if (!(2 * blocked > n)) tops_.assign(headings, 0.0);
  return tops_;
}

int LayerComputer::obstaclePoints(const StoredFace& f, bool steep, std::array<Eigen::Vector2d, 9>& points) const {
  points[0].setZero();
  if (steep || !(0.5 * std::abs(f.projected_det) > footprint_area_m2_)) return 1;
  const Eigen::Vector2d c = f.centroid_L.head<2>();
  const Eigen::Vector2d a = f.p_L[0].head<2>() - c, b = f.p_L[1].head<2>() - c, d = f.p_L[2].head<2>() - c;
  // Barycentric (i, j, k) / 3 grid, i + j + k = 3: the 6 upward sub-triangles' centroids are at
  // (i + 1/3, j + 1/3, k + 1/3) / 3 with i + j + k = 2, the 3 downward ones' at
  // (i + 2/3, j + 2/3, k + 2/3) / 3 with i + j + k = 1.
  int n = 0;
  const auto add = [&](double u, double v, double w) {
    Eigen::Vector2d q = (u * a + v * b + w * d) / 3.0;
    const double len = q.norm();
    if (len > radius_m_) q *= radius_m_ / len;
    points[static_cast<std::size_t>(n++)] = q;
  };
  for (int i = 0; i <= 2; ++i) {
    for (int j = 0; i + j <= 2; ++j) add(i + 1.0 / 3, j + 1.0 / 3, 2 - i - j + 1.0 / 3);
  }
  for (int i = 0; i <= 1; ++i) {
    for (int j = 0; i + j <= 1; ++j) add(i + 2.0 / 3, j + 2.0 / 3, 1 - i - j + 2.0 / 3);
  }
  return n;
}

bool LayerComputer::overDrivenGround(const SurfaceStore& store, const Eigen::Vector2d* corners, int n,
                                     const Eigen::Vector3d& c, double z_lo, double z_hi) const {
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p = c.head<2>() + corners[i];
    bool found = false;
    store.forEachAt(p.x(), p.y(), [&](Slot u) {
      if (found) return;
      const FaceBounds& b = store.bounds(u);
      if (!b.alive || b.max_z < z_lo || b.min_z > z_hi) return;
      const SampleGeometry& g = store.geometry(u);
      if (!g.sampleable || !g.driven) return;
      found = g.heightAt(p.x(), p.y()).has_value();
    });
    if (!found) return false;
  }
  return true;
}

Eigen::Vector2d LayerComputer::centreLinePoint(const StoredFace& f) const {
  if (!(f.drive_axis.squaredNorm() > 0)) return Eigen::Vector2d::Zero();
  // Across the line (the vertices' distances from it) and along it, relative to the centroid.
  const Eigen::Vector2d n = f.driveNormal(), c = f.centroid_L.head<2>();
  const double offset = f.driveOffsetM();
  std::array<double, 3> across{}, along{};
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d p = f.p_L[static_cast<std::size_t>(i)].head<2>() - c;
    across[static_cast<std::size_t>(i)] = n.dot(p) - offset;
    along[static_cast<std::size_t>(i)] = f.drive_axis.dot(p);
  }
  const double lo = *std::min_element(across.begin(), across.end());
  const double hi = *std::max_element(across.begin(), across.end());
  // The line the face comes nearest (the centre line itself where the face spans it).
  const double line = std::clamp(0.0, lo, hi);
  if (!(std::abs(line) <= kCentreLineToleranceM)) return Eigen::Vector2d::Zero();
  // The face's chord along that line: where its edges meet it.
  double first = std::numeric_limits<double>::infinity(), last = -first;
  for (int i = 0; i < 3; ++i) {
    const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>((i + 1) % 3);
    const double da = across[a] - line, db = across[b] - line;
    if ((da > 0 && db > 0) || (da < 0 && db < 0)) continue;
    const double t = da == db ? 0.0 : da / (da - db);
    const double at = along[a] + t * (along[b] - along[a]);
    first = std::min(first, at);
    last = std::max(last, at);
  }
  if (!(first <= last)) return Eigen::Vector2d::Zero();
  // The chord's point nearest the centroid's foot on the line (along 0).
  return (offset + line) * n + std::clamp(0.0, first, last) * f.drive_axis;
}

}  // namespace terramesh::traversability::internal
