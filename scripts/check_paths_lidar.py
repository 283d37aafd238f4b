#!/usr/bin/python3
"""Checks planned paths against LiDAR (truth from outside our own map).

    check_paths_lidar.py MAP_DIR PATH... (--kitti-scans DIR --poses POSES --frames A:B | --lidar PLY)
        [--sim3 FILE] [--csv OUT.csv]

MAP_DIR is what `terramesh mesh --robot` / `terramesh traverse` wrote (traversability.ply,
map_frame.yaml, robot.yaml, trajectory.csv); every PATH is a `path.csv` of `terramesh plan`
(`x,y,z,yaw,face,cost`, map frame and units) or a folder holding one. The truth is either
- `--kitti-scans DIR` (velodyne/%06d.bin, calib.txt) with `--poses` (KITTI poses, 12 numbers a
  line) and `--frames FIRST:LAST`: each scan placed by pose * Tr, as `terramesh eval --gt-lidar`
  does, and judged on its own (returns within --ego-radius-m, 3 m, of the sensor are dropped: the
  car); on KITTI 00 use this, not the merged cloud, whose scans disagree in height (see below); or
- `--lidar PLY`: one cloud in the truth frame (float/double x y z); a PLY with faces (a synthetic
  scene's ground_truth.ply) is sampled at --mesh-density points per m^2.
A map point p goes into the truth frame by `s R p + t` with `--sim3` (the file `terramesh eval
--sim3` reads; KITTI 00: kitti00_lidar/piazza_sim3_to_gt_icp.txt, the alignment of
docs/accuracy.md), else by `metres_per_unit * p`. Up in the truth frame is `R up` (map_frame.yaml).

Every --spacing-m (0.1 m) along a path, in metres:
- ground: in each cloud the returns within --column-radius-m (0.4 m) horizontally (perpendicular
  to up) form a column; its ground is the median of its lowest --ground-layer-m (0.3 m) of
  returns; the ground is the median over the clouds. The sample fails when its height h is more
  than --ground-tol-m (0.3 m) "above the LiDAR ground" or "below the LiDAR ground"; with no return
  in any cloud it is "no LiDAR return" (outside what the scans saw).
- obstacle: a cloud sees one when at least --min-obstacle-points (2) of its returns within the
  footprint radius (robot.yaml: radius_m, or half the rectangle's diagonal; --footprint-radius-m
  overrides) lie (max(max_step_m, --ground-spread-m), min_clearance_m] above that cloud's own
  ground (above h where it has none): what the robot's body would hit (small_wheeled: 0.18-0.5 m).
  The sample fails with "LiDAR obstacle in the footprint" when at least --min-obstacle-scans (2;
  1 for a single cloud) clouds see it and they are at least half of the clouds with returns in the
  footprint; otherwise it is "transient" (moving, or a stray return: reported, not a failure).
- unknown: whether the map face under it is unknown (traversability.ply's `unknown` flag; each
  path segment's face is the nearer of its two end states' faces to the segment's midpoint).

A path is "valid" when no sample fails and every sample has returns, "invalid" when some sample
fails (the first failure, its place in the truth frame and its face kind are printed, and the
failing length per reason with how much of it lies over unknown faces), "unchecked" when none
fails but some samples have no return. Also printed: |h - ground| median and max over measured
and over unknown faces.

With --poses, and with MAP_DIR/trajectory.csv, it first prints the alignment check: the height of
the KITTI pose camera centres and of the map's keyframe centres (mapped into the truth frame)
above the LiDAR ground within --alignment-radius-m (1 m): KITTI's camera is 1.65 m above the road.

Why per scan on KITTI 00: each scan's road is 1-3 cm thick, but placed by the KITTI poses the ten
scans' grounds at one place differ by a median 0.26 m (later scans higher), which a merged cloud
turns into a 0.3-0.5 m thick ground with false obstacles in it (--ground-spread-m raises the
obstacle band's floor for such a cloud).

numpy only. Exit 0 when it ran (whatever the verdicts), 2 on bad input. docs/planning.md ("KITTI
00 paths against the LiDAR") has the commands and results; tests/planning/check_paths_lidar_test.py.
"""

import argparse
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
import ply  # noqa: E402  (scripts/figures/ply.py: the one PLY reader of the Python tools)
from common import InputError  # noqa: E402


def read_ply(path):
    """Elements of a PLY file (scripts/figures/ply.py): element[property] is an array; a list
    property (faces) an (n, k) array when every list has length k."""
    return ply.read(path)


def read_sim3(path):
    values = {}
    with open(path) as f:
        for number, line in enumerate(f, 1):
            words = line.split("#")[0].split()
            if words and words[0] in ("s", "R", "t"):
                values[words[0]] = np.array([float(w) for w in words[1:]])
    if set(values) != {"s", "R", "t"} or values["R"].size != 9 or values["t"].size != 3:
        raise InputError(path, "", "expected lines 's S', 'R r00 ... r22', 't x y z'")
    return float(values["s"][0]), values["R"].reshape(3, 3), values["t"]


def read_simple_yaml(path):
    """The flat `key: value` / `key: [a, b, c]` lines of map_frame.yaml and robot.yaml (nested
    keys are returned as 'parent.key')."""
    out, parent = {}, None
    with open(path) as f:
        for line in f:
            line = line.split("#")[0].rstrip()
            m = re.match(r"^(\s*)([A-Za-z_]+):\s*(.*)$", line)
            if not m:
                continue
            indent, key, value = m.groups()
            if not indent:
                parent = key if not value else None
            elif parent:
                key = parent + "." + key
            if value.startswith("[") or value.startswith("{"):
                inner = value.strip("[]{}")
                if ":" in inner:
                    for part in inner.split(","):
                        k, v = part.split(":")
                        out[key + "." + k.strip()] = float(v)
                else:
                    out[key] = np.array([float(v) for v in inner.split(",")])
            elif value:
                try:
                    out[key] = float(value)
                except ValueError:
                    out[key] = value
    return out


def read_path_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    if header[:5] != ["x", "y", "z", "yaw", "face"]:
        raise InputError(path, "line 1", "expected the header x,y,z,yaw,face,cost")
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if rows.shape[0] < 2:
        raise InputError(path, "", "expected at least two states")
    return rows[:, :3], rows[:, 4].astype(np.int64)


def point_triangle_distance(p, a, b, c):
    """Distance from point p to triangle abc (Ericson's closest-point test)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = ab @ ap, ac @ ap
    if d1 <= 0 and d2 <= 0:
        return np.linalg.norm(ap)
    bp = p - b
    d3, d4 = ab @ bp, ac @ bp
    if d3 >= 0 and d4 <= d3:
        return np.linalg.norm(bp)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        return np.linalg.norm(p - (a + ab * d1 / (d1 - d3)))
    cp = p - c
    d5, d6 = ab @ cp, ac @ cp
    if d6 >= 0 and d5 <= d6:
        return np.linalg.norm(cp)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        return np.linalg.norm(p - (a + ac * d2 / (d2 - d6)))
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        return np.linalg.norm(p - (b + (c - b) * (d4 - d3) / ((d4 - d3) + (d5 - d6))))
    denom = 1.0 / (va + vb + vc)
    return np.linalg.norm(p - (a + ab * vb * denom + ac * vc * denom))


class Columns:
    """LiDAR returns bucketed in a horizontal grid (axes perpendicular to up) for column queries."""

    def __init__(self, points, up, cell_m):
        self.up = up / np.linalg.norm(up)
        helper = np.array([1.0, 0, 0]) if abs(self.up[0]) < 0.9 else np.array([0, 1.0, 0])
        self.ax = np.cross(self.up, helper); self.ax /= np.linalg.norm(self.ax)
        self.ay = np.cross(self.up, self.ax)
        self.cell = cell_m
        self.uv = np.stack([points @ self.ax, points @ self.ay], axis=1)
        self.h = points @ self.up
        ij = np.floor(self.uv / cell_m).astype(np.int64)
        self.key = ij[:, 0] * 1_000_003 + ij[:, 1]
        order = np.argsort(self.key, kind="stable")
        self.key, self.uv, self.h = self.key[order], self.uv[order], self.h[order]

    def plan(self, p):
        return np.array([p @ self.ax, p @ self.ay]), p @ self.up

    def heights_within(self, uv, radius):
        """Heights of the returns within `radius` horizontally of plan point uv."""
        r = int(np.ceil(radius / self.cell))
        i0, j0 = np.floor(uv / self.cell).astype(np.int64)
        parts = []
        for i in range(i0 - r, i0 + r + 1):
            keys = i * 1_000_003 + np.arange(j0 - r, j0 + r + 1)
            lo = np.searchsorted(self.key, keys[0], "left")
            hi = np.searchsorted(self.key, keys[-1], "right")
            if hi > lo:
                d = self.uv[lo:hi] - uv
                parts.append(self.h[lo:hi][np.einsum("ij,ij->i", d, d) <= radius * radius])
        return np.concatenate(parts) if parts else np.empty(0)


def sample_mesh(vertices, triangles, per_m2, seed=1):
    """Points on a triangle mesh, area-weighted, about per_m2 per square metre (a synthetic scene's
    ground truth standing in for a LiDAR); deterministic."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    rng = np.random.default_rng(seed)
    count = rng.poisson(area * per_m2)
    face = np.repeat(np.arange(len(triangles)), count)
    u, v = rng.random(len(face)), rng.random(len(face))
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    return a[face] + u[:, None] * (b - a)[face] + v[:, None] * (c - a)[face]


def ground_height(column, layer_m):
    """The ground of a LiDAR column: the median of its lowest layer (the returns within layer_m of
    the lowest one), or None for an empty column."""
    if column.size == 0:
        return None
    layer = column[column <= column.min() + layer_m]
    return float(np.median(layer))


def robot_limits(robot):
    if "footprint.radius_m" in robot:
        radius = robot["footprint.radius_m"]
    elif "footprint.length_m" in robot and "footprint.width_m" in robot:
        radius = 0.5 * np.hypot(robot["footprint.length_m"], robot["footprint.width_m"])
    else:
        raise InputError("robot.yaml", "footprint", "expected radius_m or length_m and width_m")
    return radius, robot.get("max_step_m", 0.18), robot.get("min_clearance_m", 0.5)


def ground_and_obstacle(clouds, p, args, robot):
    """At truth-frame point p: (ground height or None, spread of the clouds' grounds, clouds that
    see an obstacle in the footprint, clouds with returns in the footprint). Each cloud is judged
    against its own ground."""
    footprint_m, step_m, clearance_m = robot
    obstacle_above_m = max(step_m, args.ground_spread_m)
    grounds, seeing, looking = [], 0, 0
    for columns in clouds:
        uv, h = columns.plan(p)
        g = ground_height(columns.heights_within(uv, args.column_radius_m), args.ground_layer_m)
        body = columns.heights_within(uv, footprint_m) - (g if g is not None else h)
        if g is not None:
            grounds.append(g)
        looking += 1 if body.size else 0
        if np.count_nonzero((body > obstacle_above_m) & (body <= clearance_m)) >= args.min_obstacle_points:
            seeing += 1
    if not grounds:
        return None, np.nan, seeing, looking
    return float(np.median(grounds)), float(np.ptp(grounds)), seeing, looking


def check_path(points_T, unknown_seg, clouds, args, robot):
    """Per-sample verdicts of one path (points in the truth frame, metres); a dict of results."""
    seg_len = np.linalg.norm(np.diff(points_T, axis=0), axis=1)
    total = float(seg_len.sum())
    samples, seg_of = [], []
    for k, length in enumerate(seg_len):
        n = max(1, int(np.ceil(length / args.spacing_m)))
        for t in (np.arange(n) + 0.5) / n:
            samples.append(points_T[k] + t * (points_T[k + 1] - points_T[k]))
            seg_of.append(k)
    seg_of = np.array(seg_of)
    weights = np.array([seg_len[k] / max(1, int(np.ceil(seg_len[k] / args.spacing_m))) for k in seg_of])
    min_seeing = args.min_obstacle_scans if len(clouds) > 1 else 1
    reasons, offsets = [], []
    for p in samples:
        g, _, seeing, looking = ground_and_obstacle(clouds, p, args, robot)
        h = p @ clouds[0].up
        if g is None:
            reasons.append("no LiDAR return"); offsets.append(np.nan)
        else:
            offsets.append(h - g)
            if h < g - args.ground_tol_m:
                reasons.append("below the LiDAR ground")
            elif h > g + args.ground_tol_m:
                reasons.append("above the LiDAR ground")
            else:
                reasons.append("")
        if seeing >= min_seeing and 2 * seeing >= looking and reasons[-1] in ("", "no LiDAR return"):
            reasons[-1] = "LiDAR obstacle in the footprint"
        elif seeing and reasons[-1] == "":
            reasons[-1] = "transient"  # seen by too few scans: moving, or a stray return
    reasons = np.array(reasons, dtype=object)
    unknown = unknown_seg[seg_of]
    out = {"length_m": total, "unknown_m": float(weights[unknown].sum()), "offsets": np.array(offsets)}
    absolute = np.abs(out["offsets"])
    for name, mask in (("measured", ~unknown), ("unknown", unknown)):
        values = absolute[mask & np.isfinite(absolute)]
        out[name + "_abs_offset"] = (float(np.median(values)), float(values.max())) if values.size else (np.nan, np.nan)
    out["by_reason"] = {}
    for reason in sorted(set(reasons) - {""}):
        mask = reasons == reason
        out["by_reason"][reason] = (float(weights[mask].sum()), float(weights[mask & unknown].sum()))
    failing = [i for i, r in enumerate(reasons) if r not in ("", "no LiDAR return", "transient")]
    if failing:
        i = failing[0]
        out["verdict"] = "invalid"
        where = samples[i]
        if not np.isfinite(offsets[i]):
            extra = ""
        elif reasons[i] == "LiDAR obstacle in the footprint":
            extra = f" (path {offsets[i]:+.2f} m from the ground)"
        else:
            extra = f" by {offsets[i]:+.2f} m"
        out["reason"] = (f"{reasons[i]}{extra} at {where[0]:.2f} {where[1]:.2f} {where[2]:.2f} "
                         f"({'unknown' if unknown[i] else 'measured'} face)")
    elif "no LiDAR return" in out["by_reason"]:
        out["verdict"] = "unchecked"
        out["reason"] = f"{out['by_reason']['no LiDAR return'][0]:.1f} m without LiDAR returns"
    else:
        out["verdict"] = "valid"
        out["reason"] = "-"
    return out


def load_kitti_scans(directory, poses, frames, ego_radius_m):
    """KITTI Velodyne scans `directory/velodyne/%06d.bin` of `frames`, each moved into the poses'
    frame by pose * Tr (calib.txt's Tr: velodyne -> cam0), as `terramesh eval --gt-lidar` does;
    returns within ego_radius_m of the sensor (horizontally) are dropped."""
    calib = {}
    with open(os.path.join(directory, "calib.txt")) as f:
        for line in f:
            if ":" in line:
                key, values = line.split(":", 1)
                calib[key.strip()] = np.array(values.split(), float)
    if "Tr" not in calib or calib["Tr"].size != 12:
        raise InputError(f"{directory}/calib.txt", "Tr", "expected a line 'Tr: ' with 12 numbers")
    tr = calib["Tr"].reshape(3, 4)
    scans = []
    for frame in frames:
        name = os.path.join(directory, "velodyne", f"{frame:06d}.bin")
        raw = np.fromfile(name, np.float32)
        if raw.size == 0 or raw.size % 4:
            raise InputError(name, "", "expected float32 x y z reflectance records")
        v = raw.reshape(-1, 4)[:, :3].astype(float)
        v = v[np.hypot(v[:, 0], v[:, 1]) >= ego_radius_m]  # the car itself; the ground there is unseen
        cam = v @ tr[:, :3].T + tr[:, 3]
        pose = poses[frame].reshape(3, 4)
        scans.append(cam @ pose[:, :3].T + pose[:, 3])
    return scans


def alignment_report(clouds, args, to_truth, trajectory, poses, frames):
    """Heights of camera centres above the LiDAR ground (KITTI: about 1.65 m)."""
    lines = []
    wide = argparse.Namespace(**{**vars(args), "column_radius_m": args.alignment_radius_m})
    def heights_above(centres):
        result = []
        for c in centres:
            g = ground_and_obstacle(clouds, c, wide, (0.0, 0.0, 0.0))[0]
            result.append(c @ clouds[0].up - g if g is not None else np.nan)
        return np.array(result)
    def describe(above):
        return (f"median {np.nanmedian(above):.3f} m, range {np.nanmin(above):.3f}-{np.nanmax(above):.3f} m "
                f"({np.isfinite(above).sum()} of {len(above)} with returns within {args.alignment_radius_m} m)")
    if poses is not None:
        above = heights_above(poses[frames].reshape(-1, 3, 4)[:, :, 3])
        lines.append(f"alignment: KITTI pose camera centres, frames {frames[0]}-{frames[-1]}, above the LiDAR ground: "
                     + describe(above))
    if trajectory is not None and len(trajectory):
        lines.append("alignment: the map's keyframe centres mapped into the truth frame, above the LiDAR ground: "
                     + describe(heights_above(to_truth(trajectory))) + " (KITTI camera height: 1.65 m)")
    return lines


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("map_dir")
    parser.add_argument("paths", nargs="+", help="path.csv files or the folders holding them")
    parser.add_argument("--lidar", help="a PLY point cloud in the truth frame (one cloud); a PLY with faces (a "
                        "synthetic scene's ground_truth.ply) is sampled at --mesh-density points per m^2")
    parser.add_argument("--mesh-density", type=float, default=200.0)
    parser.add_argument("--kitti-scans", help="a folder with velodyne/*.bin and calib.txt: each scan of --frames, "
                        "placed by --poses, is a cloud of its own (needs --poses)")
    parser.add_argument("--sim3", help="s, R, t lines: truth = s R map + t")
    parser.add_argument("--poses", help="KITTI poses (the truth frame): for --kitti-scans and the alignment check")
    parser.add_argument("--frames", default="1:10", help="FIRST:LAST frames of --kitti-scans and the alignment check")
    parser.add_argument("--spacing-m", type=float, default=0.1)
    parser.add_argument("--column-radius-m", type=float, default=0.4)
    parser.add_argument("--ground-tol-m", type=float, default=0.3)
    parser.add_argument("--footprint-radius-m", type=float,
                        help="instead of robot.yaml's footprint (e.g. its inscribed_radius_m, as the planner uses)")
    parser.add_argument("--ground-layer-m", type=float, default=0.3)
    parser.add_argument("--ground-spread-m", type=float, default=0.0,
                        help="raise the obstacle band's floor to this (a merged cloud whose scans disagree)")
    parser.add_argument("--min-obstacle-points", type=int, default=2)
    parser.add_argument("--ego-radius-m", type=float, default=3.0,
                        help="--kitti-scans: drop returns this close to the sensor (the car itself)")
    parser.add_argument("--min-obstacle-scans", type=int, default=2)
    parser.add_argument("--alignment-radius-m", type=float, default=1.0)
    parser.add_argument("--csv", help="write one row per path here")
    args = parser.parse_args(argv)
    if (args.lidar is None) == (args.kitti_scans is None):
        parser.error("give one of --lidar and --kitti-scans")
    if args.kitti_scans and not args.poses:
        parser.error("--kitti-scans needs --poses")
    try:
        frame = read_simple_yaml(os.path.join(args.map_dir, "map_frame.yaml"))
        robot = robot_limits(read_simple_yaml(os.path.join(args.map_dir, "robot.yaml")))
        if args.footprint_radius_m is not None:
            robot = (args.footprint_radius_m,) + robot[1:]
        mpu, up_map = float(frame["metres_per_unit"]), np.asarray(frame["up"], float)
        map_ply = read_ply(os.path.join(args.map_dir, "traversability.ply"))
        verts = np.stack([map_ply["vertex"][k] for k in "xyz"], axis=1).astype(float)
        tris = map_ply["face"]["vertex_indices"].astype(np.int64)
        face_unknown = map_ply["face"]["unknown"].astype(bool)
        if args.sim3:
            s, R, t = read_sim3(args.sim3)
            if abs(s - mpu) > 0.01 * mpu:
                print(f"warning: sim3 scale {s} differs from the map's metres_per_unit {mpu} by > 1 %", file=sys.stderr)
            to_truth = lambda p: (s * (R @ np.asarray(p, float).T)).T + t
            up_T = R @ up_map
        else:
            to_truth = lambda p: np.asarray(p, float) * mpu
            up_T = up_map
        poses, frames = None, []
        if args.poses:
            poses = np.loadtxt(args.poses, ndmin=2)
            first, last = (int(v) for v in args.frames.split(":"))
            frames = list(range(first, last + 1))
            if poses.shape[1] != 12 or last >= len(poses) or first < 0:
                raise InputError(args.poses, "", f"expected 12 numbers a line and frames {args.frames}")
        if args.kitti_scans:
            points = load_kitti_scans(args.kitti_scans, poses, frames, args.ego_radius_m)
        else:
            cloud = read_ply(args.lidar)
            points = np.stack([cloud["vertex"][k] for k in "xyz"], axis=1).astype(float)
            if "face" in cloud and len(cloud["face"]["vertex_indices"]):
                points = sample_mesh(points, cloud["face"]["vertex_indices"].astype(np.int64), args.mesh_density)
            points = [points]
        clouds = [Columns(p, up_T, max(0.2, args.column_radius_m)) for p in points]
        trajectory = None
        trajectory_csv = os.path.join(args.map_dir, "trajectory.csv")
        if os.path.exists(trajectory_csv):
            rows = np.loadtxt(trajectory_csv, delimiter=",", skiprows=1, ndmin=2)
            trajectory = rows[:, 2:5]
        for line in alignment_report(clouds, args, to_truth, trajectory, poses, frames):
            print(line)
        rows_out = ["path,verdict,length_m,unknown_m,checked_m,median_offset_m,reason,"
                    "fail_m,fail_unknown_m,no_lidar_m,measured_abs_offset_median_m,measured_abs_offset_max_m,"
                    "unknown_abs_offset_median_m,unknown_abs_offset_max_m"]
        print(f"robot: footprint radius {robot[0]:.2f} m, obstacle band ({max(robot[1], args.ground_spread_m):.2f}, "
              f"{robot[2]:.2f}] m above the ground ({len(clouds)} cloud(s)); column radius {args.column_radius_m} m, ground tolerance {args.ground_tol_m} m, samples "
              f"every {args.spacing_m} m")
        for given in args.paths:
            path = os.path.join(given, "path.csv") if os.path.isdir(given) else given
            states, faces = read_path_csv(path)
            if faces.min() < 0 or faces.max() >= len(tris):
                raise InputError(path, "face", f"index outside the map's {len(tris)} faces")
            seg_unknown = []
            for k in range(len(states) - 1):
                mid = 0.5 * (states[k] + states[k + 1])
                near = min((faces[k], faces[k + 1]),
                           key=lambda f: point_triangle_distance(mid, *verts[tris[f]]))
                seg_unknown.append(face_unknown[near])
            result = check_path(to_truth(states), np.array(seg_unknown, bool), clouds, args, robot)
            fails = [v for r, v in result["by_reason"].items() if r not in ("no LiDAR return", "transient")]
            fail_m, fail_unknown = sum(v[0] for v in fails), sum(v[1] for v in fails)
            no_lidar = result["by_reason"].get("no LiDAR return", (0.0, 0.0))[0]
            offsets = result["offsets"]
            median = float(np.nanmedian(offsets)) if np.isfinite(offsets).any() else float("nan")
            details = "; ".join(f"{r}: {v[0]:.1f} m ({v[1]:.1f} m over unknown)" for r, v in result["by_reason"].items())
            measured, over_unknown = result["measured_abs_offset"], result["unknown_abs_offset"]
            print(f"{path}: {result['verdict']}: {result['reason']} | length {result['length_m']:.2f} m, over unknown "
                  f"faces {result['unknown_m']:.2f} m; |height - LiDAR ground| median / max: measured faces "
                  f"{measured[0]:.2f} / {measured[1]:.2f} m, unknown faces {over_unknown[0]:.2f} / {over_unknown[1]:.2f} m"
                  + (f" | {details}" if details else ""))
            rows_out.append(f"{path},{result['verdict']},{result['length_m']:.3f},{result['unknown_m']:.3f},"
                            f"{result['length_m'] - no_lidar:.3f},{median:.3f},\"{result['reason']}\","
                            f"{fail_m:.3f},{fail_unknown:.3f},{no_lidar:.3f},{measured[0]:.3f},{measured[1]:.3f},"
                            f"{over_unknown[0]:.3f},{over_unknown[1]:.3f}")
        if args.csv:
            with open(args.csv + ".tmp", "w") as f:
                f.write("\n".join(rows_out) + "\n")
            os.replace(args.csv + ".tmp", args.csv)
    except (InputError, OSError, ValueError, KeyError) as error:
        print(f"check_paths_lidar: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
