#!/usr/bin/env python3
"""How the classes of one map's faces changed between two runs of the same stream.

Usage: class_changes.py BEFORE_DIR AFTER_DIR

Both directories are `terramesh mesh --robot` (or `traverse`) outputs of the same input, so their
traversability.ply hold the same faces in the same order; anything else (other vertices or faces)
is an input error. Prints the number of faces, the faces whose class (free, lethal, unknown,
uncertain) changed, one line per change (before -> after: count, area in m^2 with map_frame.yaml's
metres_per_unit, how many of them are driven), and how many faces' contact
layer changed. Exit 0 either way (a diagnostic, not a check). python3 + numpy.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
import ply  # noqa: E402
from common import InputError, run_main  # noqa: E402
from traversability_figures import read_frame  # noqa: E402

CLASSES = ("free", "lethal", "unknown", "uncertain")
DRIVEN = 1


def read_map(map_dir):
    """(vertices, faces, face element, metres per unit) of MAP_DIR/traversability.ply."""
    path = os.path.join(map_dir, "traversability.ply")
    elements = ply.read(path)
    for name in ("vertex", "face"):
        if name not in elements:
            raise InputError(path, "header", f"expected a '{name}' element")
    vertex, face = elements["vertex"], elements["face"]
    for layer in ("lethal", "unknown", "uncertain", "contact", "evidence"):
        if layer not in face:
            raise InputError(path, "face", f"expected a '{layer}' property (a traversability map)")
    scale = read_frame(os.path.join(map_dir, "map_frame.yaml"))[3]
    vertices = np.stack([vertex["x"], vertex["y"], vertex["z"]], 1).astype(float)
    return vertices, np.asarray(face["vertex_indices"]), face, scale


def classes(face):
    """Per face: 0 free, 1 lethal, 2 unknown, 3 uncertain (lethal first, as the map decides)."""
    return np.where(face["lethal"] > 0, 1, np.where(face["unknown"] > 0, 2, np.where(face["uncertain"] > 0, 3, 0)))


def main():
    if len(sys.argv) != 3:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    before_dir, after_dir = sys.argv[1], sys.argv[2]
    vertices, faces, before, scale = read_map(before_dir)
    vertices_after, faces_after, after, _ = read_map(after_dir)
    after_path = os.path.join(after_dir, "traversability.ply")
    if faces.shape != faces_after.shape or not np.array_equal(faces, faces_after):
        raise InputError(after_path, "face", f"expected the same faces as {before_dir} (another mesh)")
    if vertices.shape != vertices_after.shape or not np.array_equal(vertices, vertices_after):
        raise InputError(after_path, "vertex", f"expected the same vertices as {before_dir} (another mesh)")
    triangles = vertices[faces] * scale
    area = 0.5 * np.linalg.norm(np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]), axis=1)
    was, now = classes(before), classes(after)
    changed = was != now
    print(f"faces {len(faces)}, class changed {int(changed.sum())}")
    for a in range(len(CLASSES)):
        for b in range(len(CLASSES)):
            pick = changed & (was == a) & (now == b)
            if pick.any():
                driven = int((pick & (after["evidence"] == DRIVEN)).sum())
                print(f"  {CLASSES[a]} -> {CLASSES[b]}: {int(pick.sum())} faces, {area[pick].sum():.2f} m^2, "
                      f"{driven} driven")
    contact = before["contact"] != after["contact"]
    print(f"contact changed on {int(contact.sum())} faces")
    return 0


if __name__ == "__main__":
    run_main(main)
