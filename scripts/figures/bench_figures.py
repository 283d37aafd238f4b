#!/usr/bin/python3
"""Figures of a `terramesh bench -o DIR` folder (like the paper's Figures 5 and 6).

Reads DIR/runs.csv (mode,stream,keyframes_csv,summary; one row per mode, in the order bench ran
them) and each run's keyframes.csv (the per-update CSV of docs/formats.md; only rows of kind
"keyframe" are plotted). Without runs.csv, every DIR/MODE/keyframes.csv is used, modes sorted by
name. Writes into OUT (default DIR/plots):
  time_per_keyframe.png  update time per keyframe of every mode, ms, log y
  steps_MODE.png         time per step (Steiner, shrink, insertion, ray tracing, grow) and total
                         per keyframe of one mode, ms
Exit codes: 0 done, 2 missing or malformed input (message on stderr).

  scripts/figures/bench_figures.py out/bench-kitti-like
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

STEPS = [("time_steiner_s", "Steiner"), ("time_shrink_s", "shrink"), ("time_insertion_s", "insertion"),
         ("time_ray_tracing_s", "ray tracing"), ("time_grow_s", "grow"), ("time_total_s", "total")]


def parse_args(argv):
    parser = argparse.ArgumentParser(
        description="Draws the timing figures of a `terramesh bench` output folder.",
        epilog="Exit codes: 0 done, 2 missing or malformed input.")
    parser.add_argument("bench_dir", metavar="DIR", help="the folder `terramesh bench -o DIR` wrote")
    parser.add_argument("-o", "--output-dir", metavar="OUT", help="where the PNGs go (default: DIR/plots)")
    parser.add_argument("--modes", metavar="LIST", help="comma-separated modes to draw (default: all runs)")
    parser.add_argument("--title", metavar="TEXT", help="name of the stream in the titles (default: from runs.csv)")
    return parser.parse_args(argv)


def list_runs(bench_dir):
    """[(mode, stream, keyframes_csv path)] from runs.csv, or found in the folder."""
    index = os.path.join(bench_dir, "runs.csv")
    if os.path.exists(index):
        rows = common.read_csv(index, ["mode", "stream", "keyframes_csv"])
        if not rows:
            raise common.InputError(index, "", "lists no run")
        return [(row["mode"], row["stream"], os.path.join(bench_dir, row["keyframes_csv"])) for row in rows]
    if not os.path.isdir(bench_dir):
        raise common.InputError(bench_dir, "", "no such folder (expected the output folder of terramesh bench)")
    runs = []
    for name in sorted(os.listdir(bench_dir)):
        path = os.path.join(bench_dir, name, "keyframes.csv")
        if os.path.isfile(path):
            runs.append((name, "", path))
    if not runs:
        raise common.InputError(bench_dir, "", "holds neither runs.csv nor any MODE/keyframes.csv")
    return runs


def read_keyframes(path):
    """{column: [values]} of the keyframe rows of a keyframes.csv, times in ms."""
    columns = [column for column, _ in STEPS]
    rows = common.read_csv(path, ["kind"] + columns)
    series = {column: [] for column in columns}
    for row in rows:
        if row["kind"] != "keyframe":
            continue
        for column in columns:
            series[column].append(1e3 * common.number(path, row, column))
    if not series["time_total_s"]:
        raise common.InputError(path, "", "holds no keyframe row")
    return series


def new_axes(plt, title, y_label):
    figure, axes = plt.subplots(figsize=common.FIGURE_SIZE_IN, dpi=common.FIGURE_DPI)
    axes.set_title(title)
    axes.set_xlabel("keyframe")
    axes.set_ylabel(y_label)
    axes.grid(True, which="major", alpha=0.3)
    axes.margins(x=0)
    figure.set_layout_engine("tight")
    return figure, axes


def main(argv=None):
    args = parse_args(argv)
    runs = list_runs(args.bench_dir)
    if args.modes:
        wanted = [mode for mode in args.modes.split(",") if mode]
        known = {mode for mode, _, _ in runs}
        unknown = [mode for mode in wanted if mode not in known]
        if unknown:
            raise common.InputError(args.bench_dir, "--modes", "no run of mode(s) " + ", ".join(unknown) +
                                    " (runs: " + ", ".join(sorted(known)) + ")")
        runs = [run for mode in wanted for run in runs if run[0] == mode]
    data = [(mode, read_keyframes(path)) for mode, _, path in runs]
    stream = args.title or os.path.basename(runs[0][1]) or os.path.basename(os.path.normpath(args.bench_dir))
    output_dir = args.output_dir or os.path.join(args.bench_dir, "plots")

    plt = common.pyplot()
    import matplotlib.ticker
    written = []
    figure, axes = new_axes(plt, f"Time per keyframe, all modes ({stream})", "update time (ms)")
    for mode, series in data:
        axes.plot(range(len(series["time_total_s"])), series["time_total_s"], linewidth=1.0, label=mode)
    axes.set_yscale("log")
    low, high = axes.get_ylim()
    subs = (1.0, 2.0, 5.0) if high < 1e3 * low else (1.0,)  # label 1-2-5 within three decades
    axes.yaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=subs))
    axes.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda value, _: f"{value:g}"))
    axes.grid(True, which="minor", alpha=0.12)
    axes.legend(loc="upper left")
    written.append(common.save_png(figure, os.path.join(output_dir, "time_per_keyframe.png")))
    plt.close(figure)

    for mode, series in data:
        figure, axes = new_axes(plt, f"Time per step and keyframe, {mode} ({stream})", "time (ms)")
        for column, label in STEPS:
            axes.plot(range(len(series[column])), series[column], linewidth=1.0, label=label)
        axes.set_ylim(bottom=0)
        axes.legend(loc="upper left")
        written.append(common.save_png(figure, os.path.join(output_dir, f"steps_{mode}.png")))
        plt.close(figure)
    for path in written:
        print(path)
    return common.EXIT_OK


if __name__ == "__main__":
    common.run_main(main)
