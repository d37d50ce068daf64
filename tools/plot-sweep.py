#!/usr/bin/env python3
"""Plots a sweep's results.csv: a metric against a varied parameter, one line per value of
another, passing variants as filled dots and failing ones hollow (errors left out).

  tools/plot-sweep.py RESULTS.csv --x aisle --y capacity --group rows --out plot.png [--title T]

Needs python3-matplotlib (Debian; tools/setup.sh installs it).
"""
import argparse
import csv
import os
import sys
from collections import defaultdict

try:
    import matplotlib
except ImportError:
    # tools/setup.sh installs Debian's python3-matplotlib, for Debian's /usr/bin/python3. Another
    # python3 first on PATH (pyenv, a venv) lacks it: run again with Debian's, once.
    debian = "/usr/bin/python3"
    if os.path.realpath(sys.executable) != os.path.realpath(debian) and os.path.exists(debian) and \
            not os.environ.get("SSCS_PLOT_REEXEC"):
        os.environ["SSCS_PLOT_REEXEC"] = "1"
        os.execv(debian, [debian] + sys.argv)
    sys.exit(f"plot-sweep.py: matplotlib is not installed for {sys.executable}: run tools/setup.sh (it installs "
             f"Debian's python3-matplotlib for /usr/bin/python3), or pip install matplotlib for this interpreter")

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results")
    ap.add_argument("--x", required=True, help="a varied parameter (x axis)")
    ap.add_argument("--y", required=True, help="a metric or column (y axis)")
    ap.add_argument("--group", help="a second varied parameter: one line per value")
    ap.add_argument("--out", required=True, help="the PNG to write")
    ap.add_argument("--title")
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.results, newline="")))
    for col in [a.x, a.y] + ([a.group] if a.group else []):
        if rows and col not in rows[0]:
            sys.exit(f"plot-sweep: {a.results} has no column '{col}'; its columns: {', '.join(rows[0])}")
    lines = defaultdict(list)
    for r in rows:
        if r["status"] == "error" or r[a.y] == "":
            continue
        lines[r[a.group] if a.group else ""].append((float(r[a.x]), float(r[a.y]), r["status"] == "pass"))
    fig, ax = plt.subplots(figsize=(8, 5), dpi=100)
    for (name, points), color in zip(sorted(lines.items(), key=lambda kv: float(kv[0]) if kv[0] else 0),
                                     plt.rcParams["axes.prop_cycle"].by_key()["color"] * 10):
        points.sort()
        xs, ys, ok = zip(*points)
        label = f"{a.group} = {name}" if a.group else None
        ax.plot(xs, ys, "-", color=color, alpha=0.5, label=label)
        ax.scatter([x for x, _, p in points if p], [y for _, y, p in points if p], color=color, zorder=3)
        ax.scatter([x for x, _, p in points if not p], [y for _, y, p in points if not p], facecolors="white",
                   edgecolors=color, zorder=3)
    ax.set_xlabel(a.x)
    ax.set_ylabel(a.y)
    ax.set_title(a.title or f"{a.y} against {a.x} (filled: every constraint passes; hollow: some fail)")
    ax.grid(True, alpha=0.3)
    if a.group:
        ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(a.out)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
