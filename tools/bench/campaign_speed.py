#!/usr/bin/env python3
"""Campaign speed (issue 37's targets), a baseline binary and this one side by side, best of N:

  receiving, fast      scenarios/drum-store/receiving.yaml (40 drums by the crane, 8 pallets
                       by the forklift, 2 h 39 min)                                 <= 10 s wall, >= 1000x
  crane alone, fast    the same without the pallets: the 40 drums only               (the figure before the forklift)
  receiving, physics   the crane's campaign in physics mode, its first --drums drums  >= 20x
  concept study        scenarios/drum-store/concepts.yaml, 36 variants, --jobs 2      <= 180 s wall

  tools/bench/campaign_speed.py --baseline OLD_SSCS [--sscs build/src/sscs] [--runs 1] [--baseline-runs N] [--drums 10] [--study-baseline]

The physics row runs a shorter campaign (the first --drums of the 40; the real-time factor is
what is compared, and the whole campaign in physics mode takes minutes). Build the baseline from
an earlier commit in a clean clone (see sim_speed.py). docs/benchmarks.md keeps the figures.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_speed import timed  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RECEIVING = "scenarios/drum-store/receiving.yaml"
STUDY = "scenarios/drum-store/concepts.yaml"


def variant(tmp, mode, drums, pallets=True):
    """receiving.yaml with its mode and drum count set, without the forklift's pallets when not
    `pallets`, its vault named absolutely."""
    text = open(os.path.join(ROOT, RECEIVING)).read()
    text = text.replace("vault: store.yaml", f"vault: {os.path.join(ROOT, 'scenarios/drum-store/store.yaml')}")
    text = text.replace("mode: fast", f"mode: {mode}")
    if not pallets:
        text = re.sub(r'  # Pallets of supplies.*?(?=jobs:)', "", text, flags=re.S)
        text = re.sub(r'  # The forklift stores.*', "", text, flags=re.S)
    if drums < 40:
        text = text.replace("count: 40", f"count: {drums}")
        # The even rows' template takes In_20.. : with fewer drums only the odd rows' remain.
        text = re.sub(r'  - name: store_even\n(    .*\n|      .*\n)*', "", text)
    path = os.path.join(tmp, f"receiving-{mode}-{drums}{'' if pallets else '-crane'}.yaml")
    open(path, "w").write(text)
    return path


def simulate(sscs, path, out):
    """Wall seconds of one run, what it simulated and its status (sim_speed.py's, shared)."""
    return timed(sscs, path, out)


def sweep(sscs, out):
    t0 = time.perf_counter()
    p = subprocess.run([sscs, "sweep", STUDY, "--out", out, "--force", "--quiet", "--jobs", "2"], cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode not in (0, 1):
        sys.stderr.write(f"campaign_speed: {sscs} sweep: exit {p.returncode}\n{p.stderr[-2000:]}")
        return None
    return wall, 0.0, p.stdout.strip().splitlines()[-1] if p.stdout.strip() else ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline", required=True, help="the sscs binary to compare with")
    ap.add_argument("--sscs", default=os.path.join(ROOT, "build/src/sscs"))
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--baseline-runs", type=int, help="runs of the baseline (default --runs): a slow baseline once is enough")
    ap.add_argument("--drums", type=int, default=10, help="drums of the physics-mode row (of 40)")
    ap.add_argument("--study-baseline", action="store_true",
                    help="run the concept study with the baseline too (a baseline without fast glides takes most of an hour)")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        cases = [("receiving, fast", lambda b, o: simulate(b, variant(tmp, "fast", 40), o), 1000, 10, True),
                 ("crane alone, fast", lambda b, o: simulate(b, variant(tmp, "fast", 40, False), o), None, None, True),
                 (f"receiving ({args.drums}), physics", lambda b, o: simulate(b, variant(tmp, "physics", args.drums, False), o), 20, None, True),
                 ("concept study, 36", lambda b, o: sweep(b, o), None, 180, args.study_baseline)]
        for k, (name, run, factor, wall_limit, both) in enumerate(cases):
            best = {}
            for k_run in range(args.runs):
                for label, binary in (("baseline", args.baseline), ("this", args.sscs)):
                    if label == "baseline" and args.baseline_runs is not None and k_run >= args.baseline_runs and label in best:
                        continue
                    if label == "baseline" and not both:
                        best[label] = (float("nan"), 0.0, "")
                        continue
                    r = run(binary, os.path.join(tmp, f"{label}-{k}"))
                    if r is None:
                        return 1
                    if label not in best or r[0] < best[label][0]:
                        best[label] = r
            rows.append((name, factor, wall_limit, best["baseline"], best["this"]))
    runs = f"best of {args.runs}" + (f" (the baseline of {min(args.baseline_runs, args.runs)})" if args.baseline_runs is not None else "")
    print(f"campaigns: wall seconds and real-time factors, {runs}, no frames")
    print(f"  {'':24} {'baseline':>20} {'this':>20} {'speed-up':>9}  target")
    for name, factor, wall_limit, (w0, s0, st0), (w1, s1, st1) in rows:
        f0 = f"{s0 / w0:7.1f}x" if s0 else " " * 8
        f1 = f"{s1 / w1:7.1f}x" if s1 else " " * 8
        want = []
        ok = True
        if factor:
            want.append(f">= {factor}x")
            ok = ok and s1 / w1 >= factor
        if wall_limit:
            want.append(f"<= {wall_limit} s")
            ok = ok and w1 <= wall_limit
        speedup = f"{w0 / w1:8.2f}x" if w0 == w0 else " " * 9
        print(f"  {name:24} {f0} {w0:9.2f} s {f1} {w1:9.2f} s {speedup}  {', '.join(want)} {'ok' if ok else 'BELOW'}")
        if st0 and st0 != st1:
            print(f"  {'':24} status differs: baseline {st0}, this {st1}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
