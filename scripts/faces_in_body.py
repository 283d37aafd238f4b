#!/usr/bin/env python3
"""What stands in the robot's body on one face of a traversability map: the faces a footprint meets.

Usage: faces_in_body.py MAP_DIR X Y

MAP_DIR is a `terramesh mesh --robot` output: traversability.ply (the faces and their layers),
trajectory.csv (the keyframes' camera centres), robot.yaml (the footprint, max_step_m and
min_clearance_m), map_frame.yaml (up, plan axes, metres per unit) and mesh.ply (its header's
frame.sensor_height_m). X Y are map-plane coordinates in metres, as the Nav2 maps and the figures
use them (plan_x . p, plan_y . p times metres_per_unit: for the generated scenes, the map frame's x
and y); the face whose centroid lies nearest that point is judged. Its footprint is centred on its centroid and,
for a rectangle, turned along the camera path's nearest segment (a driven face's drive heading),
and sampled on a 0.05 m grid. Prints that face's class, reasons and offset from the path (left of
the direction of travel is positive), then every other face whose surface over a sample lies
between max_step_m and min_clearance_m above the face's centroid (a horizontal plane: for level
faces): its evidence (measured, driven, interpolated), whether it touches a Steiner vertex, the
up component of its normal (negative: it faces down), its height range over those samples, their
offsets from the path, and its lowest height over the samples beyond the strip a drive along the
path swept (farther from the path than half the footprint's width, or its radius). A diagnostic
of which geometry makes a face uncertain or lethal, not the layers' own test (which clips faces to
the body exactly, with the face's reference plane, the strip rules over driven ground and the
obstacles' extension). python3 + numpy.
"""
import csv
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
import ply  # noqa: E402
from common import InputError, require_file, run_main  # noqa: E402
from traversability_figures import read_frame  # noqa: E402

GRID_M = 0.05
EVIDENCE = {0: "measured", 1: "driven", 2: "interpolated"}
REASONS = ("too_steep no_heading_fits low_clearance guessed_wall possible_step slope_may_exceed "
           "worst_case_relief possible_obstacle obstacle_extension unconfirmed_point "
           "unknown_low_clearance closing_geometry few_rays seen_from_behind").split()


def header_value(path, key):
    """The numbers of a `comment KEY VALUE...` line of the PLY header at `path` (None if absent)."""
    for text in ply.comments(path):
        fields = text.split()
        if fields and fields[0] == key:
            try:
                return [float(v) for v in fields[1:]]
            except ValueError:
                raise InputError(path, f"comment {key}", "expected numbers") from None
    return None


def read_profile(path):
    """(length, width) of a rectangle or (radius, None) of a disc, max_step_m, min_clearance_m."""
    require_file(path)
    text = open(path, encoding="utf-8").read()

    def number(key, default=None):
        match = re.search(rf"^\s*{key}:\s*([-+0-9.eE]+)", text, re.MULTILINE)
        if match:
            return float(match.group(1))
        if default is None:
            raise InputError(path, key, "expected a number")
        return default

    if re.search(r"^\s*radius_m:", text, re.MULTILINE):
        footprint = (number("radius_m"), None)
    else:
        footprint = (number("length_m"), number("width_m"))
    return footprint, number("max_step_m"), number("min_clearance_m")


def read_path(path):
    """Camera centres of trajectory.csv, (N, 3), map units."""
    require_file(path)
    rows = []
    with open(path, newline="", encoding="utf-8") as handle:
        reader = csv.DictReader(handle)
        for line, row in enumerate(reader, start=2):
            try:
                rows.append([float(row["x"]), float(row["y"]), float(row["z"])])
            except (KeyError, TypeError, ValueError):
                raise InputError(path, f"line {line}", "expected numbers in columns x, y, z") from None
    if len(rows) < 2:
        raise InputError(path, "", "expected at least two keyframes")
    return np.array(rows)


def samples(centre, heading, footprint):
    """Grid points of the footprint centred at `centre` (2-D), turned to `heading` (unit 2-D)."""
    side = np.array([-heading[1], heading[0]])
    length, width = footprint
    if width is None:
        half_a = half_b = length
    else:
        half_a, half_b = length / 2, width / 2
    a, b = np.meshgrid(np.arange(-half_a, half_a + 1e-9, GRID_M), np.arange(-half_b, half_b + 1e-9, GRID_M))
    a, b = a.ravel(), b.ravel()
    if width is None:
        keep = a * a + b * b <= length * length + 1e-12
        a, b = a[keep], b[keep]
    return centre + a[:, None] * heading + b[:, None] * side


def heights_over(triangle, points):
    """Height of `triangle` (3x3: plan x, plan y, height) over each 2-D point, NaN outside its projection."""
    a, b, c = triangle
    v0, v1 = b[:2] - a[:2], c[:2] - a[:2]
    det = v0[0] * v1[1] - v0[1] * v1[0]
    if abs(det) < 1e-12:
        return np.full(len(points), np.nan)
    w = points - a[:2]
    u = (w[:, 0] * v1[1] - w[:, 1] * v1[0]) / det
    v = (v0[0] * w[:, 1] - v0[1] * w[:, 0]) / det
    z = a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2])
    return np.where((u >= -1e-9) & (v >= -1e-9) & (u + v <= 1 + 1e-9), z, np.nan)


def face_class(face, i):
    if face["lethal"][i]:
        return "lethal"
    if face["unknown"][i]:
        return "unknown"
    return "uncertain" if face["uncertain"][i] else "free"


def main():
    if len(sys.argv) != 4:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    map_dir = sys.argv[1]
    try:
        point = np.array([float(sys.argv[2]), float(sys.argv[3])])
    except ValueError:
        raise InputError("X Y", "", "expected two numbers") from None
    layers_path = os.path.join(map_dir, "traversability.ply")
    mesh_path = os.path.join(map_dir, "mesh.ply")
    require_file(mesh_path)
    elements = ply.read(layers_path)
    vertex, face = elements["vertex"], elements["face"]
    up, plan_x, plan_y, scale = read_frame(os.path.join(map_dir, "map_frame.yaml"))
    sensor = header_value(mesh_path, "frame.sensor_height_m")
    footprint, max_step, clearance = read_profile(os.path.join(map_dir, "robot.yaml"))
    rotation = np.stack([plan_x, plan_y, up])  # map frame -> (plan x, plan y, height)
    vertices = np.stack([vertex["x"], vertex["y"], vertex["z"]], 1).astype(float)
    triangles = (vertices[np.asarray(face["vertex_indices"])] @ rotation.T) * scale
    path = (read_path(os.path.join(map_dir, "trajectory.csv")) @ rotation.T) * scale
    centroids = triangles.mean(1)
    target = int(np.argmin(np.linalg.norm(centroids[:, :2] - point, axis=1)))
    centre = centroids[target]

    # The path's nearest segment: its direction, and each point's offset to the left of it.
    starts, ends = path[:-1, :2], path[1:, :2]
    moving = np.linalg.norm(ends - starts, axis=1) > 1e-6  # keyframes that moved, horizontally
    if not moving.any():
        raise InputError(os.path.join(map_dir, "trajectory.csv"), "", "expected keyframes that move horizontally")
    starts, ends = starts[moving], ends[moving]
    chord = ends - starts
    length2 = np.maximum((chord * chord).sum(1), 1e-12)
    t = np.clip(((centre[:2] - starts) * chord).sum(1) / length2, 0, 1)
    nearest = int(np.argmin(np.linalg.norm(centre[:2] - (starts + t[:, None] * chord), axis=1)))
    heading = chord[nearest] / np.sqrt(length2[nearest])
    left = np.array([-heading[1], heading[0]])

    def offset(p):
        return (p - starts[nearest]) @ left

    names = [n for j, n in enumerate(REASONS) if int(face["reasons"][target]) >> j & 1]
    print(f"face {target}: centroid ({centre[0]:.2f}, {centre[1]:.2f}) m on the map plane, {centre[2]:.2f} m up, "
          f"{face_class(face, target)}, evidence {EVIDENCE.get(int(face['evidence'][target]), '?')}, "
          f"reasons {','.join(names) or '-'}, {offset(centre[:2]):+.2f} m from the path")
    shape = f"{footprint[0]} x {footprint[1]} m turned along the path" if footprint[1] else f"radius {footprint[0]} m"
    sensor_text = f", sensor {sensor[0]:.2f} m up" if sensor else ""
    print(f"footprint {shape}; body {max_step} to {clearance} m above the centroid{sensor_text}")
    grid = samples(centre[:2], heading, footprint)
    # The strip a drive along the path swept: half the footprint's width (a disc: its radius).
    half_strip = footprint[1] / 2 if footprint[1] else footprint[0]
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    reach = np.linalg.norm(grid - centre[:2], axis=1).max()
    # Faces whose centroid lies within 20 m beyond the footprint (a face spans less than that).
    near = np.where(np.linalg.norm(centroids[:, :2] - centre[:2], axis=1) <= reach + 20.0)[0]
    for i in near:
        if i == target:
            continue
        z = heights_over(triangles[i], grid) - centre[2]
        inside = (z > max_step) & (z <= clearance)
        if not inside.any():
            continue
        sides = offset(grid[inside])
        beyond = np.abs(sides) > half_strip
        lowest_beyond = f"{z[inside][beyond].min():.2f} m" if beyond.any() else "none"
        print(f"  face {i}: {EVIDENCE.get(int(face['evidence'][i]), '?')}, steiner {int(face['steiner'][i])}, "
              f"{face_class(face, i)}, normal up {normals[i, 2]:+.2f}, {z[inside].min():.2f}-{z[inside].max():.2f} m "
              f"up over {int(inside.sum())} samples, {sides.min():+.2f} to {sides.max():+.2f} m from the path; "
              f"lowest beyond the strip: {lowest_beyond}")
    return 0


if __name__ == "__main__":
    run_main(main)
