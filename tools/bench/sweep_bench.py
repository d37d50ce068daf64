#!/usr/bin/env python3
"""Benchmark of issue 10: a 500-variant check sweep of the demo vault (20 aisle widths x 5 row
counts x 5 bay counts), as variants per second of `sscs sweep --jobs 1` and `--jobs 2`, side by
side with the shell loop a user would write without it: one `sscs check --set ...` process per
variant (run here on --loop variants drawn at random with a fixed seed; --loop 500 runs them all).

Targets: --jobs 2 >= 1.8x --jobs 1; --jobs 1 >= 5x the shell loop.
usage: sweep_bench.py [--build DIR] [--loop N] [--runs K]
"""
import argparse
import itertools
import os
import random
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
AISLES = [round(1.0 + 0.1 * i, 1) for i in range(20)]
ROWS = [2, 3, 4, 5, 6]
BAYS = [3, 4, 5, 6, 7]

SWEEP = f"""sscs: 1
sweep: bench
vault: {ROOT}/scenarios/demo/demo.yaml
vary:
  aisle: {{from: 1.0 m, to: 2.9 m, step: 0.1 m}}
  rows: {{values: {ROWS}}}
  bays: {{values: {BAYS}}}
metrics:
  racks: "count(type:rack)"
  min_margin: "min_margin()"
"""


def timed(cmd, ok=(0, 1), **kw):
    start = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode not in ok:
        sys.exit(f"{' '.join(cmd)} exited {p.returncode}: {p.stderr[-2000:]}")
    return time.perf_counter() - start


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--loop", type=int, default=100, help="variants the shell loop runs (its rate is what is compared)")
    ap.add_argument("--runs", type=int, default=1, help="best of K runs of each sweep")
    a = ap.parse_args()
    sscs = os.path.join(a.build, "src", "sscs")
    variants = list(itertools.product(AISLES, ROWS, BAYS))
    assert len(variants) == 500
    with tempfile.TemporaryDirectory() as tmp:
        sweep = os.path.join(tmp, "bench.yaml")
        open(sweep, "w").write(SWEEP)
        rates = {}
        for jobs in (1, 2):
            best = min(timed([sscs, "sweep", sweep, "--out", os.path.join(tmp, f"j{jobs}-{r}"), "--jobs", str(jobs), "--quiet",
                              "--allow-outside-root"])  # the sweep file is in a temporary folder, the demo in the project
                       for r in range(a.runs))
            rates[f"sscs sweep --jobs {jobs}"] = 500 / best
        # The shell loop: one process per variant, each writing its JSON report, on --loop
        # variants drawn at random (a fixed seed) from the 500: their costs differ (more rows
        # and wider aisles push racks into the robot's reach).
        sample = random.Random(1).sample(variants, min(a.loop, len(variants)))
        script = "\n".join(f"{sscs} check {ROOT}/scenarios/demo/demo.yaml --set aisle='{x} m' --set rows={r} --set bays={b} "
                           f"--format json --out {tmp}/loop-{i}.json --quiet >/dev/null || [ $? -eq 1 ]"
                           for i, (x, r, b) in enumerate(sample))
        loop = timed(["bash", "-e", "-c", script])
        rates[f"shell loop of sscs check ({a.loop} variants)"] = a.loop / loop
        for name, rate in rates.items():
            print(f"{name:45s} {rate:8.1f} variants/s")
        j1, j2, sh = rates["sscs sweep --jobs 1"], rates["sscs sweep --jobs 2"], list(rates.values())[2]
        print(f"--jobs 2 / --jobs 1:     {j2 / j1:5.2f}x  (target >= 1.8x) on {os.cpu_count()} cores")
        print(f"--jobs 1 / shell loop:   {j1 / sh:5.2f}x  (target >= 5x)")


if __name__ == "__main__":
    main()
