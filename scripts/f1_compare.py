#!/usr/bin/env python3
"""Two runs of scripts/traversability_f1.sh side by side: precision, coverage and the swept strip.

Usage: f1_compare.py BEFORE_DIR AFTER_DIR [BEFORE_DIR2 AFTER_DIR2 ...]

Each pair of directories holds the reports `traversability_f1.sh` writes (TERRAMESH_F1_OUT):
SCENE_ROBOT.txt (`traverse-eval --gt-mesh`), SCENE_ROBOT_swept.txt (`--road-under-path`) and, for
KITTI 00, kitti00_ROBOT_lidar.txt. Prints one markdown row per scene and robot found in both
directories of a pair: precision of free and coverage, the swept strip's free share by pieces and
by ground (underfoot), before -> after; then, per robot, the lowest of each over the scenes, how
many scenes reach 0.99 underfoot, and the KITTI rows. Exit 2 on a missing directory or an
unreadable report.
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
from common import InputError, run_main  # noqa: E402

ROBOTS = ("car", "legged", "small_wheeled")
COLUMNS = (("precision", "precision", ""), ("coverage", "coverage", ""),
           ("swept free", "road_free_fraction", "_swept"), ("underfoot free", "road_underfoot_free_fraction", "_swept"))


def read_report(path):
    """`key value` lines of a traverse-eval report, values as floats where they parse."""
    values = {}
    try:
        with open(path) as report:
            for line in report:
                parts = line.split()
                if len(parts) < 2:
                    continue
                try:
                    values[parts[0]] = float(parts[1])
                except ValueError:
                    values[parts[0]] = parts[1]
    except OSError as error:
        raise InputError(path, "", f"cannot read ({error.strerror})")
    return values


def cells(directory):
    """(scene, robot) of every SCENE_ROBOT.txt with its _swept.txt beside it, in a stable order."""
    if not os.path.isdir(directory):
        raise InputError(directory, "", "not a directory (expected the output of traversability_f1.sh)")
    found = []
    for name in sorted(os.listdir(directory)):
        match = re.fullmatch(r"(.+)_(car|legged|small_wheeled)\.txt", name)
        if match and not name.startswith("kitti00_") and os.path.exists(
                os.path.join(directory, f"{match.group(1)}_{match.group(2)}_swept.txt")):
            found.append((match.group(1), match.group(2)))
    return found


def fmt(value):
    return f"{value:.4f}" if isinstance(value, float) else "n/a"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) < 2 or len(argv) % 2 != 0:
        raise InputError("f1_compare.py", "arguments", "BEFORE_DIR AFTER_DIR [BEFORE_DIR2 AFTER_DIR2 ...]")
    pairs = list(zip(argv[0::2], argv[1::2]))
    found = {d: cells(d) for d in argv}  # every directory checked before anything is printed
    print("| scene | robot | " + " | ".join(f"{title} before | after" for title, _, _ in COLUMNS) + " |")
    print("|---|---|" + "---|---|" * len(COLUMNS))
    lowest = {}
    reaching = {}
    for before_dir, after_dir in pairs:
        after_cells = set(found[after_dir])
        for scene, robot in found[before_dir]:
            if (scene, robot) not in after_cells:
                continue
            row = []
            for title, key, suffix in COLUMNS:
                pair = [read_report(os.path.join(d, f"{scene}_{robot}{suffix}.txt")).get(key)
                        for d in (before_dir, after_dir)]
                row += [fmt(pair[0]), fmt(pair[1])]
                for side, value in zip(("before", "after"), pair):
                    if isinstance(value, float):
                        slot = (robot, title, side)
                        lowest[slot] = min(lowest.get(slot, 1.0), value)
                        if title == "underfoot free":
                            reaching.setdefault((robot, side), [0, 0])
                            reaching[(robot, side)][0] += value >= 0.99
                            reaching[(robot, side)][1] += 1
            print(f"| {scene} | {robot} | " + " | ".join(row) + " |")
    print()
    print("| robot | " + " | ".join(f"lowest {title} before | after" for title, _, _ in COLUMNS) +
          " | scenes >= 0.99 underfoot before | after |")
    print("|---|" + "---|---|" * len(COLUMNS) + "---|---|")
    for robot in ROBOTS:
        if not any(key[0] == robot for key in lowest):
            continue
        row = [fmt(lowest.get((robot, title, side))) for title, _, _ in COLUMNS for side in ("before", "after")]
        row += [f"{reaching[(robot, side)][0]} of {reaching[(robot, side)][1]}" for side in ("before", "after")]
        print(f"| {robot} | " + " | ".join(row) + " |")
    kitti = [(robot, d) for robot in ROBOTS for d in pairs if all(
        os.path.exists(os.path.join(x, f"kitti00_{robot}_lidar.txt")) for x in d)]
    if kitti:
        print()
        print("| KITTI 00 against the LiDAR ground | free before | after | lethal before | after "
              "| uncertain before | after |")
        print("|---|---|---|---|---|---|---|")
        for robot, (before_dir, after_dir) in kitti:
            reports = [read_report(os.path.join(d, f"kitti00_{robot}_lidar.txt")) for d in (before_dir, after_dir)]
            keys = ("lidar_free_fraction", "lidar_lethal_fraction", "lidar_uncertain_fraction")
            row = [fmt(r.get(key)) for key in keys for r in reports]
            print(f"| {robot} | " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    run_main(main)
