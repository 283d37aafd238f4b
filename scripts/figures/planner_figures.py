#!/usr/bin/python3
"""Planner comparison bars (success, cost, time) from a planning results CSV.

Input CSV, one row per planning run (header line required, columns in any order, extra columns
ignored):
  planner        name of the planner or mode (text, non-empty), e.g. rrtstar, prm, graph
  query          id of the start/goal pair (text); rows with the same id ask the same question,
                 so planners are compared on the same queries; repeated (planner, query) rows
                 (several seeds) are all used
  success        1 if a path was found that reaches the goal, else 0 (true/false also accepted)
  cost           cost of the path under the planning objective (number); ignored and may be
                 empty or nan when success is 0
  time_s         wall-clock planning time, seconds (number >= 0)
  path_length_m  optional: length of the path, metres (ignored when success is 0)
Figures (default: plots/ next to the CSV):
  planner_comparison.png  per planner: success rate (% of runs); mean cost over the queries that
                          every planner solved at least once (a planner's cost on a query is the
                          mean of its successful runs), with the spread across those queries; the
                          same for path length when the column is there; median planning time
                          with the 25-75% range (log axis when times span more than 100x)
The pairs.csv files the project's planners write are read as they are (detected by header):
  `terramesh plan MAP --random-pairs N -o OUT`  (pair,...,status,length_m,cost,time_s,graph_cost,
                 graph_time_s): two planners per pair, "BIT* (OMPL)" and "graph A*"
  `planner_demo`  (pair,map,status,length_m,cost,time_s,...): one planner per map (mesh, mesh_graph,
                 octomap)
  a pair is solved when its status is "solved" (graph A*: when graph_cost is finite).
Exit codes: 0 done, 2 missing or malformed input (message on stderr).

  scripts/figures/planner_figures.py out/planning/planners.csv
  scripts/figures/planner_figures.py out/demo/plan_pairs/pairs.csv
"""

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import numpy as np  # noqa: E402

REQUIRED = ["planner", "query", "success", "cost", "time_s"]
TRUE = {"1", "true", "yes"}
FALSE = {"0", "false", "no"}
SIZE_IN = (12.0, 5.0)


def parse_args(argv):
    parser = argparse.ArgumentParser(
        description="Draws planner comparison bars (success rate, path cost, planning time) from a "
                    "CSV with columns planner,query,success,cost,time_s[,path_length_m]; see the "
                    "top of this script for the schema.",
        epilog="Exit codes: 0 done, 2 missing or malformed input.")
    parser.add_argument("csv", metavar="CSV", help="planning results, one row per run")
    parser.add_argument("-o", "--output-dir", metavar="OUT", help="where the PNG goes (default: CSV's folder/plots)")
    parser.add_argument("--title", metavar="TEXT", help="figure title (default: the CSV's name)")
    return parser.parse_args(argv)


PLAN_PAIRS = ["pair", "status", "length_m", "cost", "time_s", "graph_cost", "graph_time_s"]
DEMO_PAIRS = ["pair", "map", "status", "length_m", "cost", "time_s"]


def header_of(path):
    common.require_file(path)
    with open(path, newline="", encoding="utf-8") as handle:
        first = handle.readline()
    return [name.strip() for name in first.strip().split(",")]


def read_pairs(path, header):
    """The runs of a pairs.csv of `terramesh plan --random-pairs` or `planner_demo`, or None."""
    if all(name in header for name in DEMO_PAIRS):
        columns = [(lambda row: row["map"], "status", "cost", "time_s", "length_m")]
    elif all(name in header for name in PLAN_PAIRS):
        columns = [(lambda row: "BIT* (OMPL)", "status", "cost", "time_s", "length_m"),
                   (lambda row: "graph A*", None, "graph_cost", "graph_time_s", None)]
    else:
        return None
    rows = common.read_csv(path, ["pair", "cost", "time_s"])
    if not rows:
        raise common.InputError(path, "", "holds no pair (only a header)")
    runs = []
    for row in rows:
        for planner, status, cost_column, time_column, length_column in columns:
            cost = common.number(path, row, cost_column, allow_empty=True)
            success = row[status] == "solved" if status else math.isfinite(cost)
            time_s = common.number(path, row, time_column)
            if not (time_s >= 0 and math.isfinite(time_s)):
                raise common.InputError(path, f"line {row['_line']}, column {time_column}", "expected a finite number >= 0")
            if success and not math.isfinite(cost):
                raise common.InputError(path, f"line {row['_line']}, column {cost_column}",
                                        "expected a finite cost for a solved pair")
            length = common.number(path, row, length_column, allow_empty=True) if length_column and success else math.nan
            runs.append((planner(row), row["pair"], success, cost if success else math.nan, time_s, length))
    planners = {run[0] for run in runs}
    has_length = all(any(run[0] == planner and math.isfinite(run[5]) for run in runs) for planner in planners)
    return runs, has_length


def read_runs(path):
    """[(planner, query, success, cost, time_s, length_m)] in file order, validated."""
    pairs = read_pairs(path, header_of(path))
    if pairs is not None:
        return pairs
    rows = common.read_csv(path, REQUIRED)
    if not rows:
        raise common.InputError(path, "", "holds no run (only a header)")
    has_length = "path_length_m" in rows[0]
    runs = []
    for row in rows:
        where = f"line {row['_line']}"
        if not row["planner"]:
            raise common.InputError(path, where + ", column planner", "expected a planner name")
        flag = row["success"].lower()
        if flag not in TRUE | FALSE:
            raise common.InputError(path, where + ", column success", f"expected 1 or 0, found \"{row['success']}\"")
        success = flag in TRUE
        time_s = common.number(path, row, "time_s")
        if not (time_s >= 0 and math.isfinite(time_s)):
            raise common.InputError(path, where + ", column time_s", "expected a finite number >= 0")
        cost = common.number(path, row, "cost", allow_empty=True) if success else math.nan
        if success and not math.isfinite(cost):
            raise common.InputError(path, where + ", column cost", "expected a finite cost for a successful run")
        length = math.nan
        if has_length and success:
            length = common.number(path, row, "path_length_m", allow_empty=True)
        runs.append((row["planner"], row["query"], success, cost, time_s, length))
    return runs, has_length


def common_query_means(runs, planners, column):
    """{planner: [mean value per query]} over the queries every planner solved, and their count."""
    solved = {}
    for planner, query, success, cost, _, length in runs:
        if success:
            value = cost if column == "cost" else length
            solved.setdefault((planner, query), []).append(value)
    queries = sorted({query for _, query, *_ in runs})
    shared = [query for query in queries if all((planner, query) in solved for planner in planners)]
    means = {planner: [float(np.nanmean(solved[(planner, query)])) for query in shared] for planner in planners}
    return means, len(shared)


def bars(axes, planners, values, errors=None, text=None):
    positions = np.arange(len(planners))
    colours = [f"C{i % 10}" for i in range(len(planners))]
    axes.bar(positions, values, color=colours, yerr=errors, capsize=4 if errors is not None else 0)
    axes.set_xticks(positions)
    axes.set_xticklabels(planners, rotation=20, ha="right")
    axes.grid(True, axis="y", alpha=0.3)
    for x, value, label in zip(positions, values, text or [None] * len(planners)):
        if label is not None and math.isfinite(value):
            axes.annotate(label, (x, value), ha="center", va="bottom", fontsize=8,
                          xytext=(0, 2), textcoords="offset points")


def main(argv=None):
    args = parse_args(argv)
    runs, has_length = read_runs(args.csv)
    planners = list(dict.fromkeys(run[0] for run in runs))
    output_dir = args.output_dir or os.path.join(os.path.dirname(os.path.abspath(args.csv)), "plots")
    plt = common.pyplot()
    panels = 4 if has_length else 3
    figure, axes = plt.subplots(1, panels, figsize=SIZE_IN, dpi=common.FIGURE_DPI)

    rates, labels = [], []
    for planner in planners:
        mine = [run for run in runs if run[0] == planner]
        found = sum(run[2] for run in mine)
        rates.append(100.0 * found / len(mine))
        labels.append(f"{found}/{len(mine)}")
    bars(axes[0], planners, rates, text=labels)
    axes[0].set_ylim(0, 110)
    axes[0].set_ylabel("success (% of runs)")
    axes[0].set_title("Success rate")

    for panel, column, unit in [(axes[1], "cost", "path cost"), (axes[3] if has_length else None, "length", "path length (m)")]:
        if panel is None:
            continue
        means, shared = common_query_means(runs, planners, column)
        if shared == 0:
            panel.text(0.5, 0.5, "no query solved\nby every planner", ha="center", va="center", transform=panel.transAxes)
            panel.set_xticks([])
        else:
            values = [float(np.mean(means[planner])) for planner in planners]
            spread = [float(np.std(means[planner])) for planner in planners]
            bars(panel, planners, values, errors=spread, text=[f"{value:.3g}" for value in values])
            panel.set_ylim(bottom=0)
        panel.set_ylabel(f"mean {unit}")
        panel.set_xlabel(f"queries solved by every planner: {shared}; whiskers: std", fontsize=8)
        panel.set_title(unit.capitalize())

    medians, low, high = [], [], []
    for planner in planners:
        times = np.array([run[4] for run in runs if run[0] == planner])
        q25, q50, q75 = np.percentile(times, [25, 50, 75])
        medians.append(q50)
        low.append(q50 - q25)
        high.append(q75 - q50)
    bars(axes[2], planners, medians, errors=np.array([low, high]), text=[f"{m:.3g} s" for m in medians])
    positive = [m for m in medians if m > 0]
    if positive and max(positive) > 100 * min(positive):
        axes[2].set_yscale("log")
    axes[2].set_ylabel("planning time (s)")
    axes[2].set_xlabel("median; whiskers: 25-75%", fontsize=8)
    axes[2].set_title("Planning time")

    figure.suptitle(args.title or f"Planner comparison ({os.path.basename(args.csv)}, {len(runs)} runs)")
    figure.set_layout_engine("tight")
    written = common.save_png(figure, os.path.join(output_dir, "planner_comparison.png"))
    plt.close(figure)
    print(written)
    return common.EXIT_OK


if __name__ == "__main__":
    common.run_main(main)
