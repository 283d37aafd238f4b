#!/usr/bin/env python3
"""Prints how memory and time per keyframe behave over a drive meshed with the online freeze:
`terramesh mesh STREAM --robot R --freeze-radius-m M --memory-log -o OUT`, then
`scripts/freeze_report.py OUT [FROM_KEYFRAME] [--whole WHOLE]` (default 1000). Reads
OUT/memory.csv and OUT/tiles/plan.json. With `--whole WHOLE`, a run of the same stream without the
freeze, it also compares OUT/mesh.ply (the surface still active at the end) with WHOLE/mesh.ply:
how many of its faces the other has too (same three vertices), and how far the others lie from the
part of WHOLE's surface the freeze let go (the freeze boundary), in plan metres. Exit 2 naming the
file for a missing or malformed input. python3 + numpy.
"""
import json
import os
import statistics
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
import common  # noqa: E402
import ply  # noqa: E402

COLUMNS = ["keyframes", "elapsed_s", "rss_mib", "map_bytes"]


def machine():
    model, cores = "unknown CPU", 0
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name") and model == "unknown CPU":
                    model = line.split(":", 1)[1].strip()
                cores += line.startswith("processor")
    except OSError:
        pass
    return f"{model}, {cores} cores"


def read_memory(path):
    rows = common.read_csv(path, COLUMNS)
    out = []
    for line, row in enumerate(rows, start=2):
        try:
            out.append({key: float(row[key]) for key in COLUMNS})
        except ValueError:
            raise common.InputError(path, f"line {line}", "expected numbers in " + ", ".join(COLUMNS))
    if not out:
        raise common.InputError(path, "", "expected one row per keyframe (mesh --memory-log)")
    return out


def face_keys(path):
    """The faces of a mesh PLY as sorted vertex-position triples (micrometres), and their centroids."""
    elements = ply.read(path)
    if "vertex" not in elements or "face" not in elements:
        raise common.InputError(path, "header", "expected vertex and face elements")
    vertex = elements["vertex"]
    points = np.stack([vertex["x"], vertex["y"], vertex["z"]], axis=1)
    corners = points[np.asarray(elements["face"]["vertex_indices"])]
    keys = [tuple(sorted(map(tuple, np.round(triangle * 1e6).astype(np.int64)))) for triangle in corners]
    return keys, corners.mean(axis=1)


def compare_with_whole(out, whole):
    active, active_centres = face_keys(os.path.join(out, "mesh.ply"))
    other, other_centres = face_keys(os.path.join(whole, "mesh.ply"))
    other_set, active_set = set(other), set(active)
    differing = np.array([k not in other_set for k in active])
    frozen = other_centres[np.array([k not in active_set for k in other])]
    line = (f"active surface at the end: {len(active) - int(differing.sum())} of {len(active)} faces also in "
            f"{whole}/mesh.ply ({1 - differing.mean():.4f})")
    if differing.any() and len(frozen):
        distances = [np.min(np.hypot(*(frozen[:, :2] - c[:2]).T)) for c in active_centres[differing]]
        line += f"; the others lie at most {max(distances):.1f} m (plan) from the surface the freeze let go"
    print(line)


def main():
    args = sys.argv[1:]
    whole = None
    if "--whole" in args:
        at = args.index("--whole")
        if at + 1 >= len(args):
            raise common.InputError(sys.argv[0], "--whole", "expected a run folder")
        whole = args[at + 1]
        del args[at:at + 2]
    if len(args) not in (1, 2):
        raise common.InputError(sys.argv[0], "", "usage: freeze_report.py OUT [FROM_KEYFRAME] [--whole WHOLE]")
    out = args[0]
    start = int(args[1]) if len(args) == 2 else 1000
    rows = read_memory(os.path.join(out, "memory.csv"))
    plan_path = os.path.join(out, "tiles", "plan.json")
    try:
        with open(plan_path) as f:
            tiles = len(json.load(f)["tiles"])
    except (OSError, ValueError, KeyError):
        raise common.InputError(plan_path, "tiles", "expected the plan a run with --freeze-radius-m writes")
    total = len(rows)
    if total < start + 2:
        raise common.InputError(os.path.join(out, "memory.csv"), "", f"expected more than {start + 1} keyframes")
    steps = [1e3 * (b["elapsed_s"] - a["elapsed_s"]) for a, b in zip(rows, rows[1:])]
    window = min(1000, (total - start) // 2)
    first = statistics.median(steps[start - 1:start - 1 + window])
    last = statistics.median(steps[-window:])
    at = rows[start - 1]
    later = max(row["rss_mib"] for row in rows[start - 1:])
    later_map = max(row["map_bytes"] for row in rows[start - 1:])
    print(f"machine: {machine()}")
    print(f"drive: {total} keyframes, {tiles} tiles, {rows[-1]['elapsed_s']:.0f} s")
    print(f"resident memory: {at['rss_mib']:.0f} MiB at keyframe {start}, at most {later:.0f} MiB from there to "
          f"keyframe {total} (ratio {later / at['rss_mib']:.3f})")
    print(f"mesher map_bytes: {at['map_bytes'] / 2**20:.0f} MiB at keyframe {start}, at most "
          f"{later_map / 2**20:.0f} MiB after (ratio {later_map / at['map_bytes']:.3f})")
    print(f"time per keyframe (wall, median): {first:.1f} ms over keyframes {start}-{start + window - 1}, "
          f"{last:.1f} ms over the last {window} (ratio {last / first:.3f})")
    if whole:
        compare_with_whole(out, whole)
    return common.EXIT_OK


if __name__ == "__main__":
    common.run_main(main)
