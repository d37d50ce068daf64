#!/usr/bin/env python3
"""Benchmark of issue 3: `sscs check` on a generated 20,000-object, 200,000-constraint vault,
side by side with bare yaml-cpp (YAML::LoadFile + a visit of every scalar) on the same file.

Prints wall time and peak resident memory of both and the ratios (targets: time <= 0.6x,
memory <= 0.25x). With --format json (or junit, sarif) it also runs `sscs check --format json
--out FILE` side by side with the text report and prints what the streamed report adds over the
text one (issue 17's target: at most 10 % time and 10 MB).
usage: check_vs_yaml.py [--build DIR] [--objects N] [--constraints M] [--runs K] [--format F]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


CPU = {}  # per command line: CPU seconds (user + system) of each run


def measure(cmd):
    """Wall seconds and peak RSS (MiB) of one run of cmd (its CPU seconds kept in CPU)."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    code = os.waitstatus_to_exitcode(status)
    if code not in (0, 1):
        sys.exit(f"{cmd[0]} exited {code}: {proc.stderr.read().decode()[:2000]}")
    CPU.setdefault(" ".join(cmd[:2] + cmd[3:]), []).append(usage.ru_utime + usage.ru_stime)
    return wall, usage.ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--objects", type=int, default=20000)
    ap.add_argument("--constraints", type=int, default=200000)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--format", default="text", choices=["text", "json", "junit", "sarif"])
    a = ap.parse_args()
    sscs = os.path.join(a.build, "src", "sscs")
    bare = os.path.join(a.build, "tools", "bench", "bare_yaml_parse")
    with tempfile.TemporaryDirectory() as tmp:
        vault = os.path.join(tmp, "bench.yaml")
        subprocess.run([sys.executable, os.path.join(ROOT, "tools", "bench", "gen_vault.py"), vault,
                        "--objects", str(a.objects), "--constraints", str(a.constraints)], check=True)
        size = os.path.getsize(vault) / 1e6
        print(f"vault: {a.objects} objects, {a.constraints} constraints, {size:.1f} MB")
        results = {"sscs check": [], "bare yaml-cpp": []}
        report = f"sscs check --format {a.format}"
        if a.format != "text":
            results[report] = []
        for _ in range(a.runs):  # interleaved, so drift affects all alike
            results["sscs check"].append(measure([sscs, "check", vault, "--quiet"]))
            results["bare yaml-cpp"].append(measure([bare, vault]))
            if a.format != "text":
                out = os.path.join(tmp, "report." + {"json": "json", "junit": "xml", "sarif": "sarif"}[a.format])
                results[report].append(measure([sscs, "check", vault, "--quiet", "--format", a.format, "--out", out]))
                size = os.path.getsize(out) / 1e6
    best = {k: (min(w for w, _ in v), min(m for _, m in v)) for k, v in results.items()}
    for name, (wall, mem) in best.items():
        print(f"{name:>28}: {wall:7.2f} s (best of {a.runs})  {mem:8.1f} MiB peak")
    if a.format != "text":
        # Medians as well as bests: single runs on this machine vary by +-0.1 s.
        median = {k: sorted(w for w, _ in v)[len(v) // 2] for k, v in results.items()}
        for label, t_text, t_report in (("best", best["sscs check"][0], best[report][0]),
                                        ("median", median["sscs check"], median[report])):
            dm = best[report][1] - best["sscs check"][1]
            rt = t_report / t_text
            print(f"{a.format} report ({size:.1f} MB) over the text report, {label} of {a.runs}: +{t_report - t_text:.2f} s "
                  f"({100 * (rt - 1):.1f} %), {dm:+.1f} MiB  (target <= 10 % and 10 MB)  {'met' if rt <= 1.10 and dm <= 10 else 'MISSED'}")
        # CPU time as well: on a shared virtual machine wall time drifts by 10-20 % between runs.
        cpu_text = min(min(v) for k, v in CPU.items() if "--format" not in k and " check " in k)
        cpu_report = min(min(v) for k, v in CPU.items() if "--format" in k)
        rc = cpu_report / cpu_text
        print(f"{a.format} report over the text report, CPU seconds (user + system), best of {a.runs}: "
              f"{cpu_text:.2f} s -> {cpu_report:.2f} s ({100 * (rc - 1):+.1f} %)  {'met' if rc <= 1.10 else 'MISSED'}")
        print(f"ratio time   {best[report][0] / best['bare yaml-cpp'][0]:.3f}, memory "
              f"{best[report][1] / best['bare yaml-cpp'][1]:.3f} of bare yaml-cpp with the {a.format} report")
    t = best["sscs check"][0] / best["bare yaml-cpp"][0]
    m = best["sscs check"][1] / best["bare yaml-cpp"][1]
    print(f"ratio time   {t:.3f}  (target <= 0.6)  {'met' if t <= 0.6 else 'MISSED'}")
    print(f"ratio memory {m:.3f}  (target <= 0.25) {'met' if m <= 0.25 else 'MISSED'}")


if __name__ == "__main__":
    main()
