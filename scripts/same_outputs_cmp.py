#!/usr/bin/env python3
"""Compares two output trees of scripts/same_outputs.sh, file by file.

Usage: same_outputs_cmp.py BASE_DIR HEAD_DIR

Every file must exist in both trees and be identical byte for byte, except what no two runs share:
  - CSV files lose the columns that hold times or memory (names ending in _s or _ms, or naming
    time, rss or memory) before they are compared;
  - text files (.txt, .md, .log) lose the numbers on lines that state times or memory (seconds,
    ms, MiB, "time"), and the paths of the two trees (as given and absolute) are made the same;
  - HDF5 files (.h5) are compared by content (every group, dataset and attribute, with h5py), not
    by bytes: HDF5 stamps each object with the time it was written;
  - `plan --random-pairs` runs OMPL with a time limit beside the face-graph optimum: its pairs.csv
    loses the sampled planner's columns (status, length, cost) and its plan.txt the solved count;
    the pairs and the graph optimum are compared;
  - a few files only the compare command's measurements fill (its figures, OMPL's log) are listed
    as not compared.
Prints one line per differing or missing file and a summary; exit 0 when everything is the same.
"""
import csv
import io
import re
import sys
from pathlib import Path

TIMING_COLUMN = re.compile(r"(_s|_ms|_us|_mb|_mib|_gib)$|time|rss|memory|mib|_per_s$", re.IGNORECASE)
TIMING_LINE = re.compile(r"time|\bms\b|\d\s*s\b|seconds|MiB|GiB|memory|rss|per second|/s\b", re.IGNORECASE)
NUMBER = re.compile(r"[-+]?\d+(\.\d*)?([eE][-+]?\d+)?")
NOT_COMPARED = {"benchmark.log"}
# The compare command's report repeats compare.csv (compared without its times) with the times and
# memory in the same table rows.
NOT_COMPARED_PATHS = {"compare/report.md"}
NOT_COMPARED_SUFFIXES = {".png"}
NOT_COMPARED_DIRS = {"compare"}


# What a time-limited OMPL search decides (plan --random-pairs): not reproducible between runs.
SAMPLED_COLUMNS = {"pairs.csv": {"status", "length_m", "cost", "unknown_length_m"}}
SAMPLED_LINES = {"plan.txt": re.compile(r"^solved ")}


def csv_without_timings(text, name=""):
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return rows
    sampled = SAMPLED_COLUMNS.get(name, set())
    keep = [i for i, column in enumerate(rows[0]) if not TIMING_COLUMN.search(column) and column not in sampled]
    return [[row[i] for i in keep if i < len(row)] for row in rows]


def text_without_timings(text, roots, name=""):
    for root in roots:
        text = text.replace(root, "ROOT")
    lines = []
    sampled = SAMPLED_LINES.get(name)
    for line in text.splitlines():
        if sampled and sampled.match(line):
            continue
        lines.append(NUMBER.sub("N", line) if TIMING_LINE.search(line) else line)
    return lines


def h5_content(path):
    import h5py
    import numpy as np
    items = []
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            attributes = sorted((k, np.asarray(v).tobytes()) for k, v in obj.attrs.items())
            data = (obj.dtype.str, obj.shape, obj[()].tobytes()) if isinstance(obj, h5py.Dataset) else None
            items.append((name, attributes, data))
        visit("/", f)
        f.visititems(visit)
    return items


def same(base_file, head_file, base_roots, head_roots):
    a, b = base_file.read_bytes(), head_file.read_bytes()
    if a == b:
        return True
    suffix = base_file.suffix
    if suffix == ".h5":
        return h5_content(base_file) == h5_content(head_file)
    try:
        ta, tb = a.decode(), b.decode()
    except UnicodeDecodeError:
        return False
    if suffix == ".csv":
        return csv_without_timings(ta, base_file.name) == csv_without_timings(tb, base_file.name)
    if suffix in {".txt", ".md", ".log"}:
        return (text_without_timings(ta, base_roots, base_file.name) ==
                text_without_timings(tb, head_roots, base_file.name))
    return False


def measured_only(relative):
    """Files only measurements fill: OMPL's log, the compare command's figures of its timings."""
    return (relative.name in NOT_COMPARED or relative.as_posix() in NOT_COMPARED_PATHS or
            (relative.parts[0] in NOT_COMPARED_DIRS and relative.suffix in NOT_COMPARED_SUFFIXES))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    base, head = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve()
    # Longest first: the absolute path contains the relative one.
    base_roots = [str(base), sys.argv[1].rstrip("/")]
    head_roots = [str(head), sys.argv[2].rstrip("/")]
    files = sorted({p.relative_to(base) for p in base.rglob("*") if p.is_file()} |
                   {p.relative_to(head) for p in head.rglob("*") if p.is_file()})
    differ, skipped, compared = [], [], 0
    for relative in files:
        a, b = base / relative, head / relative
        if not a.exists() or not b.exists():
            differ.append(f"{relative}: only in {'head' if b.exists() else 'base'}")
            continue
        if measured_only(relative):
            skipped.append(str(relative))
            continue
        compared += 1
        if not same(a, b, base_roots, head_roots):
            differ.append(f"{relative}: differs")
    for line in differ:
        print(line)
    print(f"{compared} files compared, {len(differ)} differ or are missing; not compared (measurements): "
          f"{', '.join(skipped) if skipped else 'none'}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
