"""Shared helpers of the figure scripts: input errors (exit 2), CSV and pose reading, atomic PNGs.

Every script imports matplotlib through `pyplot()`, which selects the Agg backend (no display, no
network) before pyplot is loaded.
"""

import csv
import math
import os
import sys
import tempfile

EXIT_OK = 0
EXIT_INPUT_ERROR = 2

# Figure size in inches at FIGURE_DPI: 1200 x 700 pixels, the size of the figures in docs/images.
FIGURE_SIZE_IN = (12.0, 7.0)
FIGURE_DPI = 100


class InputError(Exception):
    """A missing or malformed input file: names the file, the line or field, and what was expected."""

    def __init__(self, path, where, expected):
        location = f"{path}: {where}: " if where else f"{path}: "
        super().__init__(location + expected)


def run_main(main):
    """Runs `main()`, mapping InputError to exit code 2 with the message on stderr."""
    try:
        sys.exit(main())
    except InputError as error:
        print(f"{os.path.basename(sys.argv[0])}: {error}", file=sys.stderr)
        sys.exit(EXIT_INPUT_ERROR)


def pyplot():
    """matplotlib.pyplot with the Agg backend; a clear message if matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        sys.exit(f"{os.path.basename(sys.argv[0])}: needs matplotlib and numpy (Debian: python3-matplotlib); "
                 "run the script with the system Python, /usr/bin/python3")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def require_file(path):
    """Raises InputError unless `path` is a readable regular file."""
    if not os.path.isfile(path):
        raise InputError(path, "", "no such file")
    if not os.access(path, os.R_OK):
        raise InputError(path, "", "cannot open file for reading")


def read_csv(path, required_columns):
    """Reads a CSV with a header line into a list of dicts (strings), checking `required_columns`.

    Raises InputError for a missing file, an empty file, missing columns or ragged rows.
    """
    require_file(path)
    with open(path, newline="", encoding="utf-8") as handle:
        reader = csv.reader(handle)
        try:
            header = next(reader)
        except StopIteration:
            raise InputError(path, "line 1", "expected a header line, found an empty file") from None
        except csv.Error as error:
            raise InputError(path, "line 1", f"malformed CSV ({error})") from None
        header = [name.strip() for name in header]
        missing = [name for name in required_columns if name not in header]
        if missing:
            raise InputError(path, "line 1", "missing column(s) " + ", ".join(missing) +
                             " (header: " + ",".join(header) + ")")
        rows = []
        try:
            for line_number, fields in enumerate(reader, start=2):
                if not fields or all(not field.strip() for field in fields):
                    continue
                if len(fields) != len(header):
                    raise InputError(path, f"line {line_number}",
                                     f"expected {len(header)} fields, found {len(fields)}")
                row = {name: value.strip() for name, value in zip(header, fields)}
                row["_line"] = line_number
                rows.append(row)
        except csv.Error as error:
            raise InputError(path, f"line {reader.line_num}", f"malformed CSV ({error})") from None
    return rows


def number(path, row, column, allow_empty=False):
    """The float in `row[column]`; an empty field is NaN if `allow_empty`. Raises InputError."""
    text = row[column]
    if text == "" and allow_empty:
        return math.nan
    try:
        return float(text)
    except ValueError:
        raise InputError(path, f"line {row['_line']}, column {column}",
                         f"expected a number, found \"{text}\"") from None


def read_kitti_positions(path):
    """Camera positions of a KITTI pose file (12 numbers per line, row-major [R|t] camera-to-world).

    Returns an (N, 3) numpy array. Blank lines and lines starting with # are skipped.
    """
    import numpy as np
    require_file(path)
    positions = []
    with open(path, encoding="utf-8") as handle:
        for line_number, line in enumerate(handle, start=1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            fields = text.split()
            if len(fields) != 12:
                raise InputError(path, f"line {line_number}",
                                 f"expected 12 numbers (a KITTI 3x4 pose), found {len(fields)} fields")
            try:
                values = [float(field) for field in fields]
            except ValueError:
                raise InputError(path, f"line {line_number}", "expected 12 numbers") from None
            positions.append((values[3], values[7], values[11]))
    if not positions:
        raise InputError(path, "", "no pose in the file")
    return np.array(positions, dtype=float)


def write_atomically(path, suffix, write):
    """Writes `path` atomically: `write(stream)` fills a temporary file in the same folder (binary),
    which gets mode 0644 (mkstemp's is 0600) and is then renamed over `path`."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=".tmp-", suffix=suffix, dir=folder)
    try:
        with os.fdopen(handle, "wb") as stream:
            write(stream)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.remove(temporary)
        raise
    return path


def save_png(figure, path):
    """Saves `figure` as a PNG at `path` atomically, mode 0644 (write_atomically)."""
    return write_atomically(path, ".png", lambda stream: figure.savefig(stream, format="png", dpi=FIGURE_DPI))
