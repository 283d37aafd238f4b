#!/usr/bin/env python3
"""Why a traversability map calls ground free that the ground truth says is not traversable.

Usage: traversability_false_positives.py MAP_DIR GROUND_TRUTH.ply [TRAVERSE_EVAL_REPORT.txt]
           [--swept TRAJECTORY.txt LATERAL_M [CAMERA_HEIGHT_M]]

MAP_DIR is a `terramesh mesh --robot` (or `traverse`) output (traversability.ply, robot.yaml),
GROUND_TRUTH.ply the labelled mesh of `terramesh generate`, both in metres, same frame. The
optional report of `terramesh traverse-eval MAP_DIR --gt-mesh GROUND_TRUTH.ply --report R` gives
the up vector and the exact false-positive area per truth reason to check this script against.

It scores the map like traverse-eval (map faces split to edges <= 0.25 m, each piece within
0.5 m of the truth takes the answer of the nearest truth face, truth candidate faces split to
0.25 m) but re-judges the truth in numpy (evaluation/src/ground_truth_traversability.cpp is the
reference; here surfaces in the footprint are sampled as points ~0.15 m apart instead of clipped
as polygons, so areas differ by a few per cent). Every false-positive piece (map free, truth not
traversable) gets:
  - the truth's reason: not_ground/<label>, too_steep, low_clearance, curb_too_high, and for the
    footprint rule "step_at_centre" (something rises > max_step within the inscribed radius: a
    ledge or wall next to the face) or "no_heading_fits" (a rectangle: nothing under the car's
    centre, but it fits at none of the 16 headings: a narrow passage);
  - its place: "tilted" (map face normal > 10 deg from the nearest truth face's), else "off"
    (> 0.15 m from the truth), else "on" (the map face follows the truth);
  - whether a wall/obstacle/ceiling face of the truth lies within the footprint circumradius
    (horizontally, below the robot's height above the piece) and whether an unknown map face does;
  - the map's own contact (worst heading) and step (best heading) on that face.
Prints area in m^2 and fractions of the false-positive area per cause. With --swept (the
generator's trajectory.txt, the robot's half-width, the camera height, default 1.65 m), also the
robot's swept strip: the map within LATERAL_M of the camera path, CAMERA_HEIGHT_M +- 0.5 m below
it (traverse-eval --road-under-path's strip), how much of it the truth calls traversable for the
robot, and per map class the truth-traversable share (approximate, as above; `terramesh
traverse-eval MAP --gt-mesh GT --road-under-path STREAM` reports the exact share where the robot
fits, road_truth_fits_fraction). python3 + numpy + scipy.
"""
import math
import os
import sys
import time
from collections import defaultdict

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
import ply  # noqa: E402

LABELS = ["road", "sidewalk", "curb", "wall", "obstacle", "vegetation", "ceiling", "ramp"]
GROUND = {0, 1, 2, 5, 7}


START = time.process_time()


def progress(what):
    print(f"[{time.process_time() - START:7.1f} s cpu] {what}", file=sys.stderr)


def read_ply(path):
    """A triangle mesh PLY (scripts/figures/ply.py, the one PLY reader of the Python tools): vertices
    Nx3, faces Mx3 and the face element (face[property] is an array)."""
    elements = ply.read(path)
    if "vertex" not in elements or "face" not in elements:
        sys.exit(f"{path}: expected vertex and face elements")
    vertex, face = elements["vertex"], elements["face"]
    indices = face["vertex_indices"] if "vertex_indices" in face else None
    if not isinstance(indices, np.ndarray) or indices.ndim != 2 or indices.shape[1] != 3:
        sys.exit(f"{path}: only triangles are supported")
    vertices = np.stack([vertex["x"], vertex["y"], vertex["z"]], axis=1).astype(np.float64)
    return vertices, indices.astype(np.int64), face


def read_robot(path):
    """The few keys of robot.yaml the truth uses (flat 'key: value' and footprint lines)."""
    robot = {}
    for line in open(path):
        line = line.split("#")[0]
        if ":" in line:
            key, value = (s.strip() for s in line.split(":", 1))
            try:
                robot[key] = float(value)
            except ValueError:
                pass
    return robot


def refine(tris, max_edge, parent=None):
    """Splits triangles (Nx3x3) at the midpoint of their longest edge until every edge is <= max_edge
    (as evaluation/src/mesh_refinement.cpp). Returns pieces and their parent index."""
    parent = np.arange(len(tris)) if parent is None else parent
    done_t, done_p = [], []
    while len(tris):
        edges = np.stack([tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 1], tris[:, 0] - tris[:, 2]], axis=1)
        length_sq = np.einsum("nij,nij->ni", edges, edges)
        longest = np.argmax(length_sq, axis=1)
        twice_area = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
        final = (length_sq[np.arange(len(tris)), longest] <= max_edge * max_edge) | (twice_area <= 0)
        done_t.append(tris[final])
        done_p.append(parent[final])
        tris, parent, longest = tris[~final], parent[~final], longest[~final]
        idx = np.arange(len(tris))
        a, b, c = tris[idx, longest], tris[idx, (longest + 1) % 3], tris[idx, (longest + 2) % 3]
        m = 0.5 * (a + b)
        tris = np.concatenate([np.stack([a, m, c], 1), np.stack([m, b, c], 1)])
        parent = np.concatenate([parent, parent])
    return np.concatenate(done_t), np.concatenate(done_p)


def closest_on_triangles(p, a, b, c):
    """Closest points to p (Nx3) on triangles (a, b, c) (each Nx3), Ericson's region test."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    denom = va + vb + vc
    with np.errstate(divide="ignore", invalid="ignore"):
        v = np.where(denom != 0, vb / denom, 0.0)
        w = np.where(denom != 0, vc / denom, 0.0)
        out = a + ab * v[:, None] + ac * w[:, None]
        # Edge and vertex regions, in the reverse order of precedence.
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        out = np.where(((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0))[:, None], b + (c - b) * t_bc[:, None], out)
        t_ac = d2 / (d2 - d6)
        out = np.where(((vb <= 0) & (d2 >= 0) & (d6 <= 0))[:, None], a + ac * t_ac[:, None], out)
        t_ab = d1 / (d1 - d3)
        out = np.where(((vc <= 0) & (d1 >= 0) & (d3 <= 0))[:, None], a + ab * t_ab[:, None], out)
    out = np.where(((d6 >= 0) & (d5 <= d6))[:, None], c, out)
    out = np.where(((d3 >= 0) & (d4 <= d3))[:, None], b, out)
    out = np.where(((d1 <= 0) & (d2 <= 0))[:, None], a, out)
    return out


def ray_hits(origin, direction, tris, max_t):
    """Whether the ray origin + t direction, 0 < t < max_t, meets each triangle (Moller-Trumbore)."""
    e1, e2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - tris[:, 0]
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ direction) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    return ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t < max_t)


def normals(tris):
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    length = np.linalg.norm(n, axis=1)
    return n / np.where(length > 0, length, 1)[:, None]


def swept_strip(trajectory_path, lateral_m, camera_height_m, centre, up):
    """Pieces within lateral_m (horizontally) of the path camera_height_m below the cameras, and
    within 0.5 m of that height."""
    cameras = np.loadtxt(trajectory_path, ndmin=2).reshape(-1, 3, 4)[:, :, 3]
    ground = cameras - camera_height_m * up
    inside = np.zeros(len(centre), bool)
    for a, b in zip(ground[:-1], ground[1:]):
        ab = b - a
        t = np.clip(((centre - a) @ ab) / max(ab @ ab, 1e-12), 0, 1)
        rel = centre - (a + t[:, None] * ab)
        h = rel @ up
        inside |= (np.linalg.norm(rel - np.outer(h, up), axis=1) <= lateral_m) & (np.abs(h) <= 0.5)
    return inside


def print_swept(strip, area, classes, truth_ok, piece_reason):
    total = area[strip].sum()
    if not total > 0:
        print("swept strip: no scored map surface")
        return
    print(f"swept strip: {total:.1f} m2 scored, truth traversable {area[strip & truth_ok].sum() / total:.3f}")
    for c, name in enumerate(["free", "lethal", "unknown", "uncertain"]):
        m = strip & (classes == c)
        share = area[m].sum() / total
        ok = area[m & truth_ok].sum() / area[m].sum() if area[m].sum() > 0 else float("nan")
        print(f"  map {name:9s} {share:.3f} of the strip; truth traversable there {ok:.3f}")
    for r in sorted(set(piece_reason[strip])):
        print(f"  truth {r or 'unjudged'}: {area[strip & (piece_reason == r)].sum() / total:.3f}")


def main():
    args = sys.argv[1:]
    swept = None
    if "--swept" in args:
        i = args.index("--swept")
        values = args[i + 1:]
        if len(values) not in (2, 3):
            sys.exit(__doc__)
        swept = (values[0], float(values[1]), float(values[2]) if len(values) == 3 else 1.65)
        args = args[:i]
    if len(args) not in (2, 3):
        sys.exit(__doc__)
    map_dir, truth_path = args[0], args[1]
    report = {}
    if len(args) == 3:
        for line in open(args[2]):
            words = line.split()
            if len(words) >= 2:
                report[words[0]] = words[1:]
    robot = read_robot(f"{map_dir}/robot.yaml")
    length, width = robot.get("length_m", 0.0), robot.get("width_m", 0.0)
    rectangle = length > 0 and width > 0
    radius = math.hypot(length, width) / 2 if rectangle else robot["radius_m"]
    inscribed = min(length, width) / 2 if rectangle else radius
    step, height, max_slope = robot["max_step_m"], robot["min_clearance_m"], robot["max_slope_deg"]
    headings = 16

    tv, tf, tprops = read_ply(truth_path)
    labels, slopes = tprops["label"].astype(int), tprops["slope_deg"].astype(float)
    if "truth_up" in report:
        up = np.array([float(x) for x in report["truth_up"]])
    else:  # area-weighted normal of the level faces, as estimateUpFromSlopes
        level = slopes <= 1.0
        t = tv[tf[level]]
        up = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]).sum(0)
    up /= np.linalg.norm(up)

    # The truth as labelTraversability sees it: candidates split to 0.25 m, the others whole.
    tris = tv[tf]
    candidate = np.isin(labels, list(GROUND)) & (slopes <= max_slope)
    cand_tris, cand_parent = refine(tris[candidate], 0.25, np.flatnonzero(candidate))
    other_idx = np.flatnonzero(~candidate)
    truth_tris = np.concatenate([cand_tris, tris[other_idx]])
    truth_parent = np.concatenate([cand_parent, other_idx])
    truth_label = labels[truth_parent]
    truth_cand = np.concatenate([np.ones(len(cand_tris), bool), np.zeros(len(other_idx), bool)])
    progress("truth refined")
    # For nearest-face queries every truth face is split to 0.25 m; pieces map back to truth_tris.
    q_tris, q_owner = refine(truth_tris, 0.25)
    q_tree = cKDTree(q_tris.mean(1))
    progress("query index built")
    # Point samples of the whole truth surface for the footprint: the centroids of its pieces split
    # to edges <= 0.2 m (about 0.15 m apart), and its vertices.
    s_tris, s_owner = refine(tris, 0.2)
    samples = np.concatenate([s_tris.mean(1), tv])
    vertex_label = np.zeros(len(tv), int)
    vertex_label[tf.ravel()] = np.repeat(labels, 3)  # a vertex shared by labels takes one of them
    sample_label = np.concatenate([labels[s_owner], vertex_label])
    del s_tris, s_owner
    east = np.cross(up, [1.0, 0, 0] if abs(up[0]) < 0.9 else [0, 1.0, 0])
    east /= np.linalg.norm(east)
    north = np.cross(up, east)
    plane = np.stack([samples @ east, samples @ north], 1)
    plane_tree = cKDTree(plane)
    q_centres = q_tris.mean(1)
    q_plane_tree = cKDTree(np.stack([q_centres @ east, q_centres @ north], 1))
    blocking = ~np.isin(sample_label, list(GROUND))
    wall_tree = cKDTree(plane[blocking])
    wall_height = samples[blocking] @ up

    progress("samples indexed")
    # The map, split like traverse-eval's scorer.
    mv, mf, mprops = read_ply(f"{map_dir}/traversability.ply")
    m_tris = mv[mf]
    pieces, piece_face = refine(m_tris, 0.25)
    centre = pieces.mean(1)
    area = 0.5 * np.linalg.norm(np.cross(pieces[:, 1] - pieces[:, 0], pieces[:, 2] - pieces[:, 0]), axis=1)
    unknown = mprops["unknown"][piece_face] != 0
    uncertain = mprops["uncertain"][piece_face] != 0 if "uncertain" in mprops else np.zeros_like(unknown)
    free = (~unknown) & (~uncertain) & (mprops["lethal"][piece_face] == 0)

    # Only free pieces are judged (precision needs nothing else), and with --swept the strip.
    strip = swept_strip(*swept, centre, up) if swept else np.zeros(len(centre), bool)
    judged = free | strip
    best_d = np.full(len(centre), np.inf)
    best_q = np.zeros(len(centre), int)
    _, cand = q_tree.query(centre[judged], k=8)
    for k in range(cand.shape[1]):
        qt = q_tris[cand[:, k]]
        d = np.linalg.norm(closest_on_triangles(centre[judged], qt[:, 0], qt[:, 1], qt[:, 2]) - centre[judged], axis=1)
        better = d < best_d[judged]
        fi = np.flatnonzero(judged)[better]
        best_d[fi], best_q[fi] = d[better], cand[better, k]
    near_face = q_owner[best_q]
    scored = best_d <= 0.5

    progress("nearest truth faces found")
    # Judge the truth faces the scored known pieces take their answer from.
    needed = np.unique(near_face[scored & judged])
    reason = {}
    t_normals = normals(truth_tris)
    t_normals *= np.where(t_normals @ up < 0, -1.0, 1.0)[:, None]
    progress(f"{len(needed)} truth faces to judge")
    for f in needed:
        if not truth_cand[f]:
            reason[f] = "too_steep" if truth_label[f] in GROUND else "not_ground/" + LABELS[truth_label[f]]
            continue
        c, n = truth_tris[f].mean(0), t_normals[f]
        near = np.array(plane_tree.query_ball_point([c @ east, c @ north], radius + 0.5))
        rel = samples[near] - c
        # Clearance: the ray straight up from the centre hits a truth face closer than height.
        hits = q_plane_tree.query_ball_point([c @ east, c @ north], 0.3)
        if hits and np.any(ray_hits(c + 1e-6 * up, up, q_tris[hits], height - 1e-6)):
            reason[f] = "low_clearance"
            continue
        h = rel @ n
        flat = rel - np.outer(h, n)
        u = np.cross(n, east if abs(n @ east) < 0.9 else north)
        u /= np.linalg.norm(u)
        v = np.cross(n, u)
        xy = np.stack([flat @ u, flat @ v], 1)
        dist = np.linalg.norm(xy, axis=1)
        rises = (h > step) & (h <= height) & (dist <= radius)
        if np.any(rises & (dist <= inscribed)):
            reason[f] = "step_at_centre"
            continue
        if np.any(rises) and not rectangle:
            reason[f] = "step_at_centre"
            continue

        def fits(mask):
            pts = xy[mask]
            if len(pts) == 0:
                return True
            for k in range(headings):
                t = math.pi * k / headings
                a = pts @ np.array([math.cos(t), math.sin(t)])
                b = pts @ np.array([-math.sin(t), math.cos(t)])
                if not np.any((np.abs(a) <= length / 2) & (np.abs(b) <= width / 2)):
                    return True
            return False

        if not fits(rises):
            reason[f] = "no_heading_fits"
            continue
        if truth_label[f] == 2:
            drops = (h < -step) & (h >= -height) & (dist <= radius)
            if not (fits(rises | drops) if rectangle else not np.any(drops)):
                reason[f] = "curb_too_high"
                continue
        reason[f] = "traversable"

    progress("truth judged")
    piece_reason = np.array([reason.get(f, "") for f in near_face], dtype=object)
    truth_ok = piece_reason == "traversable"
    known = scored & ~unknown
    tp = area[known & free & truth_ok].sum()
    fp_mask = known & free & ~truth_ok
    fp = area[fp_mask].sum()
    if swept:
        classes = np.where(unknown, 2, np.where(uncertain, 3, np.where(mprops["lethal"][piece_face] != 0, 1, 0)))
        print_swept(strip & scored, area, classes, truth_ok, piece_reason)
    print(f"map {map_dir} ({'rectangle %.2f x %.2f m' % (length, width) if rectangle else 'disc r %.2f m' % radius}, "
          f"step {step} m, slope {max_slope} deg, height {height} m)")
    print(f"free map area {area[free].sum():.1f} m2: within 0.5 m of the truth (scored) {area[free & scored].sum():.1f}, "
          f"farther (not scored) {area[free & ~scored].sum():.1f}")
    print(f"this script: TP {tp:.1f}  FP {fp:.1f} m2  precision {tp / (tp + fp):.4f}")
    if report:
        print(f"traverse-eval: TP {float(report['true_positive_m2'][0]):.1f}  FP {float(report['false_positive_m2'][0]):.1f}"
              f" m2  precision {report['precision'][0]}")
        exact = {k[len("reason_"):-len("_free_m2")]: float(v[0]) for k, v in report.items()
                 if k.startswith("reason_") and k.endswith("_free_m2") and k != "reason_traversable_free_m2"}
        print("traverse-eval FP by truth reason: " + ", ".join(f"{k} {v:.1f}" for k, v in exact.items()))

    # Per false-positive piece: place, walls and unknown map faces nearby.
    idx = np.flatnonzero(fp_mask)
    tilt = np.degrees(np.arccos(np.clip(np.abs(np.einsum(
        "ij,ij->i", normals(pieces[idx]), t_normals[near_face[idx]])), 0, 1)))
    place = np.where(tilt > 10, "tilted", np.where(best_d[idx] > 0.15, "off", "on"))
    unknown_centres = centre[unknown]
    unknown_tree = cKDTree(unknown_centres) if len(unknown_centres) else None
    near_unknown = np.zeros(len(idx), bool)
    near_wall = np.zeros(len(idx), bool)
    for j, p in enumerate(idx):
        c = centre[p]
        if unknown_tree is not None:
            near_unknown[j] = len(unknown_tree.query_ball_point(c, radius)) > 0
        hits = wall_tree.query_ball_point([c @ east, c @ north], radius)
        if hits:
            dh = wall_height[hits] - c @ up
            near_wall[j] = np.any((dh > -0.5) & (dh < height))

    progress("false positives described")
    def table(title, keys):
        sums = defaultdict(float)
        for key, a in zip(keys, area[idx]):
            sums[key] += a
        print(title)
        for key, a in sorted(sums.items(), key=lambda kv: -kv[1]):
            print(f"  {key:40s} {a:8.1f} m2  {a / fp:6.3f}")

    reasons = piece_reason[idx]
    simple = np.array([r.split("/")[0] if r.startswith("not_ground") else r for r in reasons], dtype=object)
    table("FP by truth reason (this script):", reasons)
    table("FP by place:", place)
    table("FP by truth reason x place:", [f"{r} @ {p}" for r, p in zip(simple, place)])
    table("FP by wall/obstacle within the footprint radius:", np.where(near_wall, "near wall/obstacle", "no wall/obstacle"))
    table("FP by unknown map face within the footprint radius:", np.where(near_unknown, "near unknown", "no unknown"))
    table("FP by truth reason x near wall:", [f"{r} @ {'wall' if w else 'open'}" for r, w in zip(simple, near_wall)])
    # The map's own verdict: its contact at the worst heading (1 = every footprint sample supported)
    # and its step at the best heading.
    contact = mprops["contact"][piece_face[idx]]
    map_step = mprops["step_m"][piece_face[idx]]
    table("FP by truth reason x the map's worst-heading contact:",
          [f"{r} @ contact {'1' if c >= 1 else '<1'}" for r, c in zip(simple, contact)])
    table("FP by the map's step at the best heading:",
          np.where(map_step <= 0.5 * step, f"step <= {0.5 * step:g} m", f"step in ({0.5 * step:g}, {step:g}] m"))


if __name__ == "__main__":
    main()
