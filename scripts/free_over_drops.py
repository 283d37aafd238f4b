#!/usr/bin/env python3
"""How much ground a traversability map calls free lies over a drop the robot cannot step down.

Usage: free_over_drops.py MAP_DIR GROUND_TRUTH.ply [MAX_STEP_M]

MAP_DIR is a `terramesh mesh --robot` (or `traverse`) output: its traversability.ply and, unless
MAX_STEP_M is given, its robot.yaml (`max_step_m`). GROUND_TRUTH.ply is the mesh of `terramesh
generate`, in the same frame (metres, z up). Every free face of the map is sampled on a
barycentric lattice at most 0.25 m apart; a sample lies over a drop when the truth surface
nearest beneath it (at most 5 cm above it: the truth at the face's level, or the next one down)
lies more than MAX_STEP_M lower, or when there is none. That is the mesh spanning a pit, a ditch
or a ledge with a lid at the rim's height: the map says level, the truth has a step down there.
Prints the free area, the area over a drop (each face weighted by its samples' share), and the
share. python3 + numpy.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
import ply  # noqa: E402
from common import InputError  # noqa: E402

SAMPLE_M = 0.25      # lattice spacing on each free face
ABOVE_M = 0.05       # a truth surface this far above the sample still counts as its level
BUCKET_M = 1.0       # horizontal grid of the truth faces


def fail(message):
    print(f"free_over_drops.py: {message}", file=sys.stderr)
    sys.exit(2)


def max_step_of(map_dir):
    path = os.path.join(map_dir, "robot.yaml")
    try:
        with open(path) as f:
            for number, line in enumerate(f, 1):
                key, _, value = line.partition(":")
                if key.strip() == "max_step_m":
                    try:
                        return float(value.split("#")[0])
                    except ValueError:
                        fail(f"{path}: line {number}: max_step_m must be a number, got {value.strip()!r}")
    except OSError as e:
        fail(f"{path}: {e.strerror} (give MAX_STEP_M, or a map directory with robot.yaml)")
    fail(f"{path}: no max_step_m (give MAX_STEP_M)")


def mesh_of(path):
    elements = ply.read(path)
    if "vertex" not in elements or "face" not in elements:
        raise InputError(path, "header", "expected vertex and face elements")
    v, f = elements["vertex"], elements["face"]
    points = np.stack([v["x"], v["y"], v["z"]], 1).astype(float)
    faces = np.asarray(f["vertex_indices"])
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise InputError(path, "element face", "expected triangles")
    return points, faces, f


class TruthHeights:
    """The heights of the truth's surfaces at a horizontal position, by a grid of its faces."""

    def __init__(self, points, faces):
        self.a, self.b, self.c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
        lo = np.minimum(np.minimum(self.a, self.b), self.c)[:, :2]
        hi = np.maximum(np.maximum(self.a, self.b), self.c)[:, :2]
        self.buckets = {}
        for i in range(len(faces)):
            for gx in range(math.floor(lo[i, 0] / BUCKET_M), math.floor(hi[i, 0] / BUCKET_M) + 1):
                for gy in range(math.floor(lo[i, 1] / BUCKET_M), math.floor(hi[i, 1] / BUCKET_M) + 1):
                    self.buckets.setdefault((gx, gy), []).append(i)

    def candidates(self, lo, hi):
        found = set()
        for gx in range(math.floor(lo[0] / BUCKET_M), math.floor(hi[0] / BUCKET_M) + 1):
            for gy in range(math.floor(lo[1] / BUCKET_M), math.floor(hi[1] / BUCKET_M) + 1):
                found.update(self.buckets.get((gx, gy), ()))
        return np.array(sorted(found), dtype=int)

    def heights(self, samples, candidates):
        """Per sample (rows of xy), per candidate face: its height there, NaN where it is not."""
        a, b, c = self.a[candidates], self.b[candidates], self.c[candidates]
        v0, v1 = (c - a)[:, :2], (b - a)[:, :2]
        d00, d01, d11 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v1 * v1).sum(1)
        den = d00 * d11 - d01 * d01
        ok = np.abs(den) > 1e-12
        den = np.where(ok, den, 1.0)
        v2 = samples[:, None, :] - a[None, :, :2]
        d20, d21 = (v2 * v0[None]).sum(2), (v2 * v1[None]).sum(2)
        u, w = (d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den
        inside = ok & (u >= -1e-9) & (w >= -1e-9) & (u + w <= 1 + 1e-9)
        z = a[None, :, 2] + u * (c - a)[None, :, 2] + w * (b - a)[None, :, 2]
        return np.where(inside, z, np.nan)


def lattice(tri):
    """Barycentric lattice points of a triangle, at most SAMPLE_M apart along its edges."""
    longest = max(np.linalg.norm(tri[i] - tri[(i + 1) % 3]) for i in range(3))
    n = max(1, math.ceil(longest / SAMPLE_M))
    weights = [(i / n, j / n) for i in range(n + 1) for j in range(n + 1 - i)]
    return np.array([tri[0] + s * (tri[1] - tri[0]) + t * (tri[2] - tri[0]) for s, t in weights])


def main(argv):
    if len(argv) not in (3, 4):
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    map_dir, truth_path = argv[1], argv[2]
    if len(argv) == 4:
        try:
            max_step = float(argv[3])
        except ValueError:
            fail(f"MAX_STEP_M must be a number, got {argv[3]!r}")
    else:
        max_step = max_step_of(map_dir)
    if not max_step >= 0:
        fail(f"MAX_STEP_M must be >= 0, got {max_step}")
    try:
        points, faces, props = mesh_of(os.path.join(map_dir, "traversability.ply"))
        truth_points, truth_faces, _ = mesh_of(truth_path)
        for name in ("lethal", "uncertain", "unknown"):
            if name not in props:
                raise InputError(os.path.join(map_dir, "traversability.ply"), "element face",
                                 f"expected the property {name}")
    except InputError as e:
        fail(str(e))
    free = (props["lethal"] == 0) & (props["uncertain"] == 0) & (props["unknown"] == 0)
    truth = TruthHeights(truth_points, truth_faces)
    free_m2 = over_m2 = 0.0
    for f in np.flatnonzero(free):
        tri = points[faces[f]]
        area = 0.5 * np.linalg.norm(np.cross(tri[1] - tri[0], tri[2] - tri[0]))
        samples = lattice(tri)
        candidates = truth.candidates(samples[:, :2].min(0), samples[:, :2].max(0))
        if len(candidates) == 0:
            over = np.ones(len(samples), dtype=bool)
        else:
            z = truth.heights(samples[:, :2], candidates)
            z = np.where(z <= samples[:, 2:3] + ABOVE_M, z, np.nan)
            beneath = np.where(np.isnan(z).all(1), -np.inf, np.nanmax(np.where(np.isnan(z), -np.inf, z), 1))
            over = samples[:, 2] - beneath > max_step
        free_m2 += area
        over_m2 += area * over.mean()
    share = over_m2 / free_m2 if free_m2 > 0 else 0.0
    print(f"free_m2 {free_m2:.2f}")
    print(f"free_over_drop_m2 {over_m2:.2f}")
    print(f"free_over_drop_fraction {share:.4f}")
    print(f"max_step_m {max_step}")


if __name__ == "__main__":
    main(sys.argv)
