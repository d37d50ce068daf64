#!/usr/bin/env python3
"""Real-time factors of `sscs simulate` (simulated seconds per wall second, without frames), a
baseline binary and this one side by side, best of N runs each, against issue 36's targets:

  arm demo                 scenarios/drum-transfer/arm-loads-drum.yaml        >= 80x
  store crane run          scenarios/drum-store/store-drum.yaml               >= 60x
  AGV + pallet + 4 drums   scenarios/drum-transfer/agv-unload.yaml            >= 20x
                           (an arm takes one drum off the pallet the AGV holds)
  store crane run, fast    the store's crane run in `sim: {mode: fast}`        >= 1000x
  arm demo, fast           the arm demo in fast mode
  AGV run, fast            the AGV run in fast mode (its stack carried: physics)

The fast-mode rows compare with this binary in physics mode (the baseline column), since a
baseline from before fast mode cannot run them.

  tools/bench/sim_speed.py --baseline OLD_SSCS [--sscs build/src/sscs] [--runs 3]

Build the baseline from the previous commit in a clean clone (`git clone -q . /tmp/base && git
-C /tmp/base checkout HEAD~1 && /tmp/base/tools/build.sh`). Run it on an idle machine: the two
binaries alternate, so a busy core slows both alike, but not equally. docs/benchmarks.md keeps
the figures measured.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = [
    ("arm demo", "scenarios/drum-transfer/arm-loads-drum.yaml", 80, None),
    ("store crane run", "scenarios/drum-store/store-drum.yaml", 60, None),
    ("AGV + pallet + 4 drums", "scenarios/drum-transfer/agv-unload.yaml", 20, None),
    ("store crane run, fast", "scenarios/drum-store/store-drum.yaml", 1000, "fast"),
    ("arm demo, fast", "scenarios/drum-transfer/arm-loads-drum.yaml", 0, "fast"),
    ("AGV run, fast", "scenarios/drum-transfer/agv-unload.yaml", 0, "fast"),
]


def with_mode(scenario, mode, tmp):
    """A copy of `scenario` with sim.mode set (its vault named by its absolute path)."""
    import yaml
    doc = yaml.safe_load(open(os.path.join(ROOT, scenario)))
    doc.setdefault("sim", {})["mode"] = mode
    doc["vault"] = os.path.normpath(os.path.join(ROOT, os.path.dirname(scenario), doc["vault"]))
    path = os.path.join(tmp, f"{mode}-{os.path.basename(scenario)}")
    with open(path, "w") as f:
        yaml.safe_dump(doc, f)
    return path


def timed(sscs, scenario, out):
    """Wall seconds of one run and what it simulated (summary.json), or None if it failed."""
    t0 = time.perf_counter()
    p = subprocess.run([sscs, "simulate", scenario, "--out", out, "--force", "--quiet", "--no-frames", "--allow-outside-root"],
                       cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    summary = os.path.join(out, "summary.json")
    if p.returncode not in (0, 1) or not os.path.exists(summary):
        sys.stderr.write(f"sim_speed: {sscs} {scenario}: exit {p.returncode}\n{p.stderr[-2000:]}")
        return None
    s = json.load(open(summary))
    return wall, s["simulated_time"], s["status"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline", required=True, help="the sscs binary to compare with (the previous commit's)")
    ap.add_argument("--sscs", default=os.path.join(ROOT, "build/src/sscs"))
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, scenario, target, mode in CASES:
            best = {}
            # A fast-mode row: this binary in physics mode beside it.
            runs = ((("baseline", args.baseline, scenario), ("this", args.sscs, scenario)) if mode is None else
                    (("baseline", args.sscs, scenario), ("this", args.sscs, with_mode(scenario, mode, tmp))))
            for k in range(args.runs):
                for label, binary, path in runs:
                    r = timed(binary, path, os.path.join(tmp, label))
                    if r is None:
                        return 1
                    if label not in best or r[0] < best[label][0]:
                        best[label] = r
            rows.append((name, target, best["baseline"], best["this"]))
    print(f"real-time factor (simulated s / wall s), best of {args.runs}, no frames")
    print(f"  {'':24} {'baseline':>18} {'this':>18} {'speed-up':>9} {'target':>8}")
    for name, target, (w0, s0, st0), (w1, s1, st1) in rows:
        f0, f1 = s0 / w0, s1 / w1
        mark = "" if not target else "ok" if f1 >= target else "BELOW"
        print(f"  {name:24} {f0:7.1f}x {w0:7.2f} s {f1:7.1f}x {w1:7.2f} s {w0 / w1:8.2f}x {target:6}x {mark}")
        if st0 != st1:
            print(f"  {'':24} status differs: baseline {st0}, this {st1}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
