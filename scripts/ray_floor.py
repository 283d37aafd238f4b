#!/usr/bin/python3
"""How low the camera rays of a stream pass over a map's free ground: the evidence free space gives
against a low obstacle between sparse points (docs/results/traversability.md, hazards seed 2's rock).

  scripts/ray_floor.py STREAM MAP_DIR [--point X Y R] [--faces N] [--lateral-m W] [--seed S]

A ray is the segment from a keyframe's camera centre to a point it observes (the point's last
estimate). With --point: the rays passing over the disc of radius R around (X, Y), and the lowest
height (z, map frame) each reaches over it. Always: over N free faces of MAP_DIR/traversability.ply
no steeper than 5 degrees, drawn at random, the lowest ray passing within W sideways above each of
three interior points of the face (barycentric (1,1,2)/4 and its turns), and per face the worst
(highest) of the three; printed as quantiles and as the share of faces whose worst point has no
ray below 0.15, 0.2 and 0.3 m. Assumes z is up (synthetic streams). Needs numpy.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from traversability_false_positives import read_ply  # noqa: E402


def read_rays(path):
    """Camera centres and observed points, one row per observation (points at their last estimate)."""
    centres, ids, points = [], [], {}
    with open(path) as f:
        lines = iter(f)
        for line in lines:
            words = line.split()
            if not words or words[0] != "keyframe":
                continue
            centre = [float(v) for v in words[2:5]]
            for _ in range(int(words[9])):
                obs = next(lines).split()
                points[int(obs[0])] = [float(v) for v in obs[1:4]]
                centres.append(centre)
                ids.append(int(obs[0]))
    return np.array(centres), np.array([points[i] for i in ids])


def lowest_over(samples, centres, ends, lateral):
    """Per sample (x, y, z): the lowest height above it of a ray passing within `lateral` sideways."""
    d = ends - centres
    length = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9)
    u = d[:, :2] / length[:, None]
    out = []
    for s in samples:
        rel = s[:2] - centres[:, :2]
        t = (rel * u).sum(1)
        side = np.abs(rel[:, 0] * u[:, 1] - rel[:, 1] * u[:, 0])
        h = centres[:, 2] + t * d[:, 2] / length - s[2]
        ok = (t > 0) & (t < length) & (side < lateral) & (h > -0.05)
        out.append(h[ok].min() if ok.any() else np.inf)
    return np.array(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("stream")
    parser.add_argument("map_dir")
    parser.add_argument("--point", nargs=3, type=float, metavar=("X", "Y", "R"))
    parser.add_argument("--faces", type=int, default=300)
    parser.add_argument("--lateral-m", type=float, default=0.1)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    centres, ends = read_rays(args.stream)
    if args.point:
        x, y, r = args.point
        ts = np.linspace(0, 1, 2001)
        lowest = []
        for c, p in zip(centres, ends):
            xy = c[:2] + ts[:, None] * (p[:2] - c[:2])
            inside = np.hypot(xy[:, 0] - x, xy[:, 1] - y) < r
            if inside.any():
                lowest.append((c[2] + ts[inside] * (p[2] - c[2])).min())
        lowest = np.sort(lowest)
        print(f"rays over the disc: {len(lowest)}; lowest heights: {np.round(lowest[:10], 3).tolist()}")
    vertices, faces, props = read_ply(os.path.join(args.map_dir, "traversability.ply"))
    free = np.where((props["lethal"] == 0) & (props["unknown"] == 0) & (props["uncertain"] == 0) &
                    (props["slope_deg"] < 5))[0]
    if len(free) == 0:
        sys.exit(f"{args.map_dir}: no free face no steeper than 5 degrees")
    chosen = np.random.default_rng(args.seed).choice(free, min(args.faces, len(free)), replace=False)
    weights = np.array([[1, 1, 2], [1, 2, 1], [2, 1, 1]]) / 4.0
    worst = np.array([lowest_over(weights @ vertices[faces[f]], centres, ends, args.lateral_m).max() for f in chosen])
    finite = worst[np.isfinite(worst)]
    print(f"free faces sampled: {len(chosen)}; with an interior point no ray passes over: "
          f"{np.mean(~np.isfinite(worst)):.3f}")
    if len(finite):
        print("worst interior point's lowest ray, quantiles 0.5 0.8 0.9 0.95 (m):",
              np.round(np.quantile(finite, [0.5, 0.8, 0.9, 0.95]), 3).tolist())
    for limit in (0.15, 0.2, 0.3):
        print(f"share of faces whose worst point has no ray below {limit} m: {np.mean(worst > limit):.3f}")


if __name__ == "__main__":
    main()
