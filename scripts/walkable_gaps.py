#!/usr/bin/python3
"""What cuts the walkable surface of a traversability map into pieces.

    walkable_gaps.py MAP_DIR [--truth GROUND_TRUTH.ply] [--max-gap-m 2]

MAP_DIR is what `terramesh mesh --robot` or `terramesh traverse` wrote (traversability.ply,
robot.yaml, map_frame.yaml). Walkable faces are the planner's (planning::FaceGraph): class free,
lethal_distance_m >= the robot's inscribed radius, normal within 60 deg of up, non-zero area.

For every two walkable pieces (components) the shortest bridge over non-walkable faces is found
(multi-source Dijkstra over face centroids from every walkable face, then the cheapest edge
between faces reached from different pieces). The faces on bridges no longer than --max-gap-m
are what separates pieces that almost touch; they are tallied by why they are not walkable:

  unknown/steiner, unknown/few-rays, lethal/<failed tests>, free/near-lethal, free/tilted.

Lethal tests are re-evaluated from the layers with the robot's limits (slope: steeper than
max_slope_deg; the layer's riser exemption needs per-face data not in the file, so "slope" may
include risers the layer exempted); a lethal face whose failed tests are not found is
"lethal/?". With --truth (a generated scene's ground_truth.ply), each bridge face is compared
with the nearest truth surface (sampled every 10 cm): distance, truth label, and the face's tilt
against the truth's slope; "right geometry" means within 0.15 m of a traversable truth face and
within 10 deg of its slope, i.e. the layer, not the reconstruction, blocks there.

Finally the components are recomputed with each cause lifted (those faces made walkable, the
lethal distance recomputed from the remaining lethal faces): how many pieces, how large.
Needs numpy and scipy (Debian python3-numpy, python3-scipy). Prints a Markdown report.
"""
import argparse
import collections
import math
import os
import sys

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, dijkstra
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
import ply  # noqa: E402

TRAVERSABLE_TRUTH = {0, 1, 2, 5, 7}  # road, sidewalk, curb, vegetation, ramp


def read_ply(path):
    """Elements of a PLY file (scripts/figures/ply.py, the one PLY reader of the Python tools):
    element[property] is an array."""
    return ply.read(path)


def sample_triangles(p0, p1, p2, spacing):
    """Points on each triangle on a barycentric grid of about `spacing`; (points, triangle index)."""
    points, owner = [], []
    for k in range(len(p0)):
        q0, q1, q2 = p0[k], p1[k], p2[k]
        steps = max(1, int(math.ceil(max(np.linalg.norm(q1 - q0), np.linalg.norm(q2 - q0)) / spacing)))
        u, v = np.meshgrid(np.arange(steps + 1), np.arange(steps + 1))
        keep = u + v <= steps
        u, v = u[keep] / steps, v[keep] / steps
        points.append(q0 + u[:, None] * (q1 - q0) + v[:, None] * (q2 - q0))
        owner.append(np.full(len(u), k))
    return np.concatenate(points), np.concatenate(owner)


def read_yaml_scalars(path):
    values = {}
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].rstrip()
            if ":" in line and not line.startswith(" "):
                key, value = line.split(":", 1)
                values[key.strip()] = value.strip()
    return values


def face_adjacency(faces):
    """Pairs of faces sharing an edge used by exactly two faces."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(faces)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    edges, owner = edges[order], owner[order]
    same = np.all(edges[1:] == edges[:-1], axis=1)
    starts = np.flatnonzero(np.concatenate([[True], ~same]))
    counts = np.diff(np.concatenate([starts, [len(edges)]]))
    two = starts[counts == 2]
    return owner[two], owner[two + 1]


def lethal_tests(layers, robot):
    tests = collections.OrderedDict()
    tests["slope"] = ~(layers["slope_deg"] <= float(robot["max_slope_deg"]))
    tests["step"] = layers["step_m"] > float(robot["max_step_m"])
    tests["roughness"] = layers["roughness_m"] > float(robot["max_roughness_m"])
    tests["contact"] = layers["contact"] < float(robot["min_support"])
    tests["clearance"] = layers["clearance_m"] < float(robot["min_clearance_m"])
    return tests


def cause_of(f, layers, tests, reasons):
    if layers["unknown"][f]:
        return "unknown/steiner" if layers["steiner"][f] else "unknown/few-rays"
    if layers["lethal"][f]:
        failed = [name for name, mask in tests.items() if mask[f]]
        return "lethal/" + ("+".join(failed) if failed else "?")
    return reasons[f]


def components(n, walkable, a, b):
    keep = walkable[a] & walkable[b]
    graph = coo_matrix((np.ones(keep.sum()), (a[keep], b[keep])), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    labels = np.where(walkable, labels, -1)
    return labels


def summarize(labels, area):
    ids, inverse = np.unique(labels[labels >= 0], return_inverse=True)
    sums = np.bincount(inverse, weights=area[labels >= 0]) if len(ids) else np.zeros(0)
    return len(ids), float(sums.sum()), float(sums.max()) if len(sums) else 0.0


def coverage(args, tp, tv, tf, vertices, faces, normal, up, mpu, layers, tests, reasons, walkable, max_slope_deg):
    """What the map has on the truth's traversable surface near the camera path."""
    cameras = np.loadtxt(args.trajectory)[:, [3, 7, 11]]
    label = tp["face"]["label"]
    # Drivable truth: a traversable label and a true slope within the robot's (no curb risers).
    traversable = np.isin(label, list(TRAVERSABLE_TRUTH)) & (tp["face"]["slope_deg"] <= max_slope_deg)
    idx = np.flatnonzero(traversable)
    q0, q1, q2 = tv[tf[idx, 0]], tv[tf[idx, 1]], tv[tf[idx, 2]]
    points, owner = sample_triangles(q0, q1, q2, 0.1)
    owner = idx[owner]
    face_area = 0.5 * np.linalg.norm(np.cross(tv[tf[:, 1]] - tv[tf[:, 0]], tv[tf[:, 2]] - tv[tf[:, 0]]), axis=1)
    weight = face_area[owner] / np.bincount(owner, minlength=len(tf))[owner]
    flat = lambda p: p - np.outer(p @ up, up)
    near_path, _ = cKDTree(flat(cameras)).query(flat(points))
    keep = near_path <= args.corridor_m
    points, owner, weight = points[keep], owner[keep], weight[keep]
    # The map face straight above or below each truth point (along up), the nearest in height.
    e1 = np.cross(up, [1.0, 0, 0] if abs(up[0]) < 0.9 else [0, 1.0, 0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    plane = lambda p: np.stack([p @ e1, p @ e2], axis=-1)
    tree = cKDTree(plane(points))
    height = points @ up
    d = np.full(len(points), np.inf)
    face = np.zeros(len(points), dtype=np.int64)
    corners = vertices[faces] * mpu
    for f in range(len(faces)):
        c2 = plane(corners[f])
        centre = c2.mean(axis=0)
        candidates = tree.query_ball_point(centre, np.max(np.linalg.norm(c2 - centre, axis=1)) + 1e-9)
        if not candidates:
            continue
        candidates = np.asarray(candidates)
        q = plane(points[candidates]) - c2[0]
        m = np.array([c2[1] - c2[0], c2[2] - c2[0]]).T
        if abs(np.linalg.det(m)) < 1e-12:
            continue
        uv = np.linalg.solve(m, q.T).T
        inside = (uv[:, 0] >= 0) & (uv[:, 1] >= 0) & (uv.sum(axis=1) <= 1)
        if not inside.any():
            continue
        hit = candidates[inside]
        z = corners[f][0] @ up + uv[inside] @ np.array([(corners[f][1] - corners[f][0]) @ up, (corners[f][2] - corners[f][0]) @ up])
        dz = np.abs(z - height[hit])
        better = dz < d[hit]
        d[hit[better]] = dz[better]
        face[hit[better]] = f
    tilt = np.degrees(np.arccos(np.clip(normal[face] @ up, -1, 1)))
    right = (d < 0.15) & (np.abs(tilt - tp["face"]["slope_deg"][owner]) <= 10)
    tally = collections.defaultdict(lambda: [0.0, 0.0])
    for k in range(len(points)):
        if not np.isfinite(d[k]):
            cause = "no map face above or below"
        elif d[k] > 0.3:
            far = "walkable" if walkable[face[k]] else cause_of(face[k], layers, tests, reasons)
            cause = "nearest face > 0.3 m off: " + (far if far.startswith("unknown") or far == "walkable" else far.split("/")[0])
        elif walkable[face[k]]:
            cause = "walkable"
        else:
            cause = cause_of(face[k], layers, tests, reasons)
        tally[cause][0] += weight[k]
        tally[cause][1] += weight[k] if right[k] else 0.0
    total = weight.sum()
    print(f"\n## The truth's drivable surface (traversable label, slope <= {max_slope_deg} deg) within "
          f"{args.corridor_m} m of the camera path "
          f"({total:.0f} m^2): what the map has there\n")
    print("| map face nearest in height (within 0.3 m) | truth m^2 | share | of it with right geometry (< 0.15 m in height, tilt within 10 deg) |")
    print("|---|---|---|---|")
    for cause, (s, r) in sorted(tally.items(), key=lambda item: -item[1][0]):
        print(f"| {cause} | {s:.0f} | {100 * s / total:.1f} % | {r:.0f} m^2 |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("map_dir")
    parser.add_argument("--truth")
    parser.add_argument("--trajectory", help="with --truth: trajectory.txt (KITTI poses) of the generated scene")
    parser.add_argument("--corridor-m", type=float, default=12.0, help="truth within this of the camera path")
    parser.add_argument("--max-gap-m", type=float, default=2.0)
    parser.add_argument("--max-tilt-deg", type=float, default=60.0)
    args = parser.parse_args()

    map_ply = read_ply(os.path.join(args.map_dir, "traversability.ply"))
    robot = read_yaml_scalars(os.path.join(args.map_dir, "robot.yaml"))
    frame = read_yaml_scalars(os.path.join(args.map_dir, "map_frame.yaml"))
    up = np.array([float(v) for v in frame.get("up_W", "[0, 0, 1]").strip("[]").split(",")])
    up /= np.linalg.norm(up)
    mpu = float(frame.get("metres_per_unit", 1))
    vertices = np.stack([map_ply["vertex"]["x"], map_ply["vertex"]["y"], map_ply["vertex"]["z"]], axis=1)
    layers = map_ply["face"]
    faces = layers["vertex_indices"].astype(np.int64)
    n = len(faces)
    p0, p1, p2 = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    cross = np.cross(p1 - p0, p2 - p0)
    norm = np.linalg.norm(cross, axis=1)
    area = 0.5 * norm * mpu * mpu
    normal = cross / np.maximum(norm, 1e-300)[:, None]
    centroid = (p0 + p1 + p2) / 3.0
    inscribed = float(robot["inscribed_radius_m"])
    facing_up = normal @ up >= math.cos(math.radians(args.max_tilt_deg))
    free = (layers["lethal"] == 0) & (layers["unknown"] == 0) & np.isfinite(layers["cost"])
    near_lethal = layers["lethal_distance_m"] < inscribed
    walkable = free & ~near_lethal & facing_up & (norm > 0)
    reasons = np.where(near_lethal, "free/near-lethal", np.where(~facing_up, "free/tilted", "free/degenerate"))
    tests = lethal_tests(layers, robot)

    a, b = face_adjacency(faces)
    labels = components(n, walkable, a, b)
    count, total, largest = summarize(labels, area)
    print(f"# Walkable pieces of {args.map_dir}\n")
    print(f"{n} faces; walkable {int(walkable.sum())} faces, {total:.0f} m^2 in {count} pieces, the largest "
          f"{largest:.0f} m^2 (robot {robot.get('name', '?')}, inscribed radius {inscribed} m)\n")

    # Bridges: Dijkstra from every walkable face over non-walkable faces.
    length = np.linalg.norm(centroid[a] - centroid[b], axis=1) * mpu
    through = ~walkable[a] | ~walkable[b]  # an edge into or between non-walkable faces
    graph = coo_matrix((np.maximum(length[through], 1e-9), (a[through], b[through])), shape=(n, n)).tocsr()
    sources = np.flatnonzero(walkable)
    dist, pred, origin = dijkstra(graph, directed=False, indices=sources, min_only=True,
                                  return_predecessors=True, limit=args.max_gap_m)
    piece = np.where(origin >= 0, labels[np.maximum(origin, 0)], -1)
    best = {}
    for i, j, d in zip(a, b, length):
        ci, cj = piece[i], piece[j]
        if ci < 0 or cj < 0 or ci == cj:
            continue
        gap = dist[i] + d + dist[j]
        key = (min(ci, cj), max(ci, cj))
        if gap <= args.max_gap_m and gap < best.get(key, (math.inf,))[0]:
            best[key] = (gap, i, j)
    bridge_faces = set()
    bridge_causes = collections.Counter()
    for gap, i, j in best.values():
        on_bridge = []
        for start in (i, j):
            f = start
            while f >= 0 and not walkable[f]:
                on_bridge.append(f)
                f = pred[f]
        bridge_faces.update(on_bridge)
        causes = sorted({cause_of(f, layers, tests, reasons) for f in on_bridge})
        bridge_causes[" + ".join(causes)] += 1
    print(f"## Joins: {len(best)} pairs of pieces with a bridge <= {args.max_gap_m} m over non-walkable faces\n")
    print("| causes of the faces on the bridge | bridges |\n|---|---|")
    for causes, k in bridge_causes.most_common():
        print(f"| {causes} | {k} |")

    tally = collections.defaultdict(lambda: [0, 0.0])
    for f in bridge_faces:
        cause = cause_of(f, layers, tests, reasons)
        tally[cause][0] += 1
        tally[cause][1] += area[f]
    print(f"\n## The {len(bridge_faces)} faces on those bridges ({sum(area[f] for f in bridge_faces):.1f} m^2)\n")
    truth_columns = ""
    truth = None
    if args.truth:
        tp = read_ply(args.truth)
        tv = np.stack([tp["vertex"]["x"], tp["vertex"]["y"], tp["vertex"]["z"]], axis=1)
        tf = tp["face"]["vertex_indices"].astype(np.int64)
        points, owner = sample_triangles(tv[tf[:, 0]], tv[tf[:, 1]], tv[tf[:, 2]], 0.1)
        truth = (cKDTree(points), owner, tp["face"]["label"], tp["face"]["slope_deg"])
        truth_columns = " near traversable truth (< 0.15 m) | right geometry (and tilt within 10 deg) |"
    print("| cause | faces | area (m^2) |" + truth_columns)
    print("|---|---|---|" + ("---|---|" if truth else ""))
    right_geometry = np.zeros(n, dtype=bool)
    if truth:
        tree, owner, label, slope = truth
        idx = np.array(sorted(bridge_faces), dtype=np.int64)
        if len(idx):
            d, nearest = tree.query(centroid[idx] * mpu)
            tlabel = label[owner[nearest]]
            tilt = np.degrees(np.arccos(np.clip(normal[idx] @ up, -1, 1)))
            near = (d < 0.15) & np.isin(tlabel, list(TRAVERSABLE_TRUTH))
            right_geometry[idx] = near & (np.abs(tilt - slope[owner[nearest]]) <= 10)
            near_truth = np.zeros(n, dtype=bool)
            near_truth[idx] = near
    for cause, (k, s) in sorted(tally.items(), key=lambda item: -item[1][1]):
        row = f"| {cause} | {k} | {s:.1f} |"
        if truth:
            members = [f for f in bridge_faces if cause_of(f, layers, tests, reasons) == cause]
            row += (f" {sum(area[f] for f in members if near_truth[f]):.1f} m^2 |"
                    f" {sum(area[f] for f in members if right_geometry[f]):.1f} m^2 |")
        print(row)

    if args.truth and args.trajectory:
        coverage(args, tp, tv, tf, vertices, faces, normal, up, mpu, layers, tests, reasons, walkable,
                 float(robot["max_slope_deg"]))

    # Lift each cause: which faces become walkable, and what the pieces become.
    print("\n## Pieces with one cause lifted (lethal distance recomputed)\n")
    print("| lifted | faces made walkable | pieces | walkable m^2 | largest m^2 |\n|---|---|---|---|---|")
    lethal = layers["lethal"] != 0
    tilt_ok = facing_up & (norm > 0)
    known_free = free

    def lethal_distance(lethal_mask):
        src = np.flatnonzero(lethal_mask)
        if len(src) == 0:
            return np.full(n, np.inf)
        graph_all = coo_matrix((np.maximum(length, 1e-9), (a, b)), shape=(n, n)).tocsr()
        d = dijkstra(graph_all, directed=False, indices=src, min_only=True, limit=inscribed * 1.0001)
        d[src] = 0.0
        return d

    only = {name: lethal & mask & ~np.any([m for other, m in tests.items() if other != name], axis=0)
            for name, mask in tests.items()}
    lifts = [
        ("nothing (the map as planned on; distance from centroids)", np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)),
        ("unknown faces (allow_unknown)", layers["unknown"] != 0, np.zeros(n, dtype=bool)),
    ]
    for name, mask in only.items():
        lifts.append((f"lethal only by {name}", np.zeros(n, dtype=bool), mask))
    lifts.append(("lethal only by contact or clearance", np.zeros(n, dtype=bool), only["contact"] | only["clearance"]))
    lifts.append(("unknown + lethal only by contact", layers["unknown"] != 0, only["contact"]))
    for name, unknown_lift, lethal_lift in lifts:
        remaining_lethal = lethal & ~lethal_lift
        d = lethal_distance(remaining_lethal)
        candidate = (known_free | unknown_lift | lethal_lift) & ~(d < inscribed) & tilt_ok
        lifted_labels = components(n, candidate, a, b)
        k, s, big = summarize(lifted_labels, area)
        print(f"| {name} | {int((unknown_lift | lethal_lift).sum())} | {k} | {s:.0f} | {big:.0f} |")


if __name__ == "__main__":
    main()
