#!/usr/bin/env python3
"""How much of the open ground the rays of a generated hazards stream cross just above it.

Usage: low_ray_coverage.py SCENE_DIR [LOW_M HIGH_M [CELL_M]]

SCENE_DIR is a `terramesh generate hazards` output: its stream.json (every keyframe's camera
centre and the points it observed) and hazards.csv (the hazards and their extents). The ground of
that scene is the plane z = 0 outside the hazards. Every ray, camera centre to observed point, is
followed over a horizontal grid of CELL_M cells (default 0.1 m) while it runs between LOW_M and
HIGH_M above that plane (default 0.18 and 0.30 m: above small_wheeled's step, below the shortest
rock's top). A cell such a ray passes over is space just above the ground that the rays saw free:
an obstacle taller than LOW_M standing there would have cut the ray. Prints, for open ground (z = 0
and farther than 0.5 m from every hazard's extent) within 3, 6 and 10 m of the cameras, the share
of its cells crossed; and for every rock, how many of its inner cells (0.05 m inside its extent) a
ray crossed. A rule "free only where low rays crossed" keeps free only the crossed share of open
ground; it tells a rock nobody measured from the ground around it only if that share is high and
the rock's cells are not crossed. python3 + numpy.
"""
import csv
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
from common import InputError, run_main  # noqa: E402

HAZARD_MARGIN_M = 0.5      # open ground lies this far from every hazard's extent
ROCK_INSET_M = 0.05        # a rock's inner cells lie this far inside its extent
STEP_ALONG_RAY_M = 0.05    # the ray is followed in steps this long, horizontally
DISTANCES_M = (3.0, 6.0, 10.0)


def read_rays(path):
    """Camera centres and observed points, one row per observation: an (N, 6) array."""
    try:
        with open(path, encoding="utf-8") as f:
            stream = json.load(f)
    except (OSError, ValueError) as e:
        raise InputError(path, "", f"expected a readable slam_data JSON stream ({e})") from e
    rows = []
    views = stream.get("views") if isinstance(stream, dict) else None
    if not isinstance(views, list) or not views:
        raise InputError(path, "views", "expected a non-empty list of keyframes")
    for k, view in enumerate(views):
        try:
            centre = [float(v) for v in view["extrinsic"]["center"]]
            for obs in view.get("observations", []):
                rows.append(centre + [float(v) for v in obs["X"]])
        except (KeyError, TypeError, ValueError) as e:
            raise InputError(path, f"views[{k}]", f"expected extrinsic.center and observations[].X ({e})") from e
    if not rows:
        raise InputError(path, "views", "expected observations")
    return np.array(rows, dtype=float), np.array([[float(v) for v in view["extrinsic"]["center"]] for view in views])


def read_hazards(path):
    """The hazards of hazards.csv: name, kind, centre (x, y) and extent (x, y) in metres."""
    out = []
    try:
        with open(path, encoding="utf-8", newline="") as f:
            for line, row in enumerate(csv.DictReader(f), start=2):
                try:
                    sx, sy = float(row["size_x_m"]), float(row["size_y_m"])
                    if row["kind"] == "plateau":  # its ramps run out on either side
                        sx += 2 * float(row["ramp_length_m"])
                        sy += 2 * float(row["ramp_length_m"])
                    out.append((row["name"], row["kind"], float(row["centre_x"]), float(row["centre_y"]), sx, sy,
                                float(row["height_m"])))
                except (KeyError, TypeError, ValueError) as e:
                    raise InputError(path, f"line {line}", f"expected the columns of terramesh generate ({e})") from e
    except OSError as e:
        raise InputError(path, "", f"expected a readable hazards.csv ({e})") from e
    return out


def crossed_cells(rays, low, high, cell):
    """The set of grid cells (i, j) some ray passes over while between low and high above z = 0."""
    cells = set()
    a, b = rays[:, :3], rays[:, 3:]
    dz = b[:, 2] - a[:, 2]
    for k in range(len(rays)):
        if max(a[k, 2], b[k, 2]) < low or min(a[k, 2], b[k, 2]) > high:
            continue
        if abs(dz[k]) < 1e-12:
            t0, t1 = 0.0, 1.0
        else:
            ta, tb = (low - a[k, 2]) / dz[k], (high - a[k, 2]) / dz[k]
            t0, t1 = max(0.0, min(ta, tb)), min(1.0, max(ta, tb))
        if t1 <= t0:
            continue
        horizontal = b[k, :2] - a[k, :2]
        steps = max(2, int(math.ceil(np.linalg.norm(horizontal) * (t1 - t0) / STEP_ALONG_RAY_M)) + 1)
        t = np.linspace(t0, t1, steps)
        points = a[k, :2] + t[:, None] * horizontal
        cells.update(map(tuple, np.floor(points / cell).astype(np.int64)))
    return cells


def main():
    args = sys.argv[1:]
    if len(args) not in (1, 3, 4):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    scene = args[0]
    try:
        low, high = (float(args[1]), float(args[2])) if len(args) >= 3 else (0.18, 0.30)
        cell = float(args[3]) if len(args) == 4 else 0.1
    except ValueError as e:
        raise InputError("arguments", "LOW_M HIGH_M CELL_M", f"expected numbers ({e})") from e
    if not (0 <= low < high) or not cell > 0:
        raise InputError("arguments", "LOW_M HIGH_M CELL_M", "expected 0 <= LOW_M < HIGH_M and CELL_M > 0")
    rays, cameras = read_rays(os.path.join(scene, "stream.json"))
    hazards = read_hazards(os.path.join(scene, "hazards.csv"))
    cells = crossed_cells(rays, low, high, cell)

    def near_hazard(x, y):
        return any(abs(x - cx) <= sx / 2 + HAZARD_MARGIN_M and abs(y - cy) <= sy / 2 + HAZARD_MARGIN_M
                   for _, _, cx, cy, sx, sy, _ in hazards)

    def camera_distance(x, y):
        return float(np.min(np.hypot(cameras[:, 0] - x, cameras[:, 1] - y)))

    print(f"rays {len(rays)}")
    print(f"band_m {low} {high}")
    print(f"cell_m {cell}")
    lo = np.floor((cameras[:, :2].min(0) - max(DISTANCES_M)) / cell).astype(int)
    hi = np.ceil((cameras[:, :2].max(0) + max(DISTANCES_M)) / cell).astype(int)
    totals = {d: [0, 0] for d in DISTANCES_M}
    for i in range(lo[0], hi[0] + 1):
        for j in range(lo[1], hi[1] + 1):
            x, y = (i + 0.5) * cell, (j + 0.5) * cell
            d = camera_distance(x, y)
            if d > max(DISTANCES_M) or near_hazard(x, y):
                continue
            crossed = (i, j) in cells
            for limit in DISTANCES_M:
                if d <= limit:
                    totals[limit][0] += 1
                    totals[limit][1] += crossed
    for limit in DISTANCES_M:
        n, c = totals[limit]
        print(f"open_ground_within_{limit:g}_m_crossed_fraction {c / n if n else float('nan'):.4f} (of {n} cells)")
    for name, kind, cx, cy, sx, sy, height in hazards:
        if kind != "rock":
            continue
        columns = range(int(math.floor((cx - sx / 2) / cell)), int(math.floor((cx + sx / 2) / cell)) + 1)
        rows = range(int(math.floor((cy - sy / 2) / cell)), int(math.floor((cy + sy / 2) / cell)) + 1)
        inner = [(i, j) for i in columns for j in rows
                 if abs((i + 0.5) * cell - cx) < sx / 2 - ROCK_INSET_M
                 and abs((j + 0.5) * cell - cy) < sy / 2 - ROCK_INSET_M]
        crossed = sum(c in cells for c in inner)
        print(f"{name} height_m {height:.2f} camera_distance_m {camera_distance(cx, cy):.1f} "
              f"inner_cells {len(inner)} crossed {crossed}")
    return 0


if __name__ == "__main__":
    run_main(main)
