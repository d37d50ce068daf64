#!/usr/bin/env python3
"""Benchmark of issue 4: sscs's no_overlap and clearance over 10,000 racks made by `array`,
side by side with a bare FCL program (tools/bench/bare_fcl.cpp) that builds the same boxes in a
DynamicAABBTree manager and runs the same queries. Also prints the naive all-pairs estimate.

The vault's racks are of a type the bench writes itself (BENCH_RACK: two uprights and a bottom
beam, the boxes bare_fcl.cpp builds), not the library's `rack`: when `rack` gained a deck at
every level (5 boxes a rack) the two sides did unequal work and the ratio read 2.53x for what
was 0.98x on equal work. Both sides build what the vault builds.

Target: sscs's constraint stage <= 1.5x the bare FCL time.
usage: spatial_vs_fcl.py [--build DIR] [--rows 100] [--cols 100] [--runs 3]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PX, PY, MIN = 2.9, 1.6, 0.5  # aisle pitch: racks 2.743 x 1.067, so gaps of 0.157 m and 0.533 m
# bare_fcl.cpp's make_rack, box for box (L 2.743, D 1.067, H 4.877).
BENCH_RACK = """sscs: 1
type: bench_rack
description: the rack bare_fcl.cpp builds (tools/bench/spatial_vs_fcl.py)
geometry:
  - box: {size: [0.08, 1.067, 4.877], xyz: [0.04, 0.5335, 2.4385]}
  - box: {size: [0.08, 1.067, 4.877], xyz: [2.703, 0.5335, 2.4385]}
  - box: {size: [2.743, 1.067, 0.1], xyz: [1.3715, 0.5335, 0.1]}
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--rows", type=int, default=100)
    ap.add_argument("--cols", type=int, default=100)
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    sscs = os.path.join(a.build, "src", "sscs")
    bare = os.path.join(a.build, "tools", "bench", "bare_fcl")
    with tempfile.TemporaryDirectory() as tmp:
        vault = os.path.join(tmp, "racks.yaml")
        os.makedirs(os.path.join(tmp, "lib", "types"))
        with open(os.path.join(tmp, "lib", "types", "bench_rack.yaml"), "w") as f:
            f.write(BENCH_RACK)
        with open(vault, "w") as f:
            f.write(f"""sscs: 1
vault: RackField
library: [lib]
objects:
  - type: bench_rack
    array: {{name: "R_{{i}}_{{j}}", count: [{a.rows}, {a.cols}], pitch: [{PX}, {PY}, 0]}}
constraints:
  - {{name: no overlaps, no_overlap: {{objects: "R_*"}}}}
  - {{name: aisles, clearance: {{objects: "R_*", min: {MIN} m}}}}
""")
        sscs_times, bare_times = [], []
        for _ in range(a.runs):
            p = subprocess.run([sscs, "check", vault, "--quiet"], capture_output=True, text=True,
                               env=dict(os.environ, SSCS_TIMING="1"))
            if p.returncode not in (0, 1):
                sys.exit(p.stderr)
            sscs_times.append(float(re.search(r"timing: check\s+([\d.]+)", p.stderr).group(1)))
            q = subprocess.run([bare, str(a.rows), str(a.cols), str(PX), str(PY), str(MIN)], capture_output=True, text=True,
                               check=True)
            bare_times.append(float(re.search(r"broadphase ([\d.]+) s", q.stdout).group(1)))
            summary = p.stdout.strip().splitlines()[-1]
        naive = subprocess.run([bare, str(a.rows), str(a.cols), str(PX), str(PY), str(MIN), "--naive", "1000"],
                               capture_output=True, text=True, check=True).stdout.strip().splitlines()[-1]
    s, b = min(sscs_times), min(bare_times)
    print(f"racks: {a.rows * a.cols} ({a.rows} x {a.cols}), pitch {PX} x {PY} m, clearance min {MIN} m")
    print(f"sscs check stage: {s:.3f} s (best of {a.runs}); sscs says: {summary}")
    print(f"bare FCL:         {b:.3f} s (best of {a.runs}); {q.stdout.strip().splitlines()[0]}")
    print(naive)
    print(f"ratio {s / b:.2f} (target <= 1.5) {'met' if s / b <= 1.5 else 'MISSED'}")


if __name__ == "__main__":
    main()
