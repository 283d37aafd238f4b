#!/usr/bin/python3
"""Figures of a `terramesh compare` folder (docs/comparison.md).

Inputs (OUT is the folder):
  OUT/compare.csv        one row per map: map, slug, built, build_s, to_surface_s,
                         accuracy_median_m, completeness_median_m, ... (see docs/comparison.md)
  OUT/topview/SLUG.csv   per map, its upward-facing faces in the plan frame (metres):
                         x0,y0,x1,y1,x2,y2,height,class; class 0 free, 1 lethal, 2 unknown (with a
                         robot), 3 measured, 4 Steiner / unsupported (without one)
Outputs:
  OUT/accuracy_vs_build_time.png  accuracy and completeness medians against build time, one
                                  marker per map (log time axis)
  OUT/top_views.png               a top view of every map: with a robot coloured free / lethal /
                                  unknown, otherwise by height with unsupported faces grey
Exit codes: 0 done, 2 missing or malformed input (message on stderr).

  /usr/bin/python3 scripts/figures/compare_figures.py out/compare/street
"""

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import numpy as np  # noqa: E402

CLASS_RGBA = {0: (0.15, 0.65, 0.2, 1.0), 1: (0.85, 0.0, 0.0, 1.0), 2: (0.62, 0.62, 0.62, 1.0),
              4: (0.62, 0.62, 0.62, 1.0)}
MARKERS = {"mesh": "o", "voxels": "s", "points": "^"}


def read_top_view(path):
    """Triangles (N x 3 x 2), heights (N) and classes (N) of one top-view CSV."""
    common.require_file(path)
    with open(path, encoding="utf-8") as handle:
        header = handle.readline().strip()
    if header != "x0,y0,x1,y1,x2,y2,height,class":
        raise common.InputError(path, "line 1", "expected the header x0,y0,x1,y1,x2,y2,height,class")
    try:
        values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except ValueError as error:
        raise common.InputError(path, "", f"expected 8 numbers per line ({error})") from None
    if values.size == 0:
        return np.zeros((0, 3, 2)), np.zeros(0), np.zeros(0, dtype=int)
    if values.shape[1] != 8:
        raise common.InputError(path, "", f"expected 8 columns, found {values.shape[1]}")
    return values[:, :6].reshape(-1, 3, 2), values[:, 6], values[:, 7].astype(int)


def accuracy_figure(plt, rows, path):
    figure, axes = plt.subplots(1, 2, figsize=common.FIGURE_SIZE_IN, dpi=common.FIGURE_DPI)
    for axis, column, title in ((axes[0], "accuracy_median_m", "accuracy: median distance to the truth (m)"),
                                (axes[1], "completeness_median_m", "completeness: median distance from the truth (m)")):
        for row in rows:
            if row["built"] != "1":
                continue
            seconds = float(row["build_s"]) + float(row["to_surface_s"])
            value = float(row[column])
            if math.isnan(value):
                continue
            axis.scatter([max(seconds, 1e-3)], [value], marker=MARKERS.get(row["kind"], "o"), s=60)
            axis.annotate(row["map"], (max(seconds, 1e-3), value), textcoords="offset points", xytext=(5, 4), fontsize=8)
        axis.set_xscale("log")
        axis.set_xlabel("build time (s, log scale)")
        axis.set_title(title, fontsize=10)
        axis.grid(True, alpha=0.3)
    figure.suptitle("lower is better; circles: mesher, squares: OctoMap, triangles: PCL")
    figure.tight_layout()
    common.save_png(figure, path)


def top_views_figure(plt, rows, folder, path):
    from matplotlib.collections import PolyCollection
    shown = [row for row in rows if row["built"] == "1" and os.path.isfile(os.path.join(folder, "topview", row["slug"] + ".csv"))]
    if not shown:
        raise common.InputError(os.path.join(folder, "topview"), "", "no top view of a built map")
    columns = 3
    lines = (len(shown) + columns - 1) // columns
    figure, axes = plt.subplots(lines, columns, figsize=(15.0, 4.0 * lines), dpi=common.FIGURE_DPI, squeeze=False)
    for axis in axes.flat:
        axis.set_axis_off()
    for axis, row in zip(axes.flat, shown):
        triangles, heights, classes = read_top_view(os.path.join(folder, "topview", row["slug"] + ".csv"))
        axis.set_axis_on()
        axis.set_title(row["map"], fontsize=10)
        axis.set_aspect("equal")
        if len(triangles) == 0:
            continue
        order = np.argsort(heights)  # upper faces drawn over lower ones
        triangles, heights, classes = triangles[order], heights[order], classes[order]
        if np.any(classes <= 2):
            colours = [CLASS_RGBA.get(c, CLASS_RGBA[2]) for c in classes]
        else:
            lo, hi = np.percentile(heights, [2, 98])
            scaled = np.clip((heights - lo) / max(hi - lo, 1e-9), 0, 1)
            colours = plt.get_cmap("viridis")(scaled)
            colours[classes == 4] = CLASS_RGBA[4]
        axis.add_collection(PolyCollection(triangles, facecolors=colours, edgecolors="none"))
        axis.set_xlim(triangles[:, :, 0].min(), triangles[:, :, 0].max())
        axis.set_ylim(triangles[:, :, 1].min(), triangles[:, :, 1].max())
        axis.tick_params(labelsize=7)
    figure.suptitle("upward-facing faces from above (plan metres); green free, red lethal, grey unknown "
                    "(without a robot: height, grey unsupported)")
    figure.tight_layout()
    common.save_png(figure, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder", help="a terramesh compare output folder")
    args = parser.parse_args()
    csv_path = os.path.join(args.folder, "compare.csv")
    common.require_file(csv_path)
    rows = common.read_csv(csv_path, ["map", "slug", "kind", "built", "build_s", "to_surface_s",
                                      "accuracy_median_m", "completeness_median_m"])
    plt = common.pyplot()
    accuracy_figure(plt, rows, os.path.join(args.folder, "accuracy_vs_build_time.png"))
    top_views_figure(plt, rows, args.folder, os.path.join(args.folder, "top_views.png"))
    return common.EXIT_OK


if __name__ == "__main__":
    common.run_main(main)
