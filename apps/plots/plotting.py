# SPDX-License-Identifier: MIT
"""What the figure scripts share: reading a benchmark CSV, a palette that pairs 10 colours with
markers (so 40 series stay apart), log axes with readable ticks, and writing the PNG."""
import csv
import itertools
import os
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files only: the benches run headless
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = plt.get_cmap("tab10").colors
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")


def style(i):
    """Colour and marker of series i: every colour with the first marker, then the second, ..."""
    return COLOURS[i % len(COLOURS)], MARKERS[(i // len(COLOURS)) % len(MARKERS)]


def read_rows(path):
    """The CSV's rows as dicts; numbers as floats where they parse."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        for key, value in row.items():
            try:
                row[key] = float(value)
            except (TypeError, ValueError):
                pass
    if not rows:
        sys.exit(f"{path}: no rows to plot")
    return rows


def groups(rows, *keys):
    """Rows grouped by the values of `keys`, in order of first appearance."""
    key = lambda r: tuple(r[k] for k in keys)  # noqa: E731
    order = list(dict.fromkeys(key(r) for r in rows))
    return [(k, [r for r in rows if key(r) == k]) for k in order]


def pareto(points, better_x=min, better_y=max):
    """The points no other point beats in both coordinates, by increasing x."""
    front = []
    for p in points:
        dominated = any(q != p and better_x(q[0], p[0]) == q[0] and better_y(q[1], p[1]) == q[1] and
                        (q[0] != p[0] or q[1] != p[1]) for q in points)
        if not dominated:
            front.append(p)
    return sorted(set(front))


def save(figure, path):
    """Writes the figure beside `path` and renames it there: no partial PNG, even when killed."""
    path = pathlib.Path(path)
    partial = path.with_name(path.name + ".partial.png")
    figure.savefig(partial, dpi=110)
    plt.close(figure)
    os.replace(partial, path)
    print(f"plotted {path}")


def arguments(usage):
    """(csv path, png path) from the command line, or the usage and exit status 2."""
    if len(sys.argv) != 3:
        sys.exit(f"usage: {usage}")
    return pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])


__all__ = ["plt", "style", "read_rows", "groups", "pareto", "save", "arguments", "itertools"]
