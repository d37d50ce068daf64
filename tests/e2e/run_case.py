#!/usr/bin/env python3
"""End-to-end test driver: runs the sscs binary and compares what it prints and writes.

  run_case.py --sscs BIN --root REPO golden tests/golden/NAME.case
      NAME.case holds `args: ...` (run from the repository root) and `exit: N`; the output
      (stdout, or the --out file when the args name {out}) must equal NAME.out byte for byte.
      SSCS_UPDATE_GOLDEN=1 rewrites NAME.out instead.
  run_case.py ... bad tests/data/bad/NAME.expect
      NAME.expect holds `exit: N` and `stderr: FRAGMENT` lines (and optionally `args: ...`,
      default `check tests/data/bad/NAME.yaml`). The run must exit N, print every fragment on
      stderr, print nothing on stdout and write no --out file.
  In args, {build} stands for the build folder (plugins: --plugins {build}/plugins).
  run_case.py ... cli
      command-line behaviour: formats, --out, --set, --strict, exit statuses, types.
"""
import argparse
import collections
import csv
import io
import glob
import hashlib
import json
import math
import random
import shutil
import os
import re
import shlex
import subprocess
import sys
import tempfile
import zipfile
from concurrent.futures import ThreadPoolExecutor


def parse_case(path):
    fields = {"stderr": [], "stdout": []}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line.strip() or line.startswith("#"):
                continue
            key, _, value = line.partition(":")
            value = value[1:] if value.startswith(" ") else value
            if key in ("stderr", "stdout"):
                fields[key].append(value)
            else:
                fields[key] = value
    return fields


def build_dir(sscs):
    """The build folder (the binary is BUILD/src/sscs): `{build}` in case args, e.g. {build}/plugins."""
    return os.path.dirname(os.path.dirname(os.path.abspath(sscs)))


def run(sscs, root, args, env=None):
    proc = subprocess.run([sscs] + args, cwd=root, capture_output=True, text=True, errors="replace", timeout=300,
                          env=dict(os.environ, **(env or {}), NO_COLOR="1"))
    return proc


def fail(msg, proc=None):
    print("FAIL:", msg)
    if proc is not None:
        print("--- exit", proc.returncode)
        print("--- stdout\n" + proc.stdout[-4000:])
        print("--- stderr\n" + proc.stderr[-4000:])
    sys.exit(1)


def golden(sscs, root, case):
    fields = parse_case(case)
    expected_out = case[:-len(".case")] + ".out"
    with tempfile.TemporaryDirectory() as tmp:
        out_file = os.path.join(tmp, "report")
        args = [a.replace("{out}", out_file).replace("{build}", build_dir(sscs)) for a in shlex.split(fields["args"])]
        proc = run(sscs, root, args)
        if proc.returncode != int(fields["exit"]):
            fail(f"exit status {proc.returncode}, expected {fields['exit']}", proc)
        actual = open(out_file, encoding="utf-8").read() if "{out}" in fields["args"] else proc.stdout
    if os.environ.get("SSCS_UPDATE_GOLDEN"):
        with open(expected_out, "w", encoding="utf-8") as f:
            f.write(actual)
        print("updated", expected_out)
        return
    expected = open(expected_out, encoding="utf-8").read()
    if actual != expected:
        import difflib
        diff = "".join(difflib.unified_diff(expected.splitlines(True), actual.splitlines(True), "expected", "actual"))
        fail(f"output differs from {expected_out}:\n{diff[:6000]}")
    print("ok", case)


def bad(sscs, root, expect):
    fields = parse_case(expect)
    name = os.path.basename(expect)[:-len(".expect")]
    if not fields["stderr"]:
        fail(f"{expect} names no stderr fragment")
    with tempfile.TemporaryDirectory() as tmp:
        # {tmp}: an output path inside the folder that must stay empty.
        args = [a.replace("{build}", build_dir(sscs)).replace("{tmp}", os.path.join(tmp, "out"))
                for a in shlex.split(fields.get("args", f"check tests/data/bad/{name}.yaml"))]
        out_file = os.path.join(tmp, "report.json")
        # env: NAME=VALUE ... (a limit lowered for the case)
        env = dict(kv.split("=", 1) for kv in shlex.split(fields.get("env", "")))
        proc = run(sscs, root, args + ["--out", out_file] if args[0] in ("check", "simulate", "sweep") and "merge" not in args else args,
                   env=env)
        if proc.returncode != int(fields["exit"]):
            fail(f"exit status {proc.returncode}, expected {fields['exit']}", proc)
        for fragment in fields["stderr"]:
            if fragment not in proc.stderr:
                fail(f"stderr lacks {fragment!r}", proc)
        # errors: N (optional): exactly N errors, none that follow from another
        if "errors" in fields and proc.stderr.count(": error: ") != int(fields["errors"]):
            fail(f"{proc.stderr.count(': error: ')} errors, expected {fields['errors']}", proc)
        if proc.stdout.strip():
            fail("an input error must print nothing on stdout", proc)
        if os.listdir(tmp):
            fail(f"an input error must write no output, found {os.listdir(tmp)}", proc)
    print("ok", expect)


def cli(sscs, root):
    demo = "scenarios/demo/demo.yaml"
    good = "tests/data/good/minimal.yaml"
    with tempfile.TemporaryDirectory() as tmp:
        # A passing vault exits 0 and says so.
        p = run(sscs, root, ["check", good])
        if p.returncode != 0 or p.stdout.strip().splitlines()[-1] != "3 passed, 0 failed, 0 warnings":
            fail("minimal vault should pass", p)
        # --set changes a parameter and so the result; a failing error constraint exits 1.
        p = run(sscs, root, ["check", good, "--set", "gap=3 m"])
        if p.returncode != 1 or "2 passed, 1 failed, 0 warnings" not in p.stdout:
            fail("--set gap=3 m should fail one constraint", p)
        # Warnings pass the gate unless --strict.
        p = run(sscs, root, ["check", "tests/data/good/warning_only.yaml"])
        if p.returncode != 0 or "1 passed, 0 failed, 1 warnings" not in p.stdout:
            fail("a failing warning alone exits 0", p)
        p = run(sscs, root, ["check", "tests/data/good/warning_only.yaml", "--strict"])
        if p.returncode != 1:
            fail("a failing warning with --strict exits 1", p)
        # A warning-severity check that cannot be evaluated is no warning: nothing is known to
        # hold, so it fails the gate in every report.
        unevaluated = "tests/data/good/warning_unevaluated.yaml"
        p = run(sscs, root, ["check", unevaluated])
        if p.returncode != 1 or "1 passed, 1 failed (1 could not be evaluated), 0 warnings" not in p.stdout or \
                ": error: spare ratio" not in p.stdout:
            fail("a warning that cannot be evaluated fails the gate", p)
        p = run(sscs, root, ["check", unevaluated, "--format", "junit"])
        import xml.etree.ElementTree as ET
        suite = ET.fromstring(p.stdout).find("testsuite")
        if p.returncode != 1 or suite.get("errors") != "1" or len(suite.findall("testcase/error")) != 1:
            fail("junit: a warning that cannot be evaluated is an <error>", p)
        p = run(sscs, root, ["check", unevaluated, "--format", "sarif"])
        levels = [r["level"] for r in json.loads(p.stdout)["runs"][0]["results"]]
        if p.returncode != 1 or levels != ["error"]:
            fail("sarif: a warning that cannot be evaluated is level error", p)
        p = run(sscs, root, ["check", unevaluated, "--format", "json"])
        if p.returncode != 1 or json.loads(p.stdout)["failed"] != 1 or json.loads(p.stdout)["warnings"] != 0:
            fail("json: a warning that cannot be evaluated counts as failed", p)
        # --out infers the format from the extension and writes the file atomically.
        out = os.path.join(tmp, "r.json")
        p = run(sscs, root, ["check", demo, "--out", out])
        report = json.load(open(out))
        if p.returncode != 1 or report["vault"] != "DemoStore" or report["failed"] != 4:
            fail("--out r.json should write the JSON report", p)
        if [f for f in os.listdir(tmp) if f.startswith(".")]:
            fail("temporary file left behind")
        xml = os.path.join(tmp, "r.xml")
        run(sscs, root, ["check", demo, "--out", xml])
        import xml.etree.ElementTree as ET
        suites = ET.parse(xml).getroot()
        suite = suites.find("testsuite")
        if suites.tag != "testsuites" or suite.get("name") != "DemoStore" or suite.get("tests") != str(len(report["results"])):
            fail("junit structure")
        if len(suite.findall("testcase/failure")) != 4 or len(suite.findall("testcase/error")) != 0:
            fail("junit should hold 4 failures and no error for the demo")
        # Several vaults in one run: one JSON document with a report each.
        p = run(sscs, root, ["check", good, demo, "--format", "json"])
        both = json.loads(p.stdout)
        if [r["vault"] for r in both["reports"]] != ["Minimal", "DemoStore"] or p.returncode != 1:
            fail("two vaults", p)
        # An unknown --set parameter is an input error with a suggestion.
        p = run(sscs, root, ["check", good, "--set", "gapp=1"])
        if p.returncode != 2 or "did you mean 'gap'" not in p.stderr:
            fail("unknown --set", p)
        # Usage errors exit 2; --version and --help exit 0.
        if run(sscs, root, ["check"]).returncode != 2 or run(sscs, root, ["frobnicate"]).returncode != 2:
            fail("usage errors exit 2")
        p = run(sscs, root, ["--version"])
        if p.returncode != 0 or not p.stdout.startswith("sscs "):
            fail("--version", p)
        if run(sscs, root, ["check", "--help"]).returncode != 0:
            fail("check --help")
        # types lists the standard library with attributes, in text and JSON.
        p = run(sscs, root, ["types", "--format", "json"])
        types = {t["name"]: t for t in json.loads(p.stdout)["types"]}
        for t in ["room", "wall", "door", "rack", "shelf", "drum", "shipping_container", "pallet", "cart"]:
            if t not in types:
                fail(f"types lacks {t}", p)
        drum = {a["name"]: a for a in types["drum"]["attributes"]}
        if drum["diameter"]["default"] != "0.572" or drum["diameter"]["max"] != 2 or drum["lid"]["values"] != ["open", "closed"]:
            fail("drum attributes", p)
        p = run(sscs, root, ["types", "--library", "scenarios/demo/library"])
        if "waste_drum (extends drum_hooped)" not in p.stdout or "fissile_mass" not in p.stdout:
            fail("types --library", p)
    print("ok cli")


def simulate(sscs, root):
    """sscs simulate on the standard scenarios: physics checked, runs repeatable, outputs complete."""
    arm = "scenarios/drum-transfer/arm-loads-drum.yaml"
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run")
        p = run(sscs, root, ["simulate", arm, "--out", out, "--quiet"])
        if p.returncode != 0 or "arm-loads-drum: ok" not in p.stdout:
            fail("the arm scenario should run ok", p)
        for f in ["summary.json", "events.jsonl", "trajectories/Robot.csv", "objects.csv"]:
            if not os.path.isfile(os.path.join(out, f)):
                fail(f"missing {f}")
        if [f for f in os.listdir(tmp) if f != "run"]:
            fail(f"temporary output left behind: {os.listdir(tmp)}")
        summary = json.load(open(os.path.join(out, "summary.json")))
        events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
        kinds = [e["kind"] for e in events]
        if summary["status"] != "ok" or "collision" in kinds or kinds.count("step_start") != 10:
            fail(f"arm scenario events: {kinds}")
        # The released drum lands on the rack and rests on its bottom level: slot_1 is at
        # (2.6 + 2.743/2, 4.6 + 1.067/2, 0.15); the drum's origin is its bottom.
        rest = [e for e in events if e["kind"] == "at_rest"]
        if len(rest) != 1 or abs(rest[0]["position"][2] - 0.15) > 0.005 or \
                abs(rest[0]["position"][0] - 3.9715) > 0.02 or abs(rest[0]["position"][1] - 5.1335) > 0.02:
            fail(f"drum at rest: {rest}")
        landed = [e for e in events if e["kind"] == "landed"]
        if len(landed) != 1 or landed[0]["on"] != "Rack_A":
            fail(f"landed: {landed}")
        # Every logged joint stays within its limits (j1 +-180, j2 -95..155, j3 -180..75, j5 +-120).
        rows = open(os.path.join(out, "trajectories/Robot.csv")).read().splitlines()
        header = rows[0].split(",")
        limits = {"j1": (-180, 180), "j2": (-95, 155), "j3": (-180, 75), "j5": (-120, 120)}
        for row in rows[1:]:
            values = dict(zip(header, map(float, row.split(","))))
            for j, (lo, hi) in limits.items():
                if not lo - 0.1 <= values[j] <= hi + 0.1:
                    fail(f"{j} = {values[j]} outside [{lo}, {hi}] at t = {values['t']}")
        # Frames at record.frames.fps (15) of simulated time: duration x fps + 1 of them, listed
        # with their times in frames/index.csv.
        index = open(os.path.join(out, "frames", "index.csv")).read().splitlines()
        frames = sorted(f for f in os.listdir(os.path.join(out, "frames")) if f.endswith(".png"))
        expected = int(summary["simulated_time"] * 15 + 1e-9) + 1
        if len(frames) != expected or len(index) != expected + 1 or index[1] != "0,0.0000,frame_000000.png" or \
                frames[-1] != f"frame_{expected - 1:06d}.png":
            fail(f"{len(frames)} frames, {len(index) - 1} indexed, expected {expected}")
        for row in index[1:]:
            n, t, _ = row.split(",")
            if not int(n) / 15 - 0.0005 <= float(t) < int(n) / 15 + 0.001:
                fail(f"frame {n} drawn at {t} s")
        # Frames look as they should: the opening view, the arm carrying the drum past the rack,
        # the drum on the shelf (golden images, mean absolute difference below 2).
        for n in (0, 75, 150):
            compare_image(os.path.join(out, "frames", f"frame_{n:06d}.png"),
                          os.path.join(root, f"tests/golden/arm_frame_{n:06d}.png"))
        # The contact sheet: one labelled thumbnail (320 px wide) per step end, four to a row:
        # ten steps, three rows.
        w, h, rows = read_png(os.path.join(out, "contact_sheet.png"))
        if (w, h) != (10 + 4 * 330, 10 + 3 * (180 + 26 + 10)):
            fail(f"contact sheet {w}x{h}")
        # Labels are drawn in dark ink under each thumbnail (FreeType).
        label = rows[10 + 180 + 4: 10 + 180 + 22]
        if not any(min(r[i] for i in range(0, 3 * 200)) < 80 for r in label):
            fail("no label text under the first thumbnail")
        # replay draws the frames again from the logs: with the run's cameras, the same pictures
        # (mean absolute difference below 0.5 of 255; joint values come from 50 Hz logs rounded to
        # 1e-6 deg); with a camera file, another view.
        replay = os.path.join(tmp, "replay")
        p = run(sscs, root, ["replay", out, "--out", replay], env={"DISPLAY": ""})
        if p.returncode != 0 or f"replayed {expected} frames" not in p.stdout:
            fail("replay of the arm run", p)
        for n in (0, expected // 2, expected - 1):
            compare_image(os.path.join(replay, "frames", f"frame_{n:06d}.png"),
                          os.path.join(out, "frames", f"frame_{n:06d}.png"), threshold=0.5)
        cams = os.path.join(tmp, "top.yaml")
        open(cams, "w").write("sscs: 1\ncameras:\n  - {t: 0, eye: [4, 4, 12], target: [4, 4.01, 0], fov: 60}\n")
        top = os.path.join(tmp, "replay-top")
        p = run(sscs, root, ["replay", out, "--out", top, "--camera", cams, "--size", "320x180"])
        w, h, _ = read_png(os.path.join(top, "frames", "frame_000000.png"))
        if p.returncode != 0 or (w, h) != (320, 180) or \
                len(open(os.path.join(top, "frames", "index.csv")).read().splitlines()) != expected + 1:
            fail("replay with a camera file and --size", p)
        open(cams, "w").write("sscs: 1\ncameras:\n  - {t: 0, eye: [4, 4, 12], target: [4, 4, 0], fvo: 60}\n")
        p = run(sscs, root, ["replay", out, "--out", os.path.join(tmp, "bad-camera"), "--camera", cams])
        if p.returncode != 2 or "top.yaml:3:48: error: unknown key 'fvo' in camera keyframe (did you mean 'fov'?)" not in p.stderr or \
                os.path.exists(os.path.join(tmp, "bad-camera")):
            fail("a camera file with a misspelt key", p)
        if run(sscs, root, ["replay", tmp, "--out", os.path.join(tmp, "nothing")]).returncode != 2:
            fail("replay of a folder that is not a run exits 2")
        # A corrupt log (a cell that is no number, nan, a short row, time going back) is an input
        # error naming file and line, never a crash or a replay of NaN poses.
        robot_csv = os.path.join(out, "trajectories", "Robot.csv")
        good = open(robot_csv).read()
        lines = good.splitlines(True)
        for label, bad_row in [("text", lines[3].replace(lines[3].split(",")[1], "abc", 1)),
                               ("nan", lines[3].replace(lines[3].split(",")[1], "nan", 1)),
                               ("short", lines[3].split(",")[0] + "\n"),
                               ("backwards", "0" + lines[3][lines[3].index(","):])]:
            open(robot_csv, "w").write("".join(lines[:3] + [bad_row] + lines[4:]))
            p = run(sscs, root, ["replay", out, "--out", os.path.join(tmp, "corrupt-" + label)])
            if p.returncode != 2 or "Robot.csv:4:" not in p.stderr or os.path.exists(os.path.join(tmp, "corrupt-" + label)):
                fail(f"replay of a run whose trajectory log is corrupt ({label})", p)
        open(robot_csv, "w").write(good)
        # The same for the frame index the replay takes its times from (it crashed on a cell
        # that was no number: exit 3, "internal error: stod").
        index_csv = os.path.join(out, "frames", "index.csv")
        good = open(index_csv).read()
        lines = good.splitlines(True)
        # A row cut short, a frame number that is no number, a time beyond the run: the same.
        for label, bad_row in [("text", "2,abc,frame_000002.png\n"), ("backwards", "2,0.0000,frame_000002.png\n"),
                               ("cut", "2,0.1333,\n"), ("frame", "x,0.1333,frame_000002.png\n"),
                               ("beyond", "2,99.0000,frame_000002.png\n")]:
            open(index_csv, "w").write("".join(lines[:3] + [bad_row] + lines[4:]))
            p = run(sscs, root, ["replay", out, "--out", os.path.join(tmp, "index-" + label)])
            if p.returncode != 2 or "frames/index.csv:4:" not in p.stderr or os.path.exists(os.path.join(tmp, "index-" + label)):
                fail(f"replay of a run whose frame index is corrupt ({label})", p)
        # An index that lists nothing, or whose header is not the recorder's (replays of 0 frames
        # passed, exit 0).
        for label, text in [("empty", ""), ("header", "frame,t,file\n"), ("renamed", good.replace("frame,t,file", "frame,time,file", 1))]:
            open(index_csv, "w").write(text)
            p = run(sscs, root, ["replay", out, "--out", os.path.join(tmp, "index-" + label)])
            if p.returncode != 2 or "frames/index.csv" not in p.stderr or os.path.exists(os.path.join(tmp, "index-" + label)):
                fail(f"replay of a run whose frame index is {label}", p)
        open(index_csv, "w").write(good)
        # A missing log of a device the run moved (the arm stood still in every frame, exit 0),
        # trajectory rows short of the header's cells, an objects.csv whose header is not ours.
        shutil.move(robot_csv, robot_csv + ".away")
        p = run(sscs, root, ["replay", out, "--out", os.path.join(tmp, "no-robot-log")])
        if p.returncode != 2 or "Robot.csv: missing, though the run moved Robot" not in p.stderr or \
                os.path.exists(os.path.join(tmp, "no-robot-log")):
            fail("replay of a run without the moved arm's log", p)
        shutil.move(robot_csv + ".away", robot_csv)
        robot_lines = open(robot_csv).read().splitlines(True)
        open(robot_csv, "w").write("".join(robot_lines[:3] + [",".join(robot_lines[3].split(",")[:7]) + "\n"] + robot_lines[4:]))
        p = run(sscs, root, ["replay", out, "--out", os.path.join(tmp, "short-rows")])
        if p.returncode != 2 or "Robot.csv:4: a row of 7 cells" not in p.stderr:
            fail("replay of a trajectory row short of its cells", p)
        open(robot_csv, "w").write("".join(robot_lines))
        objects_csv = os.path.join(out, "objects.csv")
        objects_good = open(objects_csv).read()
        open(objects_csv, "w").write(objects_good.replace("t,object,x,y,z,roll,pitch,yaw", "t,object,x,y", 1))
        p = run(sscs, root, ["replay", out, "--out", os.path.join(tmp, "objects-header")])
        if p.returncode != 2 or "objects.csv:1: the header is 't,object,x,y'" not in p.stderr:
            fail("replay of an objects.csv with another header", p)
        open(objects_csv, "w").write(objects_good)
        # --out: never a folder of other files, a file or the run itself (replay replaced them
        # with its frames); an earlier replay only with --force.
        keep = os.path.join(tmp, "keep")
        os.makedirs(keep, exist_ok=True)
        open(os.path.join(keep, "notes.txt"), "w").write("mine")
        afile = os.path.join(tmp, "afile")
        open(afile, "w").write("mine")
        for target, says in [(keep, "exists and is not an earlier replay"), (afile, "is a file"), (out, "exists and is not an earlier replay"),
                             (replay, "holds an earlier replay; pass --force")]:
            p = run(sscs, root, ["replay", out, "--out", target])
            if p.returncode != 2 or says not in p.stderr:
                fail(f"replay --out {target}: refused", p)
        if open(os.path.join(keep, "notes.txt")).read() != "mine" or open(afile).read() != "mine" or \
                not os.path.exists(os.path.join(out, "summary.json")):
            fail("a refused replay --out left its target as it was")
        p = run(sscs, root, ["replay", out, "--out", replay, "--force", "--quiet"])
        if p.returncode != 0 or not os.path.exists(os.path.join(replay, "frames", "index.csv")):
            fail("replay --force over an earlier replay", p)
        # simulate --bundle --force replaces a run's bundle, never another zip (any .zip was).
        other_zip = os.path.join(tmp, "other.zip")
        shutil.make_archive(other_zip[:-4], "zip", keep)
        p = run(sscs, root, ["simulate", arm, "--bundle", other_zip, "--force", "--no-frames", "--quiet"])
        if p.returncode != 2 or "is not the bundle of a run of sscs simulate" not in p.stderr or \
                not zipfile.is_zipfile(other_zip) or zipfile.ZipFile(other_zip).namelist() != ["notes.txt"]:
            fail("simulate --bundle --force over a zip that is no run's", p)
        # --wall-limit: decimal seconds above 0, given (an empty value ran without a limit, 0x10 was 16 s).
        for value in ("", "0x10"):
            p = run(sscs, root, ["simulate", arm, "--out", os.path.join(tmp, "wall"), "--wall-limit", value, "--no-frames"])
            if p.returncode != 2 or "--wall-limit expects a number of seconds above 0" not in p.stderr or \
                    os.path.exists(os.path.join(tmp, "wall")):
                fail(f"--wall-limit '{value}'", p)
        # --video pipes the raw frames to ffmpeg (a stand-in here that records what it got: the
        # real encoder is not installed on CI); without ffmpeg on PATH it is an input error.
        fake = os.path.join(root, "tests/data/fake-ffmpeg")
        video = os.path.join(tmp, "arm.mp4")
        p = run(sscs, root, ["simulate", arm, "--out", os.path.join(tmp, "video"), "--video", video, "--quiet"],
                env={"PATH": fake + os.pathsep + os.environ["PATH"]})
        got = open(video).read() if os.path.exists(video) else ""
        if p.returncode != 0 or "-f rawvideo -pix_fmt rgb24 -s 960x540 -framerate 15 -i -" not in got or \
                f"bytes {expected * 960 * 540 * 3}" not in got:
            fail(f"--video: {got}", p)
        p = run(sscs, root, ["simulate", arm, "--out", os.path.join(tmp, "novideo"), "--video", video], env={"PATH": tmp})
        if p.returncode != 2 or "--video needs ffmpeg, which is not installed" not in p.stderr or \
                os.path.exists(os.path.join(tmp, "novideo")):
            fail("--video without ffmpeg", p)
        # Re-checks of containment during a run hold within sim.check_tolerance (0.1 mm): a drum set
        # down on the floor sinks by micrometres in ODE's contacts, which is no violation; with a
        # tolerance of 0 the same run reports it (what the default absorbs, and nothing more).
        floor = os.path.join(tmp, "floor")
        p = run(sscs, root, ["simulate", "tests/data/sim/floor-lift.yaml", "--out", floor, "--quiet"])
        kinds = [json.loads(line)["kind"] for line in open(os.path.join(floor, "events.jsonl"))]
        if p.returncode != 0 or "constraint" in kinds or kinds.count("grasp") != 2 or "landed" not in kinds:
            fail(f"floor-lift should run ok without constraint events: {kinds}", p)
        strict = os.path.join(tmp, "floor-lift-strict.yaml")
        text = open(os.path.join(root, "tests/data/sim/floor-lift.yaml")).read()
        open(strict, "w").write(text.replace("vault: floor-cell.yaml", "vault: " + os.path.join(root, "tests/data/sim/floor-cell.yaml"))
                                .replace("limit: 30 s}", "limit: 30 s, check_tolerance: 0}"))
        # The scenario (in a temporary folder) names the project's vault: --root lets it.
        p = run(sscs, root, ["simulate", strict, "--out", os.path.join(tmp, "floor0"), "--quiet", "--root", root])
        events = [json.loads(line) for line in open(os.path.join(tmp, "floor0", "events.jsonl"))]
        sunk = [e for e in events if e["kind"] == "constraint"]
        if p.returncode != 1 or len(sunk) != 1 or not (-1e-4 < sunk[0]["margin"] < 0):
            fail(f"with check_tolerance 0 the sinking drum is one micrometre-scale constraint event: {sunk}", p)
        # An existing run folder is never replaced without --force (issue 17): exit 2, untouched.
        before = open(os.path.join(out, "summary.json"), "rb").read()
        p = run(sscs, root, ["simulate", arm, "--out", out, "--quiet", "--no-frames"])
        if p.returncode != 2 or f"'{out}' exists (an earlier run?); pass --force to replace it" not in p.stderr or \
                open(os.path.join(out, "summary.json"), "rb").read() != before or p.stdout.strip():
            fail("a second run into the same folder must be refused", p)
        # --force replaces runs only: a folder of something else is never deleted.
        precious = os.path.join(tmp, "precious")
        os.makedirs(precious)
        open(os.path.join(precious, "notes.txt"), "w").write("keep me")
        p = run(sscs, root, ["simulate", arm, "--out", precious, "--quiet", "--no-frames", "--force"])
        if p.returncode != 2 or "is not a run of sscs simulate; it is never replaced, even with --force" not in p.stderr or \
                not os.path.exists(os.path.join(precious, "notes.txt")):
            fail("--force must not delete a folder that is no run", p)
        # A second run gives the same bytes, frames too; --force replaces a folder.
        again = os.path.join(tmp, "again")
        os.makedirs(again)
        run(sscs, root, ["simulate", arm, "--out", again, "--quiet", "--force"])
        for f in ["summary.json", "events.jsonl", "trajectories/Robot.csv", "objects.csv", "frames/index.csv",
                  "contact_sheet.png"] + \
                [f"frames/{f}" for f in frames]:
            if open(os.path.join(out, f), "rb").read() != open(os.path.join(again, f), "rb").read():
                fail(f"{f} differs between two runs")
        # The rerun from resolved/ gives the same bytes, and its resolved/ is the same again.
        rerun = os.path.join(tmp, "rerun")
        p = run(sscs, tmp, ["simulate", os.path.join(out, "resolved", "scenario.yaml"), "--out", rerun, "--quiet",
                            "--no-frames"])
        if p.returncode != 0:
            fail("rerun from resolved/", p)
        for f in ["events.jsonl", "trajectories/Robot.csv", "objects.csv", "resolved/vault.yaml", "resolved/scenario.yaml"]:
            if open(os.path.join(out, f), "rb").read() != open(os.path.join(rerun, f), "rb").read():
                fail(f"{f} differs between the run and its rerun from resolved/")
        resolved = sorted(os.path.relpath(os.path.join(d, f), os.path.join(out, "resolved"))
                          for d, _, fs in os.walk(os.path.join(out, "resolved")) for f in fs)
        expected = ["library/meshes/eur_pallet.ply"] + [f"library/types/{t}.yaml" for t in
                                                        ["arm6", "door", "drum", "pallet", "rack", "room"]] + ["scenario.yaml", "vault.yaml"]
        if resolved != expected:
            fail(f"resolved/ holds {resolved}, expected {expected}")
        vault = open(os.path.join(out, "resolved", "vault.yaml")).read()
        if "library: [library]\nstandard_library: false\n" not in vault or "# Type A packages" not in vault:
            fail(f"resolved/vault.yaml: {vault}")
        # Every input's sha256, checked against the files themselves.
        import hashlib
        inputs = {os.path.basename(i["path"]): i["sha256"] for i in summary["inputs"]}
        for name, path in [("arm-loads-drum.yaml", arm), ("cell.yaml", "scenarios/drum-transfer/cell.yaml"),
                           ("eur_pallet.ply", "library/meshes/eur_pallet.ply"), ("arm6.yaml", "library/types/arm6.yaml")]:
            if inputs.get(name) != hashlib.sha256(open(os.path.join(root, path), "rb").read()).hexdigest():
                fail(f"sha256 of {name} in summary.json: {inputs.get(name)}")
        # The closest approach: the carried drum swinging past the rack's end, 95 mm, at 4.88 s
        # (the rack it is set down on later counts outside the move that sets it down: the whole
        # run's approaches to it were left out, and the arm's 0.2 m to an upright was reported).
        mc = summary["min_clearance"]
        if not (0.09 < mc["distance"] < 0.1) or (mc["a"], mc["b"]) != ("Drum_1", "Rack_A") or abs(mc["t"] - 4.88) > 0.05:
            fail(f"min_clearance {mc}")
        # The logs end where the run does, off the 50 Hz rate or not (10.001 s): the glTF
        # animation and the page's player are made from them (they stopped at the last 20 ms).
        for f in ["trajectories/Robot.csv", "objects.csv"]:
            last_t = float(open(os.path.join(out, f)).read().splitlines()[-1].split(",")[0])
            if abs(last_t - summary["simulated_time"]) > 1e-9 or abs(last_t - 10.001) > 1e-9:
                fail(f"{f} ends at {last_t}, the run at {summary['simulated_time']}")
        # --bundle: the same tree in one zip, byte-identical across runs; compare reads it.
        bundles = [os.path.join(tmp, f"b{i}.zip") for i in (1, 2)]
        for b in bundles:
            p = run(sscs, root, ["simulate", arm, "--bundle", b, "--quiet", "--no-frames"])
            if p.returncode != 0 or os.path.exists(os.path.join(root, "run-arm-loads-drum")):
                fail("--bundle alone writes the bundle only", p)
        if open(bundles[0], "rb").read() != open(bundles[1], "rb").read():
            fail("two bundles of the same run differ")
        names = zipfile.ZipFile(bundles[0]).namelist()
        # With frames, the bundle holds them too, stored (PNG is compressed already).
        framed = os.path.join(tmp, "framed.zip")
        p = run(sscs, root, ["simulate", arm, "--bundle", framed, "--quiet"])
        z = zipfile.ZipFile(framed)
        pngs = [i for i in z.infolist() if i.filename.startswith("frames/frame_")]
        if p.returncode != 0 or len(pngs) != len(os.listdir(os.path.join(out, "frames"))) - 1 or any(i.compress_type != zipfile.ZIP_STORED for i in pngs) or \
                "contact_sheet.png" not in z.namelist() or \
                z.read("frames/frame_000075.png") != open(os.path.join(out, "frames", "frame_000075.png"), "rb").read():
            fail("a bundle with frames", p)
        for f in ["summary.json", "events.jsonl", "objects.csv", "trajectories/Robot.csv", "resolved/scenario.yaml"]:
            if f not in names:
                fail(f"bundle lacks {f}: {names}")
        if zipfile.ZipFile(bundles[0]).read("events.jsonl") != open(os.path.join(out, "events.jsonl"), "rb").read():
            fail("the bundle's events.jsonl differs from the folder's")
        p = run(sscs, root, ["compare", bundles[0], out, "--format", "csv"])
        rows = p.stdout.splitlines()
        if p.returncode != 0 or len(rows) != 3 or rows[1].split(",")[1:] != rows[2].split(",")[1:]:
            fail("compare of a bundle and the same run's folder", p)
        # A vault rule that reads the moving drum is re-checked during the motion: the store that
        # allows a 0.3 m lift sees a constraint event when the arm lifts it 0.4 m.
        high = os.path.join(tmp, "too-high")
        p = run(sscs, root, ["simulate", "scenarios/drum-transfer/too-high.yaml", "--out", high, "--quiet"])
        events = [json.loads(line) for line in open(os.path.join(high, "events.jsonl"))]
        hits = [e for e in events if e["kind"] == "constraint"]
        if p.returncode != 1 or "too-high: violations" not in p.stdout or len(hits) != 1 or \
                hits[0]["constraint"] != "drum within the allowed lift height" or hits[0]["subjects"] != ["Drum_1"] or \
                not -0.01 < hits[0]["margin"] < 0:
            fail(f"too-high scenario: {hits}", p)
        # The lift starts after the grasp at 1.865 s; the drum's bottom (0.144 m) passes 0.3 m
        # 0.156 m later: 0.4 s accelerating at 0.5 m/s^2 to 0.2 m/s (0.04 m), then 0.116 m at
        # 0.2 m/s (0.58 s): 2.845 s, plus up to one 20 ms log interval.
        if not 2.84 <= hits[0]["t"] <= 2.866:
            fail(f"the constraint event comes at {hits[0]['t']} s")
        # The same transfer by the gantry, then both side by side.
        gantry = os.path.join(tmp, "gantry")
        p = run(sscs, root, ["simulate", "scenarios/drum-transfer/gantry-loads-drum.yaml", "--out", gantry, "--quiet"])
        if p.returncode != 0 or "gantry-loads-drum: ok" not in p.stdout:
            fail("the gantry scenario should run ok", p)
        p = run(sscs, root, ["compare", again, gantry, "--format", "json"])
        runs = json.loads(p.stdout)["runs"]
        if p.returncode != 0 or [r["scenario"] for r in runs] != ["arm-loads-drum", "gantry-loads-drum"]:
            fail("compare --format json", p)
        arm_time, gantry_time = runs[0]["cycle_time"], runs[1]["cycle_time"]
        p = run(sscs, root, ["compare", again, gantry])
        lines = p.stdout.splitlines()
        if not lines[0].split() == [again, gantry] or not any(l.startswith("cycle time (s)") and f"{arm_time:.3f}" in l
                                                               and f"{gantry_time:.3f}" in l for l in lines):
            fail("compare text", p)
        # Joint travel per joint kind: the arm turns (deg), the gantry slides (m); never one sum.
        travel = {l.split("  ")[0].strip(): l for l in lines if "joint travel" in l}
        if sorted(travel) != ["Gantry joint travel, prismatic (m)", "Robot joint travel, revolute (deg)"]:
            fail(f"compare joint travel rows: {sorted(travel)}", p)
        p = run(sscs, root, ["compare", again, gantry, "--format", "csv"])
        rows = p.stdout.splitlines()
        if len(rows) != 3 or not rows[0].startswith("run,scenario,status,cycle time (s)"):
            fail("compare csv", p)
        # CSV is for scripts that rank runs: every digit summary.json holds, not the table's 3 decimals.
        table = list(csv.DictReader(io.StringIO(p.stdout)))
        for r, j in zip(table, runs):
            if float(r["cycle time (s)"]) != j["cycle_time"] or float(r["min clearance (m)"]) != j["min_clearance"]["distance"]:
                fail(f"compare csv numbers {r} differ from summary.json's {j['cycle_time']}, {j['min_clearance']}", p)
        if run(sscs, root, ["compare", os.path.join(tmp, "nothing")]).returncode != 2:
            fail("compare of a folder that is not a run exits 2")
        # Swinging the drum straight to the rack drags it through an upright: a collision naming
        # both objects, status violations, exit 1.
        out = os.path.join(tmp, "collision")
        p = run(sscs, root, ["simulate", "scenarios/drum-transfer/collision.yaml", "--out", out, "--quiet"])
        events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
        hits = collisions_between(events, "Drum_1", "Rack_A")
        if p.returncode != 1 or "collision: violations" not in p.stdout or not hits:
            fail(f"collision scenario: {events}", p)
        # The drum's blow pushes the wrist past its limit: link6 touches link4 (a few mm at most,
        # for a few ms). A device against itself is measured by its contacts: it read 0.2 m deep
        # (the whole arm's overlap at its joints) from 4.283 s to the run's end, and the run's
        # min_clearance was that -0.2 (a new user's review: the parts are 45 mm apart at home).
        summary = json.load(open(os.path.join(out, "summary.json")))
        for ep in summary["collisions"]:
            if ep["a"].split(".")[0] == ep["b"].split(".")[0] and (ep["depth"] > 0.005 or ep["end"] - ep["start"] > 0.1):
                fail(f"collision scenario: a self-collision episode {ep} (a touch of a few mm for a few ms)")
        if summary["min_clearance"]["distance"] < -0.01:
            fail(f"collision scenario: min_clearance {summary['min_clearance']} (the drum into the rack is millimetres)")
        # A run interrupted (SIGINT) or killed (SIGKILL) half-way leaves nothing under its name.
        import signal
        import time
        for sig in (signal.SIGINT, signal.SIGKILL):
            out = os.path.join(tmp, f"killed-{int(sig)}")
            proc = subprocess.Popen([sscs, "simulate", "scenarios/drum-transfer/long-hold.yaml", "--out", out, "--quiet"],
                                    cwd=root, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(0.5)
            proc.send_signal(sig)
            code = proc.wait(timeout=60)
            if os.path.exists(out):
                fail(f"a run stopped by signal {int(sig)} left {out}")
            if sig == signal.SIGINT and code != 130:
                fail(f"an interrupted run exits 130, not {code}")
        left = [f for f in os.listdir(tmp) if f.startswith(".") and "killed-9" not in f]
        if left:
            fail(f"an interrupted run left temporary files: {left}")
        # --wall-limit: the two simulated minutes of long-hold stop after 1 s of wall time, as a
        # failed run that says why (a wall_limit event, the last) and writes what it has.
        out = os.path.join(tmp, "wall")
        p = run(sscs, root, ["simulate", "scenarios/drum-transfer/long-hold.yaml", "--out", out, "--quiet", "--no-frames",
                             "--wall-limit", "1"])
        events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))] if p.returncode == 1 else []
        summary = json.load(open(os.path.join(out, "summary.json"))) if events else {}
        if not events or events[-1]["kind"] != "wall_limit" or events[-1]["limit"] != 1 or summary.get("status") != "failed" \
                or not 0 < events[-1]["t"] < 120 or "long-hold: failed (wall_limit at " not in p.stdout \
                or "no cycle time" not in p.stdout:
            fail(f"--wall-limit 1 on long-hold: {events[-1:]}, {summary.get('status')}", p)
        # A run that stopped has no cycle time and claims no step time it did not reach.
        stopped = summary.get("stopped", {})
        if summary.get("cycle_time") is not None or stopped.get("by") != "wall_limit" or stopped.get("t") != events[-1]["t"] \
                or summary["steps"][-1]["end"] is not None \
                or any(st[k] is not None and st[k] > summary["simulated_time"] + 1e-6 for st in summary["steps"] for k in ("start", "end")):
            fail(f"a stopped run's summary: {summary}")
        p = run(sscs, root, ["compare", out, "--format", "csv"])
        if p.returncode != 0 or "cycle time" not in p.stdout:
            fail("compare reads a stopped run (no cycle time)", p)
        p = run(sscs, root, ["simulate", "scenarios/drum-transfer/long-hold.yaml", "--out", out + "0", "--wall-limit", "0"])
        if p.returncode != 2 or "--wall-limit" not in p.stderr:
            fail("--wall-limit 0 is a usage error", p)
        # A killed run cannot clean up its hidden work folder; the next run to that name does.
        run(sscs, root, ["simulate", "scenarios/drum-transfer/unreachable.yaml", "--out", os.path.join(tmp, "killed-9"),
                         "--quiet"])
        left = [f for f in os.listdir(tmp) if f.startswith(".")]
        if left:
            fail(f"the killed run's work folder is still there: {left}")
        shutil.rmtree(os.path.join(tmp, "killed-9"))
        # An unreachable target fails the run promptly, exit 1, with the event.
        out = os.path.join(tmp, "unreachable")
        p = run(sscs, root, ["simulate", "scenarios/drum-transfer/unreachable.yaml", "--out", out, "--quiet"])
        events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
        bad = [e for e in events if e["kind"] == "unreachable"]
        if p.returncode != 1 or "unreachable: failed" not in p.stdout or len(bad) != 1 or bad[0]["step"] != 1:
            fail(f"unreachable scenario: {events}", p)
    print("ok simulate")


def collisions_between(events, a, b):
    """The collision events of a run between a and b (either way round)."""
    return [e for e in events if e["kind"] == "collision" and {e["a"], e["b"]} == {a, b}]


def last_rows(run_dir):
    """{object: [x, y, z, roll, pitch, yaw]} of each object's last row in a run's objects.csv."""
    last = {}
    for row in open(os.path.join(run_dir, "objects.csv")).read().splitlines()[1:]:
        cols = row.split(",")
        last[cols[1]] = [float(x) for x in cols[2:8]]
    return last


def last_positions(run_dir):
    """{object: [x, y, z]} of each object's last row in a run's objects.csv."""
    return {o: row[:3] for o, row in last_rows(run_dir).items()}


# The standard loads a gantry lifts in the `loads` sweep: type, attributes, the frame the tool
# takes it by, the middle of its top (from its origin), the half sizes of the top riders may
# stand on (a radius for a drum), its top's height, and its footprint's half sizes.
LOADS = [
    ("drum", "", "top", (0, 0), 0.286, 0.851, (0.286, 0.286)),
    ("drum_hooped", "", "top", (0, 0), 0.286, 0.851, (0.30, 0.30)),
    ("pallet", "", "top", (0.6, 0.4), (0.6, 0.4), 0.144, (0.6, 0.4)),
    ("cart", "", "deck", (0.6095, 0.305), (0.6095, 0.305), 0.229, (0.6095, 0.305)),
    ("shelf", ", height: 1.0", "top", (0.457, 0.2285), (0.457, 0.2285), 1.0, (0.457, 0.2285)),
]


def load_cases(rnd):
    """(label, vault, scenario, riders, top_z, x0, y0, yb) of every standard load a gantry lifts,
    carries 0.8 m and sets down, two random configurations each (the `loads` test's)."""
    cases = []
    for name, attrs, frame, mid, top, top_z, half in LOADS:
        for n in range(2):
            x0, y0 = 2.5 - mid[0], 2.0 - mid[1]  # the load's origin: its middle at (2.5, 2.0)
            riders = []
            for k in range(rnd.choice([1, 2])):
                for _ in range(1000):  # a place on the top, clear of the 0.3 m gripper plate and the other riders
                    if isinstance(top, float):  # a round top: near an axis, or the plate covers it
                        a = rnd.choice([0, 0.5, 1, 1.5]) * math.pi + rnd.uniform(-0.4, 0.4)
                        r = rnd.uniform(0.21 / math.cos(abs(a - round(a / (math.pi / 2)) * math.pi / 2)), top - 0.05)
                        dx, dy = r * math.cos(a), r * math.sin(a)
                    else:
                        dx, dy = rnd.uniform(-top[0] + 0.05, top[0] - 0.05), rnd.uniform(-top[1] + 0.05, top[1] - 0.05)
                    if name == "cart" and dx < -top[0] + 0.1:
                        continue  # the handle
                    if name == "pallet":  # on a deck board (0.1 m wide, 0.175 m apart): over a gap a drum tips in
                        dx = rnd.choice([-0.55, -0.275, 0, 0.275, 0.55]) + rnd.uniform(-0.03, 0.03)
                    if max(abs(dx), abs(dy)) > 0.21 and all(math.hypot(dx - ox, dy - oy) > 0.11 for ox, oy in riders):
                        riders.append((dx, dy))
                        break
            side_gap = rnd.choice([0.0005, 0.02])
            yb = round(2.0 - half[1] - 0.15 - side_gap, 4)
            lines = ["sscs: 1", f"vault: Loads_{name}_{n}", "objects:",
                     "  - {type: room, name: Hall, length: 8, width: 6, height: 4}",
                     "  - {type: gantry, name: G, parent: Hall, location: [0.5, 0.5, 0]}",
                     f"  - {{type: {name}, name: L, parent: Hall, location: [{x0}, {y0}, 0]{attrs}}}",
                     f"  - {{type: drum, name: Beside, parent: Hall, location: [2.5, {yb}, 0], "
                     "diameter: 0.3, height: 0.4, tare_mass: 5}"]
            for k, (dx, dy) in enumerate(riders):
                if rnd.random() < 0.5:
                    where = f"parent: L, location: [{mid[0] + dx:.4f}, {mid[1] + dy:.4f}, {top_z}]"
                else:
                    where = f"parent: Hall, location: [{2.5 + dx:.4f}, {2.0 + dy:.4f}, {top_z}]"
                lines.append(f"  - {{type: drum, name: R{k}, {where}, diameter: 0.1, height: 0.2, tare_mass: 2}}")
            down = "rpy: [180, 0, 0]"
            steps = [f"  - {{device: G, move_to: {{target: L.{frame}, offset: {{xyz: [0, 0, 0.3], {down}}}}}}}",
                     f"  - {{device: G, move_to: {{target: L.{frame}, offset: {{{down}}}}}, path: linear, speed: 0.2 m/s}}",
                     "  - {device: G, grasp: L}",
                     f"  - {{device: G, move_to: {{target: {{xyz: [2.5, 2.0, {top_z + 0.3}], {down}}}}}, path: linear, speed: 0.2 m/s}}",
                     f"  - {{device: G, move_to: {{target: {{xyz: [3.3, 2.0, {top_z + 0.3}], {down}}}}}, path: linear, speed: 0.3 m/s}}",
                     f"  - {{device: G, move_to: {{target: {{xyz: [3.3, 2.0, {top_z}], {down}}}}}, path: linear, speed: 0.2 m/s}}",
                     "  - {device: G, release: {}}",
                     f"  - {{device: G, move_to: {{target: {{xyz: [3.3, 2.0, {top_z + 0.3}], {down}}}}}, path: linear, speed: 0.2 m/s}}"]
            scenario = ["sscs: 1", f"scenario: lift-{name}-{n}", "vault: vault.yaml", "sim: {timestep: 1 ms, limit: 60 s}",
                        "steps:", *steps]
            cases.append((f"{name}-{n}", "\n".join(lines) + "\n", "\n".join(scenario) + "\n", riders, top_z, x0, y0, yb))
    return cases


def loads(sscs, root):
    """Every standard load a gantry lifts, carries 0.8 m and sets down, with small drums standing
    on it at random places (parented to the load or to the hall: riders are what stands on it)
    and a drum beside it (touching or not: no rider). The run is ok, the riders arrive where they
    stood on the load (within 5 mm), the drum beside it stays, and nothing collides, shifts or is
    displaced. Random configurations from a fixed seed, two per load."""
    cases = load_cases(random.Random(19))
    with tempfile.TemporaryDirectory() as tmp:
        def one(case):
            label = case[0]
            vault, scenario = case[1], case[2]
            d = os.path.join(tmp, label)
            os.makedirs(d)
            open(os.path.join(d, "vault.yaml"), "w").write(vault)
            open(os.path.join(d, "scenario.yaml"), "w").write(scenario)
            p = run(sscs, root, ["simulate", os.path.join(d, "scenario.yaml"), "--out", os.path.join(d, "run"), "--quiet"])
            return case, p
        with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            results = list(pool.map(one, cases))
        for (label, vault, scenario, riders, top_z, x0, y0, yb), p in results:
            out = os.path.join(tmp, label, "run")
            where = f"{label}:\n{vault}\n{scenario}"
            if not os.path.exists(os.path.join(out, "summary.json")):
                fail(f"{where}no run", p)
            summary = json.load(open(os.path.join(out, "summary.json")))
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            bad = [e for e in events if e["kind"] in ("collision", "displaced", "load_shifted", "not_at_rest", "grasp_missed",
                                                      "tracking_error", "unreachable", "constraint")]
            if p.returncode != 0 or summary["status"] != "ok" or bad:
                fail(f"{where}the lift must run ok: {bad or events}", p)
            last = last_positions(out)
            for k, (dx, dy) in enumerate(riders):
                want = [3.3 + dx, 2.0 + dy, top_z]
                got = last.get(f"R{k}")
                if got is None or math.dist(got, want) > 0.005:
                    fail(f"{where}R{k} must arrive on the load at {want}, is at {got}", p)
            if "Beside" in last and math.dist(last["Beside"], [2.5, yb, 0]) > 1e-3:
                fail(f"{where}the drum beside the load must stay: {last['Beside']}", p)
            got = last.get("L")
            if got is None or math.dist(got, [x0 + 0.8, y0, 0]) > 0.005:
                fail(f"{where}the load must be set down at {[x0 + 0.8, y0, 0]}, is at {got}", p)


def agreement(sscs, root):
    """check and simulate agree where a new user found them apart (tests/data/agreement): a
    pedestal an arm stands on is a solid to both, forks pushed into a pallet's blocks fail reach
    and collide in the run (the first touch under 1 mm hid the rest), min_clearance follows the
    deepest penetration, a drum on a lifted pallet rides on it, a pallet and its hooped drum
    (meshes) set down rest where they were, and a drum that rolls off is no `ok`."""
    data = "tests/data/agreement"
    p = run(sscs, root, ["check", f"{data}/pedestal.yaml"])
    if p.returncode != 1 or "Robot reaches [5, 4.6, 0.5] only in collision: part link6 hits Ped by 0.2 m" not in p.stdout:
        fail("reach into the arm's own pedestal must fail", p)
    p = run(sscs, root, ["check", f"{data}/forks.yaml"])
    if p.returncode != 1 or "1 passed, 1 failed" not in p.stdout or \
            "Truck reaches P.fork_pockets only with its tool inside P: part carriage enters it by 0.039 m" not in p.stdout:
        fail("forks from the long side pass, from the short side fail", p)
    with tempfile.TemporaryDirectory() as tmp:
        def events_of(name):
            out = os.path.join(tmp, name)
            p = run(sscs, root, ["simulate", f"{data}/{name}.yaml", "--out", out, "--quiet"])
            summary = json.load(open(os.path.join(out, "summary.json")))
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            return p, summary, events, out

        def must_collide(name, a, b, what):
            """Scenario `name` ends with violations and a collision between a and b."""
            p, summary, events, _ = events_of(name)
            if p.returncode != 1 or not collisions_between(events, a, b):
                fail(f"{name}: {what}: {events}", p)
        # A drum released 0.2 m above the deck falls onto it: no set-down (it landed, came to
        # rest, and the run said ok).
        p, summary, events, _ = events_of("drop")
        shown = [e for e in events if e["kind"] == "displaced" and e["object"] == "D"]
        if p.returncode != 1 or summary["status"] != "violations" or len(shown) != 1 or abs(shown[0]["fall"] - 0.205) > 0.005:
            fail(f"the drum dropped 0.2 m must be displaced: {events}", p)
        # A drum leaning on the tool past its tipping angle falls when the tool draws back
        # (ODE had put it to sleep while the tool held it up: it stood at -30 deg, run ok).
        p, summary, events, out = events_of("lean-retreat")
        shown = [e for e in events if e["kind"] == "displaced" and e["object"] == "D"]
        if p.returncode != 1 or not shown or abs(abs(last_rows(out)["D"][3]) - 90) > 1:
            fail(f"the leaning drum must fall when the tool draws back: {events}", p)
        # A run that ends with a released object held up by a device is no set-down: a drum
        # leaning on the tool past its tipping angle, a pallet on forks left at its pockets' ceiling.
        for name, obj, by in [("lean-held", "D", "Robot"), ("forks-left-under", "P", "Truck")]:
            p, summary, events, _ = events_of(name)
            shown = [e for e in events if e["kind"] == "propped" and e["object"] == obj and e["by"] == by]
            if p.returncode != 1 or summary["status"] != "violations" or not shown:
                fail(f"{name}: {obj} is propped by {by} at the end: {events}", p)
        p, summary, events, _ = events_of("pedestal-dive")
        hits = collisions_between(events, "Ped", "Robot.link6")
        if p.returncode != 1 or summary["status"] != "violations" or not hits:
            fail(f"the arm diving into its pedestal must collide: {events}", p)
        p, summary, events, _ = events_of("forks-short-side")
        hits = collisions_between(events, "P", "Truck.carriage")
        if p.returncode != 1 or not hits or summary["min_clearance"]["distance"] > -0.035:
            fail(f"forks into the blocks must collide, min_clearance about -0.039: {summary['min_clearance']} {events}", p)
        p, summary, events, out = events_of("forks-lift")
        if p.returncode != 0 or summary["status"] != "ok" or any(e["kind"] == "collision" for e in events):
            fail(f"lifting a pallet with a drum on it runs ok: {events}", p)
        last = last_positions(out)
        if abs(last["P"][2] - 0.5) > 0.005 or abs(last["D"][2] - 0.644) > 0.005:
            fail(f"the drum rides on the lifted pallet (P z 0.5, D z 0.644): {last}")
        # Mesh on mesh (a hooped drum on the pallet's boards): set down and released, both rest
        # where they stood; the drum used to walk and turn (54 deg) and never rest, and the
        # pallet "landed" on its own drum.
        p, summary, events, out = events_of("forks-set-down")
        rest = {e["object"]: e["position"] for e in events if e["kind"] == "at_rest"}
        landed = [(e["object"], e["on"]) for e in events if e["kind"] == "landed"]
        if p.returncode != 0 or summary["status"] != "ok" or landed != [("P", "floor")] or set(rest) != {"D", "P"} or \
                max(abs(a - b) for a, b in zip(rest["D"], [8.6, 8.4, 0.144])) > 0.002 or \
                max(abs(a - b) for a, b in zip(rest["P"], [8.0, 8.0, 0.0])) > 0.002:
            fail(f"the pallet and its hooped drum rest where they were set down: {events}", p)
        # A drum lying on its side rolls off the pallet the truck drives away: it moved on its
        # load (load_shifted), fell (a collision: it rode on a carried load) and still rolls
        # 5 s after the last step (not_at_rest): violations, not ok.
        p, summary, events, out = events_of("roll-carry")
        kinds = [e["kind"] for e in events]
        shifted = [e for e in events if e["kind"] == "load_shifted"]
        if p.returncode != 1 or summary["status"] != "violations" or "not_at_rest" not in kinds or len(shifted) != 1 or \
                shifted[0]["object"] != "D" or shifted[0]["on"] != "P" or shifted[0]["shift"] < 1:
            fail(f"the drum rolling off the driven pallet is load_shifted and not_at_rest: {events}", p)
        # A drum standing on the pallet whose parent is the hall rides along too (it stayed in the
        # air), and the vault's lift rule is re-checked on it (riders were not re-checked).
        p, summary, events, out = events_of("stand-on-lift")
        rules = [e for e in events if e["kind"] == "constraint"]
        last = last_positions(out)
        if p.returncode != 1 or len(rules) != 1 or rules[0]["subjects"] != ["D"] or any(e["kind"] == "collision" for e in events) or \
                max(abs(a - b) for a, b in zip(last.get("D", [0, 0, 0]), [8.6, 4.12, 0.444])) > 0.002:
            fail(f"the drum standing on the pallet rides to (8.6, 4.12, 0.444) and breaks the lift rule: {last} {events}", p)
        if "Far" in last or any(e["kind"] == "load_shifted" for e in events):
            fail(f"the pallet's child standing 2.4 m from it is no rider: {events}", p)
        # Its closest approach is the carriage under the drum's rim (about 0.042 m), not the
        # truck's body 0.625 m into the drum (a stretch halved after the drum had ridden away,
        # where it was by then; review 22).
        mc = summary["min_clearance"]
        if not 0.03 < mc["distance"] < 0.05 or {mc["a"], mc["b"]} != {"Truck.carriage", "D"}:
            fail(f"stand-on-lift: min_clearance about 0.042 m, carriage to drum: {mc}", p)
        # The arm picks the drum where the truck set its pallet down (planning moves what stands
        # on a carried load with it: the arm went to where the drum stood in the vault, 1 m off,
        # and lifted it from there).
        p, summary, events, out = events_of("handover-pick")
        last = last_positions(out)
        tool = [float(x) for x in open(os.path.join(out, "trajectories", "Robot.csv")).read().splitlines()[-1].split(",")[7:10]]
        if p.returncode != 0 or max(abs(a - b) for a, b in zip(tool, [9.6, 8.4, 0.844])) > 0.002 or \
                max(abs(a - b) for a, b in zip(last["D"], [9.6, 8.4, 0.444])) > 0.002:
            fail(f"the arm lifts the drum where the pallet was set down: tool {tool}, D {last.get('D')}", p)
        # A pallet on a pallet (meshes face to face) with a drum on a drum (one axis) on it, the
        # bottom pallet lifted 0.3 m: everything rides (the top pallet flew off at 41 m/s, and
        # the coaxial drums aborted ODE with exit 134).
        p, summary, events, out = events_of("stacked-lift")
        last = last_positions(out)
        expected = {"P2": [8.0, 8.0, 0.444], "D1": [8.9, 8.4, 0.588], "D2": [8.9, 8.4, 1.439]}
        # (Within 5 mm, load_shifted's threshold: two pallets face to face, mesh on mesh, slide
        # by about 3 mm in ODE's contacts.)
        if p.returncode != 0 or any(max(abs(a - b) for a, b in zip(last.get(o, [0, 0, 0]), at)) > 0.005 for o, at in expected.items()):
            fail(f"the stack rides on the lifted pallet: {last} {events}", p)
        # What a lifted load's stack shows: min_clearance is no longer the drum resting on its own
        # pallet (-1.6e-6 m for every lifted pallet, hiding the drum passing under a beam).
        p, summary, events, out = events_of("beam-pass")
        near = summary["min_clearance"]
        if near is None or {near["a"], near["b"]} == {"P", "D"} or near["distance"] <= 0:
            fail(f"min_clearance is no overlap of the drum with its own pallet: {near}", p)
        under = [e for e in events if e["kind"] == "constraint" and e["subjects"] == ["D", "Beam"]]
        if p.returncode != 1 or len(under) != 1:
            fail(f"the drum riding under the beam breaks its clearance rule: {events}", p)
        # Only what stands on a load rides: not a drum beside it on a pallet of its own (a false
        # collision and a 0.3 m load_shifted; nor a child of the pallet standing 2.4 m from it:
        # stand-on-lift above).
        p, summary, events, out = events_of("neighbours-lift")
        if p.returncode != 0 or summary["status"] != "ok" or "D2" in last_positions(out):
            fail(f"the drum beside the lifted one stays put and is no rider: {events}", p)
        # A rider picked off the lifted load by another device rides no more (load_shifted 1.3 m).
        p, summary, events, out = events_of("pick-off-lifted")
        if p.returncode != 0 or any(e["kind"] == "load_shifted" for e in events):
            fail(f"the drum picked off the lifted pallet is no shifted load: {events}", p)
        # Set down on a tray another arm holds: it lands there and rides (it was a collision).
        p, summary, events, out = events_of("onto-held-tray")
        landed = [(e["object"], e["on"]) for e in events if e["kind"] == "landed"]
        if p.returncode != 0 or landed != [("D", "T")] or any(e["kind"] == "collision" for e in events) or \
                (summary["min_clearance"] or {"distance": 1})["distance"] < 0:
            fail(f"the drum set down on the held tray lands on it: {summary['min_clearance']} {events}", p)
        # A tool held back short of its object: the grasp says so, not that the object moved.
        p, summary, events, out = events_of("blocked-grasp")
        missed = [e for e in events if e["kind"] == "grasp_missed"]
        if summary["status"] != "failed" or len(missed) != 1 or "something held it back" not in missed[0]["message"]:
            fail(f"the blocked tool's grasp_missed says the tool was held back: {events}", p)
        # Lifting a drum straight off a rack's deck is no collision (the rack, rising far above the
        # drum's bottom, was not taken for its support); pushing it into the rack's upright after
        # setting it down there is one (the whole rack had become its support: ok).
        p, summary, events, out = events_of("rack-lift")
        if p.returncode != 0 or any(e["kind"] == "collision" for e in events):
            fail(f"the drum lifted off the rack deck runs ok: {events}", p)
        must_collide("rack-place-drag", "R", "D", "the drum pushed into the rack's upright collides")
        # A drum beside a tray turned 45 deg is no rider of it.
        p, summary, events, out = events_of("turned-tray-lift")
        if p.returncode != 0 or "D2" in last_positions(out):
            fail(f"the drum beside the turned tray stays put: {events}", p)
        # Set on the pallet a truck holds, then picked where the truck took it (planning left it
        # where it was released, and the grasp missed by 0.15 m).
        p, summary, events, out = events_of("set-on-carried")
        if p.returncode != 0 or any(e["kind"] in ("grasp_missed", "collision") for e in events):
            fail(f"the drum set on the carried pallet is picked where it rode to: {events}", p)
        # Forks backing out of a pallet they set down drag it: a collision once it has moved 5 mm
        # sideways since its release (the excused touch of a released load hid a 127 mm drag).
        must_collide("forks-drag-released", "P", "Truck.carriage", "the forks dragging the released pallet collide")
        # A release on a trajectory sample: min_clearance is no gripper inside the drum it lets go.
        p, summary, events, out = events_of("shelf-to-pallet-run")
        near = summary["min_clearance"]
        if p.returncode != 0 or near is None or near["distance"] < 0:
            fail(f"min_clearance at a release is no overlap of the gripper and its drum: {near}", p)
        # A grasp where the object no longer is (it fell when released) fails the run; it held
        # the drum 0.4 m below the gripper and said ok.
        p, summary, events, out = events_of("regrasp-fallen")
        missed = [e for e in events if e["kind"] == "grasp_missed"]
        if p.returncode != 1 or summary["status"] != "failed" or len(missed) != 1 or abs(missed[0]["distance"] - 0.4) > 0.005:
            fail(f"grasping the fallen drum from 0.4 m above is grasp_missed: {events}", p)


def read_png(path):
    """(width, height, rows of RGB bytes) of an 8-bit RGB PNG, without third-party modules."""
    import struct
    import zlib
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(f"{path} is not a PNG")
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, color = struct.unpack(">IIBB", body[:10])
            if depth != 8 or color != 2:
                fail(f"{path}: expected 8-bit RGB, found depth {depth} colour type {color}")
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), w * 3, [], bytearray(w * 3)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 3] if i >= 3 else 0
            b, c = prev[i], prev[i - 3] if i >= 3 else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, rows


def write_png(path, w, h, rows):
    import struct
    import zlib
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff)
    raw = b"".join(b"\x00" + r for r in rows)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                           chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def compare_image(path, golden_path, threshold=2.0):
    """Mean absolute difference per channel (0-255) below `threshold`; on failure a diff image
    (differences x4) is written beside the output and named in the message."""
    if os.environ.get("SSCS_UPDATE_GOLDEN") and "/tests/golden/" in golden_path:
        shutil.copyfile(path, golden_path)
        return
    w, h, got = read_png(path)
    gw, gh, want = read_png(golden_path)
    if (w, h) != (gw, gh):
        fail(f"{path} is {w}x{h}, the golden {golden_path} {gw}x{gh}")
    total = sum(abs(a - b) for r1, r2 in zip(got, want) for a, b in zip(r1, r2))
    mad = total / (w * h * 3)
    if mad >= threshold:
        diff = os.path.join(os.environ.get("TMPDIR", "/tmp"), os.path.basename(golden_path).replace(".png", "-diff.png"))
        write_png(diff, w, h, [bytes(min(255, 4 * abs(a - b)) for a, b in zip(r1, r2)) for r1, r2 in zip(got, want)])
        fail(f"{path} differs from {golden_path}: mean absolute difference {mad:.2f} >= {threshold} (diff: {diff})")


def catalogue(sscs, root):
    """docs/library.md and docs/img/library/ are what `sscs types --format md` makes of the
    standard library now: the text byte for byte, the same thumbnails (each within the render
    tolerance), none missing and none left over. --format md needs --out, a .md one."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "library.md")
        p = run(sscs, root, ["types", "--format", "md", "--out", out], env={"DISPLAY": ""})
        if p.returncode != 0:
            fail("sscs types --format md", p)
        committed = os.path.join(root, "docs/library.md")
        if open(out).read() != open(committed).read():
            import difflib
            diff = "".join(list(difflib.unified_diff(open(committed).readlines(), open(out).readlines(), "docs/library.md", "fresh"))[:40])
            fail(f"docs/library.md is not what sscs makes of the library now; run `sscs types --format md --out docs/library.md`:\n{diff}")
        fresh = sorted(os.listdir(os.path.join(tmp, "img", "library")))
        kept = sorted(os.listdir(os.path.join(root, "docs/img/library")))
        if fresh != kept:
            fail(f"docs/img/library holds {sorted(set(kept) - set(fresh))} that the catalogue no longer draws and lacks {sorted(set(fresh) - set(kept))}")
        for name in fresh:
            compare_image(os.path.join(tmp, "img", "library", name), os.path.join(root, "docs/img/library", name), threshold=1.0)
        for args, says in ((["types", "--format", "md"], "give --out FILE.md"), (["types", "--out", out], "--out is for --format md"),
                           (["types", "--format", "md", "--out", os.path.join(tmp, "x.txt")], "--out expects a .md file")):
            p = run(sscs, root, args)
            if p.returncode != 2 or says not in p.stderr:
                fail(f"sscs {' '.join(args)} should exit 2 saying '{says}'", p)
    print("catalogue: docs/library.md and its thumbnails are current")


def drum_store(sscs, root):
    """The reference store (scenarios/drum-store), built only from the standard library: every
    rule holds (the crane over all 48 top positions and onto every top-level drum); the crane's
    run stores the inbound drum on Row_2's free top position, where it lands and rests; the
    capacity sweep passes exactly the layouts that keep the rules, and counts the drums."""
    import csv, json, tempfile
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "store.json")
        p = run(sscs, root, ["check", "scenarios/drum-store/store.yaml", "--format", "json", "--out", report])
        if p.returncode != 0:
            fail("the reference store should pass every rule", p)
        results = json.load(open(report))["results"]
        if len(results) != 12 or any(r["status"] != "pass" for r in results):
            fail(f"the reference store's 12 rules: {[(r['constraint'], r['status']) for r in results]}")
        for r in results:
            if r["constraint"].startswith("the crane") and "reach" in r["message"] and "all 48 targets" not in r["message"]:
                fail(f"{r['constraint']} should reach all 48 top-level positions: {r['message']}")
        # A door larger than its opening meets the wall even rolled up (its guides stand in the opening).
        p = run(sscs, root, ["check", "tests/data/doors/open-door-too-big.yaml"])
        if p.returncode != 1 or "W and Big overlap" not in p.stdout:
            fail("a rolled-up door larger than its opening should overlap the wall", p)
        # Five levels put the top drums above what the hook clears: the crane rule fails.
        p = run(sscs, root, ["check", "scenarios/drum-store/store.yaml", "--set", "levels=5"])
        if p.returncode != 1 or "the crane reaches every rack position from above" not in p.stdout:
            fail("a five-level store should fail the crane's rule", p)
        out = os.path.join(tmp, "run")
        p = run(sscs, root, ["simulate", "scenarios/drum-store/store-drum.yaml", "--out", out, "--no-frames", "--quiet"])
        summary = json.load(open(os.path.join(out, "summary.json"))) if os.path.exists(os.path.join(out, "summary.json")) else {}
        if p.returncode != 0 or summary.get("status") != "ok" or summary.get("events", {}).get("collision", 0) != 0:
            fail(f"the crane's run should be ok without collisions: {summary}", p)
        events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
        landed = [e for e in events if e["kind"] == "landed" and e["object"] == "Inbound"]
        rest = [e for e in events if e["kind"] == "at_rest" and e["object"] == "Inbound"]
        if not landed or landed[-1]["on"] != "Row_2" or not rest:
            fail(f"Inbound should land on Row_2 and rest: {landed} {rest}")
        # Row_2.top_5: Row_2 faces +x with its front at x = 10 + 2*0.61 + 0.15, 0.61 deep; its run
        # starts at y = 1.55, position 5 is the 2nd of bay 2 (3 to a 2.134 m bay, 0.076 m uprights);
        # the top (3rd) level's beams are at 0.15 + 2*1.27 m.
        want = [10 + 2 * 0.61 + 0.15 - 0.305, 1.55 + 0.076 + (2.134 + 0.076) + 1.5 * 2.134 / 3, 0.15 + 2 * 1.27]
        got = rest[-1]["position"]
        if max(abs(a - b) for a, b in zip(got, want)) > 0.003:
            fail(f"Inbound rests at {got}, not on Row_2.top_5 at {want}")
        # The capacity sweep on each rule's two sides (aisle 2.8 | 3.2 m, rows 6 | 8, levels 4 | 5):
        # 8 of its 36 variants (the whole study takes a minute of CPU; run-demo.sh runs it).
        sweep = os.path.join(tmp, "sweep")
        text = open(os.path.join(root, "scenarios/drum-store/capacity.yaml")).read()
        for whole, part in (("[2.8 m, 3.2 m, 3.6 m]", "[2.8 m, 3.2 m]"), ("[2, 4, 6, 8]", "[6, 8]"), ("[3, 4, 5]", "[4, 5]")):
            if whole not in text:
                fail(f"scenarios/drum-store/capacity.yaml no longer varies {whole}: update this test")
            text = text.replace(whole, part)
        if "vault: store.yaml" not in text:
            fail("scenarios/drum-store/capacity.yaml no longer names vault: store.yaml: update this test")
        path = os.path.join(tmp, "capacity.yaml")
        open(path, "w").write(text.replace("vault: store.yaml", f"vault: {root}/scenarios/drum-store/store.yaml"))
        p = run(sscs, root, ["sweep", path, "--out", sweep, "--jobs", "2", "--quiet", "--allow-outside-root"])
        rows = list(csv.DictReader(open(os.path.join(sweep, "results.csv"))))
        if len(rows) != 8:
            fail(f"the capacity sweep should have 8 variants, found {len(rows)}", p)
        for r in rows:
            aisle, n, levels = float(r["aisle"]), int(r["rows"]), int(r["levels"])
            keeps = aisle >= 3.2 and n <= 6 and levels <= 4
            if (r["status"] == "pass") != keeps:
                fail(f"variant {r['folder']} is {r['status']}; the rules say it should {'pass' if keeps else 'fail'}: {r}")
            if int(r["drums"]) != n * 4 * 3 * levels:  # rows x bays x positions x levels, one free, Inbound
                fail(f"variant {r['folder']} counts {r['drums']} drums, not {n * 4 * 3 * levels}")
    print("drum_store: the reference store keeps its rules, the crane stores a drum on the top level, the sweep counts")


def zones(sscs, root):
    """A keep-out zone (tests/data/zones): reach into it fails naming it, over it passes; a run
    carrying a drum through it reports keep_out events (the load and the parts that entered) and
    ends in violations; the drum set down beyond it lands on the floor."""
    import json, tempfile
    p = run(sscs, root, ["check", "tests/data/zones/cell.yaml"])
    if p.returncode != 1 or "1 passed, 1 failed" not in p.stdout or "part gripper hits Walkway" not in p.stdout:
        fail("reach into the walkway should fail naming it, over it pass", p)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run")
        p = run(sscs, root, ["simulate", "tests/data/zones/through.yaml", "--out", out, "--no-frames", "--quiet"])
        summary = json.load(open(os.path.join(out, "summary.json")))
        if p.returncode != 1 or summary["status"] != "violations":
            fail(f"a run through a keep-out zone should end in violations: {summary.get('status')}", p)
        events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
        by = {e["by"] for e in events if e["kind"] == "keep_out" and e["zone"] == "Walkway"}
        if "Drum_1" not in by or "Gantry.gripper" not in by:
            fail(f"keep_out events should name the carried drum and the gripper: {by}")
        if not any(e["kind"] == "landed" and e["object"] == "Drum_1" and e["on"] == "floor" for e in events):
            fail("the drum set down beyond the walkway should land on the floor")
    print("zones: reach and runs keep out of guard zones")


def render(sscs, root):
    """sscs render: a still of the demo vault against its golden image, with no display; the
    same still twice; a missing OSMesa is exit 3 with nothing written."""
    import tempfile
    env = {"DISPLAY": ""}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "demo.png")
        p = run(sscs, root, ["render", "scenarios/demo/demo.yaml", "--out", out, "--size", "480x270"], env=env)
        if p.returncode != 0 or "wrote" not in p.stdout:
            fail("render of the demo vault", p)
        compare_image(out, os.path.join(root, "tests/golden/demo_render.png"))
        again = os.path.join(tmp, "again.png")
        run(sscs, root, ["render", "scenarios/demo/demo.yaml", "--out", again, "--size", "480x270"], env=env)
        if open(out, "rb").read() != open(again, "rb").read():
            fail("two renders of the same vault differ")
        # An explicit camera: the cell from above looks different from the default view.
        top = os.path.join(tmp, "top.png")
        p = run(sscs, root, ["render", "scenarios/drum-transfer/cell.yaml", "--out", top, "--size", "320x240",
                             "--eye", "5,4,15", "--target", "5,4,0", "--fov", "60"], env=env)
        if p.returncode != 0 or read_png(top)[:2] != (320, 240):
            fail("render with --eye/--target/--fov/--size", p)
        # --shadows darkens what the key light cannot reach, and stays repeatable.
        shadowed = [os.path.join(tmp, f"shadows{i}.png") for i in (1, 2)]
        for f in shadowed:
            p = run(sscs, root, ["render", "scenarios/demo/demo.yaml", "--out", f, "--size", "480x270", "--shadows"], env=env)
            if p.returncode != 0:
                fail("render --shadows", p)
        if open(shadowed[0], "rb").read() != open(shadowed[1], "rb").read():
            fail("two renders with shadows differ")
        light = sum(sum(r) for r in read_png(out)[2])
        dark = sum(sum(r) for r in read_png(shadowed[0])[2])
        if not dark < 0.995 * light:  # measured 0.991: the shadows of racks, drums and gantry
            fail(f"shadows should darken the image: {dark} vs {light}")
        # A named camera of the vault: the orbit around the robot, not the default view.
        named = os.path.join(tmp, "robot.png")
        p = run(sscs, root, ["render", "scenarios/demo/demo.yaml", "--out", named, "--size", "480x270", "--camera", "robot"],
                env=env)
        if p.returncode != 0 or "eye [10.02, -1.92, 3.44], target [11.70, 2.70, 0.00], fov 45" not in p.stdout or \
                read_png(named)[2] == read_png(out)[2]:
            fail("render --camera robot", p)
        # See-through walls: the store's default view looks through its front and end walls (and
        # the doors in them) at the racks of drums (green) its solid front wall hides; --walls
        # solid keeps them.
        store = "scenarios/drum-store/store.yaml"
        see, solid = os.path.join(tmp, "see.png"), os.path.join(tmp, "solid.png")
        p = run(sscs, root, ["render", store, "--out", see, "--size", "480x270"], env=env)
        if p.returncode != 0 or not p.stdout.rstrip().endswith("fov 45, see-through: EndWall, TruckDoor, FrontWall, ManDoor)"):
            fail("render of the store: its two near walls and their doors see-through by default", p)
        p = run(sscs, root, ["render", store, "--out", solid, "--size", "480x270", "--walls", "solid"], env=env)
        if p.returncode != 0 or "see-through" in p.stdout:
            fail("render --walls solid", p)
        def greenish(path):  # the stored drums (dark green), also seen through a wall's grey
            return sum(1 for row in read_png(path)[2] for k in range(0, len(row), 3)
                       if row[k + 1] > row[k] + 8 and row[k + 1] > row[k + 2] + 8)
        changed = sum(1 for a, b in zip(read_png(see)[2], read_png(solid)[2]) for k in range(len(a)) if abs(a[k] - b[k]) > 30)
        if not greenish(see) > 2 * greenish(solid) or changed < 0.05 * 480 * 270 * 3:
            fail(f"the drums behind the store's front wall: {greenish(see)} green pixels see-through, {greenish(solid)} "
                 f"solid; {changed} channels changed")
        p = run(sscs, root, ["render", store, "--out", solid, "--walls", "glass"], env=env)
        if p.returncode != 2 or "--walls" not in p.stderr:
            fail("render --walls glass: an input error naming the option", p)
        missing = os.path.join(tmp, "missing.png")
        p = run(sscs, root, ["render", "scenarios/demo/demo.yaml", "--out", missing],
                env=dict(env, SSCS_OSMESA="/nonexistent/libOSMesa.so"))
        if p.returncode != 3 or "rendering needs OSMesa" not in p.stderr or os.path.exists(missing):
            fail("a missing OSMesa: exit 3 with a clear message", p)
    print("ok render")


def solid_angle_at_centre_unit(pitch, n=120):
    """The total solid angle (sr) the other drums of scenarios/fissile-store subtend at the centre
    of Drum_2_3, by midpoint quadrature of d/r^3 over the faces of each drum's bounding box
    (newdrum: hoops of radius 0.296 m, height 0.851 m): a check independent of the plugin's
    closed form."""
    r, h = 0.572 / 2 + 0.01, 0.851
    boxes = {(i, j): ((1.5 + (i - 1) * pitch - r, 1.2 + (j - 1) * pitch - r, 0), (1.5 + (i - 1) * pitch + r, 1.2 + (j - 1) * pitch + r, h))
             for i in range(1, 4) for j in range(1, 5)}
    lo, hi = boxes[(2, 3)]
    c = [(lo[k] + hi[k]) / 2 for k in range(3)]
    total = 0.0
    for key, (lo, hi) in boxes.items():
        if key == (2, 3):
            continue
        for a in range(3):
            u, v = (a + 1) % 3, (a + 2) % 3
            for plane, side in ((lo[a], -1), (hi[a], 1)):
                if (c[a] - plane) * side <= 0:
                    continue
                d, du, dv = abs(c[a] - plane), (hi[u] - lo[u]) / n, (hi[v] - lo[v]) / n
                for k in range(n):
                    x = lo[u] + (k + 0.5) * du - c[u]
                    for m in range(n):
                        y = lo[v] + (m + 0.5) * dv - c[v]
                        total += d / (x * x + y * y + d * d) ** 1.5 * du * dv
    return total


def plugins(sscs, root):
    """Plugins: the example constraint class, the trust boundary, and every broken plugin's
    outcome (exit 3 naming the plugin, or the constraint's status `error` with the run going on)."""
    import tempfile
    build = build_dir(sscs)
    examples = os.path.join(build, "plugins")
    broken = os.path.join(build, "tests", "plugins")
    rooms = "tests/data/plugins/rooms.yaml"
    p = run(sscs, root, ["check", rooms, "--plugins", examples, "--format", "json"])
    results = {r["constraint"]: r for r in json.loads(p.stdout)["results"]} if p.returncode == 1 else {}
    hall, store = results.get("hall door height", {}), results.get("store door height", {})
    if hall.get("status") != "pass" or hall.get("margin") != 0 or store.get("status") != "fail" or \
            store.get("margin") != -1 or store.get("unit") != "m" or "must be lower than 7.00: it is 8.00" not in store.get("message", ""):
        fail(f"room_door_rule results: {results}", p)
    # SARIF: checks of plugin classes share the rule sscs/plugin; the message names the class.
    p = run(sscs, root, ["check", rooms, "--plugins", examples, "--format", "sarif"])
    sarif = [r for r in json.loads(p.stdout)["runs"][0]["results"]] if p.returncode == 1 else []
    if len(sarif) != 1 or sarif[0]["ruleId"] != "sscs/plugin" or \
            not sarif[0]["message"]["text"].startswith("store door height (plugin class room_door_rule)"):
        fail(f"SARIF of a plugin class: {sarif}", p)
    p = run(sscs, root, ["check", rooms])
    if p.returncode != 2 or "no loaded plugin provides constraint class 'room_door_rule'" not in p.stderr:
        fail("a plugin class without --plugins is an input error", p)
    # A vault's own plugins: key loads nothing by itself. (Written here: it names the build's
    # plugin folder, wherever the build is.)
    vp = os.path.join(tempfile.mkdtemp(), "vault-plugins.yaml")
    open(vp, "w").write(open(os.path.join(root, rooms)).read().replace("constraints:", f"plugins: [{examples}]\nconstraints:")
                        .replace("vault: Rooms", "vault: AsksForPlugins"))
    p = run(sscs, root, ["check", vp])
    if p.returncode != 2 or "a vault alone never loads code" not in p.stderr or "--allow-vault-plugins" not in p.stderr:
        fail("vault plugins without permission", p)
    # Allowed, a vault's plugin folder must still lie in the project root (the vault's temporary
    # folder here), unless the command line lets it out.
    p = run(sscs, root, ["check", vp, "--allow-vault-plugins"])
    if p.returncode != 2 or f"plugin folder '{examples}' is outside the project root" not in p.stderr:
        fail("a vault's plugin folder outside the project root", p)
    for allow in (["--allow-vault-plugins", "--allow-outside-root"], ["--allow-vault-plugins", "--root", build_dir(sscs)],
                  ["--plugins", examples]):
        p = run(sscs, root, ["check", vp] + allow)
        if p.returncode != 1 or "1 passed, 1 failed" not in p.stdout:
            fail(f"vault plugins with {allow}", p)
    shutil.rmtree(os.path.dirname(vp))
    # Broken plugins.
    bad = "tests/data/plugins/broken.yaml"
    expect = {
        "wrong_abi": (3, "wrong_abi.so: built for plugin ABI version 99, this sscs has version 1"),
        "no_register": (3, "no_register.so: missing the entry symbol sscs_plugin_register"),
        "throws": (1, "broken check [plugin D]: plugin " + os.path.join(broken, "throws", "throws.so") +
                   " could not evaluate it: the check threw: no table for D.height"),
        "nan": (1, "nan.so returned a margin that is not a number (nan)"),
        "crash": (3, "sscs: error: plugin " + os.path.join(broken, "crash", "crash.so") +
                  " crashed in the check of constraint 'broken check' (class broken)"),
    }
    for kind, (code, message) in expect.items():
        p = run(sscs, root, ["check", bad, "--plugins", os.path.join(broken, kind)])
        if p.returncode != code or message not in p.stdout + p.stderr:
            fail(f"broken plugin {kind}: expected exit {code} and {message!r}", p)
        if code == 1 and "1 passed, 1 failed" not in p.stdout:
            fail(f"broken plugin {kind}: the other constraint is still checked", p)
    # Two plugins defining one class.
    with tempfile.TemporaryDirectory() as tmp:
        shutil.copy(os.path.join(examples, "room_door_rule.so"), os.path.join(tmp, "copy.so"))
        p = run(sscs, root, ["check", rooms, "--plugins", examples, "--plugins", tmp])
        if p.returncode != 3 or "constraint class 'room_door_rule' is already defined by plugin" not in p.stderr:
            fail("a class defined twice", p)
    # sscs types lists the classes with the plugin's path.
    p = run(sscs, root, ["types", "--plugins", examples])
    if p.returncode != 0 or f"plugin constraint class room_door_rule - " not in p.stdout or \
            os.path.join(examples, "room_door_rule.so") not in p.stdout:
        fail("types --plugins", p)
    # Object types from plugins: newdrum (and the template's my_crate) used in a vault, their
    # geometry in the checks; without --plugins they are unknown types.
    nd = "tests/data/plugins/newdrum.yaml"
    p = run(sscs, root, ["check", nd, "--plugins", examples])
    if p.returncode != 1 or "7 passed, 1 failed, 0 warnings" not in p.stdout or \
            "D1.fill_mass = 200 kg <= 180 kg: violated (margin -20 kg)" not in p.stdout:
        fail("a vault of plugin types", p)
    p = run(sscs, root, ["check", nd])
    if p.returncode != 2 or "unknown type 'newdrum' (no plugins are loaded: a plugin's type needs --plugins DIR)" not in p.stderr:
        fail("plugin types without --plugins", p)
    p = run(sscs, root, ["types", "--plugins", examples])
    if p.returncode != 0 or f"newdrum (extends object; plugin {os.path.join(examples, 'newdrum.so')}) - " not in p.stdout or \
            "  lid              enum           default closed  {open, closed}" not in p.stdout:
        fail("types --plugins lists plugin types", p)
    p = run(sscs, root, ["types", "--plugins", examples, "--format", "json"])
    types = {t["name"]: t for t in json.loads(p.stdout)["types"]} if p.returncode == 0 else {}
    newdrum = types.get("newdrum", {})
    if newdrum.get("plugin") != os.path.join(examples, "newdrum.so") or types.get("drum", {}).get("plugin", 0) is not None or \
            [a["name"] for a in newdrum.get("attributes", [])] != ["diameter", "height", "wall", "fill_mass", "lid"] or \
            newdrum["attributes"][0]["unit"] != "m":
        fail(f"types --format json with a plugin type: {newdrum}", p)
    # Broken object types: a library name, an invalid declaration, one that does not resolve,
    # and one name from two plugins: exit 3 naming the plugin.
    expect = {
        "dup_type": "dup_type.so: object type 'drum' is already defined by the type library (",
        "bad_type": "bad_type.so (type bad_type):5:20: error: expected an attribute type (length, angle, mass, time, "
                    "number, integer, boolean, string, enum), found 'lenght' (did you mean 'length'?)",
        "unresolved_type": "unresolved_type.so (type unresolved_type):7:25: error: cylinder radius uses 'diametre', which "
                           "is not an attribute of type 'unresolved_type' (did you mean 'diameter'?)",
    }
    for kind, message in expect.items():
        p = run(sscs, root, ["check", bad, "--plugins", os.path.join(broken, kind)])
        if p.returncode != 3 or message not in p.stderr or p.stdout:
            fail(f"broken plugin type {kind}: expected exit 3 and {message!r}", p)
    with tempfile.TemporaryDirectory() as tmp:
        shutil.copy(os.path.join(examples, "newdrum.so"), os.path.join(tmp, "newdrum-copy.so"))
        p = run(sscs, root, ["check", nd, "--plugins", examples, "--plugins", tmp])
        if p.returncode != 3 or "object type 'newdrum' is already defined by plugin " + os.path.join(examples, "newdrum.so") not in p.stderr:
            fail("a type defined by two plugins", p)
    # The criticality rule: the store passes at its 1.4 m pitch with the solid angle an
    # independent numerical integration gives; closer drums fail on the solid angle, closer
    # still on the 0.3 m spacing.
    store = "scenarios/fissile-store/store.yaml"
    def interaction(extra):
        q = run(sscs, root, ["check", store, "--plugins", examples, "--format", "json"] + extra)
        rs = [r for r in json.loads(q.stdout)["results"] if r["constraint"] == "drum array interaction"] if q.returncode in (0, 1) else []
        if len(rs) != 1:
            fail(f"the store with {extra}", q)
        return rs[0]
    r = interaction([])
    omega = solid_angle_at_centre_unit(1.4)
    if r["status"] != "pass" or r["unit"] != "sr" or abs((3 - r["margin"]) - omega) > 1e-4 or "largest total solid angle 2.502 sr" not in r["message"]:
        fail(f"solid angle at 1.4 m pitch: {r}, integrated {omega}")
    r = interaction(["--set", "pitch=1.2 m"])
    if r["status"] != "fail" or abs((3 - r["margin"]) - solid_angle_at_centre_unit(1.2)) > 1e-4:
        fail(f"solid angle at 1.2 m pitch: {r}")
    r = interaction(["--set", "pitch=0.85 m"])
    if r["status"] != "fail" or r["unit"] != "m" or abs(r["margin"] - (0.85 - 0.592 - 0.3)) > 1e-9 or \
            "Drum_1_1 and Drum_1_2 are 0.26 m apart edge to edge" not in r["message"]:
        fail(f"spacing at 0.85 m pitch: {r}")
    # Simulating with a plugin type: real physics, and the run names and hashes the plugin
    # (code is never copied into resolved/); rerunning resolved/ with --plugins gives the same run.
    with tempfile.TemporaryDirectory() as tmp:
        out, again = os.path.join(tmp, "run"), os.path.join(tmp, "again")
        p = run(sscs, root, ["simulate", "tests/data/plugins/newdrum-lift.yaml", "--plugins", examples, "--out", out, "--quiet"])
        events = [json.loads(l) for l in open(os.path.join(out, "events.jsonl"))] if p.returncode == 0 else []
        kinds = [e["kind"] for e in events if not e["kind"].startswith("step_")]
        if kinds != ["grasp", "release", "landed", "at_rest"]:
            fail(f"newdrum lift events: {kinds}", p)
        summary = json.load(open(os.path.join(out, "summary.json")))
        so = os.path.join(examples, "newdrum.so")
        digest = hashlib.sha256(open(so, "rb").read()).hexdigest()
        # Inputs are named relative to the folder sscs ran in when inside it, else absolute.
        inside = os.path.relpath(os.path.realpath(so), os.path.realpath(root))
        so = so if inside.startswith("..") else inside
        if {"path": so, "sha256": digest} not in summary["inputs"] or summary["inputs_not_in_resolved"] != [so]:
            fail(f"the run's inputs name the plugin: {summary['inputs'][-4:]}, {summary['inputs_not_in_resolved']}")
        p = run(sscs, root, ["simulate", os.path.join(out, "resolved", "scenario.yaml"), "--plugins", examples, "--out", again, "--quiet"])
        if p.returncode != 0 or open(os.path.join(out, "events.jsonl")).read() != open(os.path.join(again, "events.jsonl")).read():
            fail("rerun of a plugin-type run from resolved/", p)
    # The template builds against an installed sscs (cmake --install, find_package(sscs),
    # sscs_add_plugin) and its class works from the installed binary.
    with tempfile.TemporaryDirectory() as tmp:
        prefix, src = os.path.join(tmp, "prefix"), os.path.join(tmp, "my-plugin")
        for cmd in (["cmake", "--install", build, "--prefix", prefix],
                    ["cp", "-r", os.path.join(root, "plugins", "template"), src],
                    ["cmake", "-S", src, "-B", os.path.join(src, "build"), f"-DCMAKE_PREFIX_PATH={prefix}"],
                    ["cmake", "--build", os.path.join(src, "build")]):
            q = subprocess.run(cmd, capture_output=True, text=True)
            if q.returncode != 0:
                fail(f"{' '.join(cmd)}: {q.stdout}{q.stderr}")
        p = run(os.path.join(prefix, "bin", "sscs"), root,
                ["check", "tests/data/plugins/template.yaml", "--plugins", os.path.join(src, "build", "plugins")])
        if p.returncode != 1 or "High.height = 4.900000, at most 3.000000 (margin -1.9 m)" not in p.stdout or \
                "the check threw: args need a number 'max'" not in p.stdout or "2 passed, 2 failed (1 could not be evaluated), 0 warnings" not in p.stdout:
            fail("the template plugin from an installed sscs", p)
        # An installed sscs names the installed schemas in the files it writes.
        p = run(os.path.join(prefix, "bin", "sscs"), root,
                ["simulate", "scenarios/drum-transfer/arm-loads-drum.yaml", "--out", os.path.join(tmp, "run"), "--quiet"])
        schema = os.path.join(prefix, "share", "sscs", "schemas", "vault.schema.json")
        if p.returncode != 0 or not os.path.exists(schema) or \
                open(os.path.join(tmp, "run", "resolved", "vault.yaml")).readline() != f"# yaml-language-server: $schema={schema}\n":
            fail("the modeline of an installed sscs", p)
    print("ok plugins")


def check_junit(path):
    """A faithful structural check of the JUnit XML that Jenkins' junit plugin and GitLab read
    (the schema of Jenkins' JUnit report: testsuites > testsuite > testcase > failure | error |
    skipped, system-out): required attributes, numeric counts that add up, nothing unknown."""
    import xml.etree.ElementTree as ET
    root = ET.parse(path).getroot()
    if root.tag != "testsuites":
        fail(f"{path}: the root is <{root.tag}>, not <testsuites>")
    totals = {"tests": 0, "failures": 0, "errors": 0}
    for suite in root:
        if suite.tag != "testsuite":
            fail(f"{path}: <{suite.tag}> under <testsuites>")
        for attr in ("name", "tests", "failures", "errors"):
            if attr not in suite.attrib:
                fail(f"{path}: a testsuite without {attr}")
        counts = {"tests": 0, "failures": 0, "errors": 0}
        for child in suite:
            if child.tag in ("system-out", "system-err", "properties"):
                continue
            if child.tag != "testcase" or "name" not in child.attrib or "classname" not in child.attrib:
                fail(f"{path}: <{child.tag} {child.attrib}> in a testsuite")
            counts["tests"] += 1
            for outcome in child:
                if outcome.tag in ("failure", "error"):
                    if "message" not in outcome.attrib or "type" not in outcome.attrib or not (outcome.text or "").strip():
                        fail(f"{path}: a <{outcome.tag}> without message, type and text")
                    counts["failures" if outcome.tag == "failure" else "errors"] += 1
                elif outcome.tag not in ("skipped", "system-out", "system-err"):
                    fail(f"{path}: <{outcome.tag}> in a testcase")
        for k, v in counts.items():
            if int(suite.attrib[k]) != v:
                fail(f"{path}: testsuite {suite.attrib['name']} says {k}={suite.attrib[k]}, has {v}")
            totals[k] += v
    for k, v in totals.items():
        if int(root.attrib.get(k, -1)) != v:
            fail(f"{path}: testsuites says {k}={root.attrib.get(k)}, has {v}")


def ci(sscs, root):
    """CI gating: SARIF valid against the OASIS 2.1.0 schema, locations and baseline states;
    JUnit that Jenkins and GitLab read; the baseline's exit statuses."""
    import jsonschema
    schema_file = os.path.join(root, "..", "shared", "third-party-schemas", "sarif-schema-2.1.0.json")
    if not os.path.exists(schema_file):
        fail(f"the SARIF schema is not at {schema_file} (the shared folder beside the repository)")
    schema = json.load(open(schema_file))
    golden_dir = os.path.join(root, "tests", "golden")
    for name in ("demo_sarif.out", "ci_example_baseline_sarif.out"):
        doc = json.load(open(os.path.join(golden_dir, name)))
        try:
            jsonschema.validate(doc, schema)
        except jsonschema.ValidationError as e:
            fail(f"{name} is not valid SARIF 2.1.0: {e.message} at {list(e.absolute_path)}")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "demo.sarif")
        p = run(sscs, root, ["check", "scenarios/demo/demo.yaml", "--out", out])  # .sarif: the format from the extension
        doc = json.load(open(out)) if p.returncode == 1 else {}
        results = doc.get("runs", [{}])[0].get("results", [])
        rules = [r["id"] for r in doc["runs"][0]["tool"]["driver"]["rules"]] if results else []
        door = [r for r in results if r["properties"]["constraint"] == "door clear height"]
        loc = door[0]["locations"][0]["physicalLocation"] if door else {}
        if len(results) != 6 or not door or loc["artifactLocation"] != {"uri": "scenarios/demo/demo.yaml", "uriBaseId": "SRCROOT"} or \
                loc["region"] != {"startLine": 28, "startColumn": 5} or door[0]["level"] != "error" or \
                rules[door[0]["ruleIndex"]] != "sscs/bound" or "(margin -0.1 m)" not in door[0]["message"]["text"] or \
                sorted(r["level"] for r in results).count("warning") != 2:
            fail(f"SARIF of the demo: {json.dumps(results)[:3000]}", p)
    states = {r["properties"]["constraint"]: r["baselineState"]
              for r in json.load(open(os.path.join(golden_dir, "ci_example_baseline_sarif.out")))["runs"][0]["results"]}
    if states != {"door clear height": "unchanged", "cart passes the door": "new", "aisle at least 1.5 m": "absent"}:
        fail(f"SARIF baseline states: {states}")
    for name in ("demo_junit.out", "ci_example_baseline_junit.out"):
        check_junit(os.path.join(golden_dir, name))
    # A warning that newly fails passes the gate, unless --strict.
    with tempfile.TemporaryDirectory() as tmp:
        base, tall = os.path.join(tmp, "base.json"), os.path.join(tmp, "tall.yaml")
        open(tall, "w").write(open(os.path.join(root, "tests/data/good/warning_only.yaml")).read().replace("height: 2.2", "height: 2.5"))
        p = run(sscs, root, ["check", tall, "--format", "json", "--out", base])
        if p.returncode != 0:
            fail("the baseline with a passing warning", p)
        p = run(sscs, root, ["check", "tests/data/good/warning_only.yaml", "--baseline", base])
        q = run(sscs, root, ["check", "tests/data/good/warning_only.yaml", "--baseline", base, "--strict"])
        if p.returncode != 0 or q.returncode != 1 or "1 new failure" not in p.stdout:
            fail("a new failing warning: exit 0, and 1 with --strict", q)
    print("ok ci")


def sweep(sscs, root):
    """sscs sweep: the example studies (values against hand counts, the table against a golden
    file), --jobs and shards giving byte-identical tables, merge refusals, resume after a killed
    and an interrupted sweep, a crashing variant and timed-out variants recorded as errors, random
    mode, and a simulated device study."""
    import csv
    import signal
    import time
    study = "scenarios/sweeps/aisle-rows.yaml"
    table_files = ("results.csv", "results.json", "sweep.json")

    def same_tables(a, b, what):
        for name in table_files:
            if open(os.path.join(a, name), "rb").read() != open(os.path.join(b, name), "rb").read():
                fail(f"{what}: {name} differs between {a} and {b}")

    def rows_of(d):
        return list(csv.DictReader(open(os.path.join(d, "results.csv"), newline="")))

    with tempfile.TemporaryDirectory() as tmp:
        full = os.path.join(tmp, "full")
        p = run(sscs, root, ["sweep", study, "--out", full, "--jobs", "2"])
        if p.returncode != 1 or "swept 55 variants: 11 pass, 44 fail, 0 error" not in p.stdout or "55/55 variants" not in p.stderr:
            fail("the aisle-rows study", p)
        golden = os.path.join(root, "tests", "golden", "sweep_aisle_rows.csv")
        actual = open(os.path.join(full, "results.csv")).read()
        if os.environ.get("SSCS_UPDATE_GOLDEN"):
            open(golden, "w").write(actual)
        if actual != open(golden).read():
            fail(f"results.csv differs from {golden} (SSCS_UPDATE_GOLDEN=1 to update after review)")
        # The manifest names every input with its own sha256 (issue 17).
        import hashlib
        manifest = json.load(open(os.path.join(full, "sweep.json")))
        inputs = {i["file"]: i["sha256"] for i in manifest["inputs"]}
        for name, path in (("store.yaml", "scenarios/sweeps/store.yaml"), ("<library>/types/rack.yaml", "library/types/rack.yaml")):
            if inputs.get(name) != hashlib.sha256(open(os.path.join(root, path), "rb").read()).hexdigest():
                fail(f"sweep.json inputs lack {name} with its sha256: {sorted(inputs)}")
        # Every row against hand counts: 4 bays x rows racks of 3 levels of 4 drums; the cart
        # rule is aisle >= 1.219 + 0.3 m; the lane rule 1 + 1.067 rows + (rows - 1) aisle + 1.5 <= 9.
        rows = rows_of(full)
        if [int(r["variant"]) for r in rows] != list(range(55)):
            fail("rows are not in variant order")
        for r in rows:
            i, aisle, n = int(r["variant"]), float(r["aisle"]), int(r["rows"])
            lane = 9 - (1 + 1.067 * n + (n - 1) * aisle + 1.5)
            expect = {"aisle": round(1.0 + (i // 5) * 0.1, 9), "rows": i % 5 + 1, "capacity": 48 * n, "racks": 4 * n}
            got = {"aisle": aisle, "rows": n, "capacity": float(r["capacity"]), "racks": float(r["racks"])}
            if got != expect or abs(float(r["aisle_margin"]) - (aisle - 1.519)) > 1e-9 or abs(float(r["lane_margin"]) - lane) > 1e-9:
                fail(f"variant {i}: {r}, expected {expect}, lane margin {lane}")
            if (r["status"] == "pass") != (aisle >= 1.519 and lane >= 0):
                fail(f"variant {i} is {r['status']}: {r}")
            if not os.path.exists(os.path.join(full, r["folder"], "report.json")):
                fail(f"variant {i} has no report in {r['folder']}")
        # The plot of docs/sweeps.md.
        png = os.path.join(tmp, "plot.png")
        q = subprocess.run([sys.executable, os.path.join(root, "tools", "plot-sweep.py"), os.path.join(full, "results.csv"),
                            "--x", "aisle", "--y", "capacity", "--group", "rows", "--out", png], capture_output=True, text=True)
        if q.returncode != 0 or open(png, "rb").read(8) != b"\x89PNG\r\n\x1a\n" or os.path.getsize(png) < 10000:
            fail(f"tools/plot-sweep.py: {q.stdout}{q.stderr}")
        q = subprocess.run([sys.executable, os.path.join(root, "tools", "plot-sweep.py"), os.path.join(full, "results.csv"),
                            "--x", "aisel", "--y", "capacity", "--out", png], capture_output=True, text=True)
        if q.returncode == 0 or "has no column 'aisel'" not in q.stderr:
            fail(f"tools/plot-sweep.py with an unknown column: {q.stderr}")
        # Run as a user would, `tools/plot-sweep.py` with whatever python3 is first on PATH (a pyenv
        # or venv one lacks Debian's matplotlib: the script runs again with /usr/bin/python3).
        plot = os.path.join(tmp, "plot2.png")
        q = subprocess.run(["python3", os.path.join(root, "tools", "plot-sweep.py"), os.path.join(full, "results.csv"),
                            "--x", "aisle", "--y", "capacity", "--out", plot], capture_output=True, text=True)
        if q.returncode != 0 or not os.path.exists(plot):
            fail(f"tools/plot-sweep.py with the python3 on PATH ({shutil.which('python3')}): {q.stderr}")
        # Without matplotlib at all (-S: no site packages), a message that says what to do.
        q = subprocess.run([sys.executable, "-S", os.path.join(root, "tools", "plot-sweep.py"), os.path.join(full, "results.csv"),
                            "--x", "aisle", "--y", "capacity", "--out", plot], capture_output=True, text=True,
                           env=dict(os.environ, SSCS_PLOT_REEXEC="1"))
        if q.returncode == 0 or "matplotlib is not installed" not in q.stderr or "tools/setup.sh" not in q.stderr:
            fail(f"tools/plot-sweep.py without matplotlib: {q.stderr}")
        # --jobs 1 and shards: the same tables, byte for byte.
        one = os.path.join(tmp, "one")
        p = run(sscs, root, ["sweep", study, "--out", one, "--jobs", "1", "--quiet"])
        if p.returncode != 1 or p.stderr:
            fail("--jobs 1 (and --quiet prints no progress)", p)
        same_tables(full, one, "--jobs 1 against --jobs 2")
        shards = [os.path.join(tmp, f"shard{k}") for k in range(3)]
        for k, d in enumerate(shards):
            p = run(sscs, root, ["sweep", study, "--shard", f"{k}/3", "--out", d, "--quiet"])
            if p.returncode != 1 or f"swept {len(range(k, 55, 3))} variants" not in p.stdout:
                fail(f"shard {k}/3", p)
        merged = os.path.join(tmp, "merged")
        p = run(sscs, root, ["sweep", "merge", *shards, "--out", merged])
        if p.returncode != 1 or "merged 55 variants: 11 pass, 44 fail, 0 error" not in p.stdout:
            fail("merge", p)
        same_tables(full, merged, "merged shards against one run")
        if sorted(os.listdir(merged)) != sorted(os.listdir(full)):
            fail("the merged folder does not hold every variant's folder")
        for args, message in (([shards[0], shards[1]], "18 of the 55 variants of sweep 'aisle-rows' are in none of the folders (variants 2, 5, 8"),
                              ([shards[0], shards[1], shards[1], shards[2]], "is named twice; merge each shard once"),
                              ([shards[0], os.path.join(root, "scenarios")], "is not a sweep folder (it has no sweep.json)")):
            bad_out = os.path.join(tmp, "refused")
            p = run(sscs, root, ["sweep", "merge", *args, "--out", bad_out])
            if p.returncode != 2 or message not in p.stderr or os.path.exists(bad_out):
                fail(f"merge must refuse: {message}", p)
        # Resume: a rerun skips what is complete; another sweep's folder is refused; --force redoes.
        p = run(sscs, root, ["sweep", study, "--out", full, "--quiet"])
        if p.returncode != 1 or "swept 55 variants (55 done before)" not in p.stdout:
            fail("rerun into a complete folder", p)
        same_tables(full, one, "after a resumed rerun")
        p = run(sscs, root, ["sweep", "tests/data/sweeps/random.yaml", "--out", full])
        if p.returncode != 2 or "holds the results of sweep 'aisle-rows'" not in p.stderr:
            fail("a folder of another sweep", p)
        p = run(sscs, root, ["sweep", study, "--out", os.path.join(root, "docs"), "--force"])
        if p.returncode != 2 or "is not empty and holds no sweep (no sweep.json)" not in p.stderr:
            fail("--out naming a folder that is no sweep's, with --force", p)
        # Killed: the next run does only what is missing and the table is the same.
        killed = os.path.join(tmp, "killed")
        for how in (signal.SIGKILL, signal.SIGINT):
            shutil.rmtree(killed, ignore_errors=True)
            proc = subprocess.Popen([sscs, "sweep", study, "--out", killed, "--jobs", "1"], cwd=root,
                                    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
            deadline = time.time() + 60
            while time.time() < deadline and len(glob.glob(os.path.join(killed, "*", "result.json"))) < 8:
                time.sleep(0.005)
            os.killpg(proc.pid, how)
            out, err = proc.communicate(timeout=60)
            done = len(glob.glob(os.path.join(killed, "*", "result.json")))
            if how == signal.SIGINT and (proc.returncode != 130 or "interrupted:" not in err or "run the same command again" not in err):
                fail(f"an interrupted sweep: exit {proc.returncode}, stderr {err}")
            if not 8 <= done < 55:
                fail(f"the sweep was stopped too late to test resuming ({done} variants done)")
            p = run(sscs, root, ["sweep", study, "--out", killed, "--quiet"])
            if p.returncode != 1 or f"({done} done before)" not in p.stdout:
                fail(f"resume after {how.name}: {done} were done", p)
            same_tables(full, killed, f"resumed after {how.name}")
            if [n for n in os.listdir(killed) if ".tmp-" in n]:
                fail(f"half-written folders left after resuming: {os.listdir(killed)}")
        # A crashing variant is an error row; the others run.
        crash = os.path.join(tmp, "crash")
        p = run(sscs, root, ["sweep", "tests/data/sweeps/crash.yaml", "--out", crash, "--plugins",
                             os.path.join(build_dir(sscs), "tests", "plugins", "crash")])
        rows = rows_of(crash) if os.path.exists(os.path.join(crash, "results.csv")) else []
        if p.returncode != 1 or len(rows) != 2 or rows[0]["status"] != "error" or \
                "crashed in the check of constraint 'broken check'" not in rows[0]["message"] or rows[1]["status"] != "pass":
            fail(f"a crashing variant: {rows}", p)
        # A type per variant: `vary: library:` adds a type folder per variant.
        lib = os.path.join(tmp, "lib")
        p = run(sscs, root, ["sweep", "tests/data/sweeps/choose-container.yaml", "--out", lib, "--quiet"])
        got = [(r["library"], r["count"], r["status"], r["total_mass"], r["headroom"]) for r in rows_of(lib)]
        if p.returncode != 1 or got != [("libraries/small", "2", "pass", "240", "0.4"), ("libraries/small", "3", "pass", "360", "0.4"),
                                        ("libraries/large", "2", "fail", "800", "-0.1"), ("libraries/large", "3", "fail", "1200", "-0.1")]:
            fail(f"vary: library: {got}", p)
        # Random mode: the same seed, the same seven grid points, listed in grid order.
        r1, r2 = os.path.join(tmp, "r1"), os.path.join(tmp, "r2")
        for d in (r1, r2):
            run(sscs, root, ["sweep", "tests/data/sweeps/random.yaml", "--out", d, "--quiet"])
        same_tables(r1, r2, "random mode with one seed")
        grid = {(r["aisle"], r["rows"]): int(r["variant"]) for r in rows_of(full)}
        points = [grid[(r["aisle"], r["rows"])] for r in rows_of(r1)]
        if len(points) != 7 or points != sorted(set(points)):
            fail(f"random mode drew {points}")
        # A simulated study: cycle times from the runs; a motion over the lift limit fails its row.
        sim = os.path.join(tmp, "sim")
        p = run(sscs, root, ["sweep", "scenarios/sweeps/arm-vs-gantry.yaml", "--out", sim, "--quiet"])
        rows = rows_of(sim)
        if p.returncode != 1 or [r["status"] for r in rows] != ["fail", "pass", "fail", "pass"]:
            fail(f"the device study: {rows}", p)
        for r in rows:
            summary = json.load(open(os.path.join(sim, r["folder"], "run", "summary.json")))
            if abs(float(r["cycle_time"]) - summary["cycle_time"]) > 1e-6 or \
                    abs(float(r["drums_per_hour"]) - 3600 / summary["cycle_time"]) > 1e-6:
                fail(f"variant {r['variant']}: {r} against its run's summary {summary['cycle_time']}")
        if not float(rows[1]["cycle_time"]) < float(rows[3]["cycle_time"]) or "run: violations" not in rows[0]["message"]:
            fail(f"the arm should be faster than the gantry, and a lift over 0.3 m a violation: {rows}")
        # Each run lists its own inputs, as `simulate` of it alone does: not the study's other
        # scenario and vault, nor the sweep file (40 entries, 23 unique, listed every variant).
        for r, scenario in zip(rows, ["arm-loads-drum", "arm-loads-drum", "gantry-loads-drum", "gantry-loads-drum"]):
            alone = os.path.join(tmp, f"alone-{r['variant']}")
            p = run(sscs, root, ["simulate", f"scenarios/drum-transfer/{scenario}.yaml", "--set", f"max_lift={r['max_lift']} m",
                                 "--out", alone, "--no-frames", "--quiet"])
            mine = json.load(open(os.path.join(sim, r["folder"], "run", "summary.json")))["inputs"]
            own = json.load(open(os.path.join(alone, "summary.json")))["inputs"]
            if p.returncode not in (0, 1) or [(i["path"], i["sha256"]) for i in mine] != [(i["path"], i["sha256"]) for i in own]:
                fail(f"variant {r['variant']}: its run's inputs {[i['path'] for i in mine]}, alone {[i['path'] for i in own]}", p)
        # Timed-out variants are errors, and the sweep goes on to the end.
        slow = os.path.join(tmp, "slow")
        p = run(sscs, root, ["sweep", "scenarios/sweeps/arm-vs-gantry.yaml", "--out", slow, "--variant-timeout", "0.01", "--quiet"])
        rows = rows_of(slow)
        if p.returncode != 1 or len(rows) != 4 or any(r["status"] != "error" or "timed out after 0.01 s" not in r["message"] for r in rows):
            fail(f"--variant-timeout: {rows}", p)
    print("ok sweep")


def recipe(root, name):
    """The YAML block after `<!-- recipe: NAME -->` in docs/ci.md, parsed."""
    import re
    text = open(os.path.join(root, "docs", "ci.md"), encoding="utf-8").read()
    m = re.search(r"<!-- recipe: " + name + r" -->\n```yaml\n(.*?)\n```\n", text, re.S)
    if not m:
        fail(f"docs/ci.md has no recipe '{name}'")
    import yaml
    load = yaml_loader()
    with tempfile.NamedTemporaryFile("w", suffix=".yaml") as f:
        f.write(m.group(1))
        f.flush()
        return load(f.name)


def html_report(path, uploaded):
    """A recipe's HTML report: written, kept as an artifact, one page with the baseline's diff
    and the model inlined (nothing to fetch)."""
    if not uploaded:
        fail(f"the recipe does not keep {os.path.basename(path)} as an artifact")
    if not os.path.isfile(path):
        fail(f"the recipe wrote no {path}")
    page = open(path, encoding="utf-8").read()
    for needle in ('<script type="application/json" id="sscs-data">', 'id="sscs-model-0"', '"baseline"', "THREE.GLTFLoader"):
        if needle not in page:
            fail(f"{path} lacks {needle!r}")
    if re.search(r'(src|href)="(https?:)?//', page):
        fail(f"{path} refers to something on the network")


def ci_recipes(sscs, root):
    """The CI recipes of docs/ci.md, run as written (less installing and building sscs) in a
    scratch repository whose base branch holds scenarios/ci-example/main and whose change holds
    scenarios/ci-example/branch: the job fails for the one new failure and leaves the reports
    and annotations the CI systems read."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, HOME=tmp, NO_COLOR="1", GIT_AUTHOR_NAME="t", GIT_AUTHOR_EMAIL="t@t",
                   GIT_COMMITTER_NAME="t", GIT_COMMITTER_EMAIL="t@t")

        def sh(script, cwd, extra=None):
            return subprocess.run(["bash", "-e", "-o", "pipefail", "-c", script], cwd=cwd, capture_output=True, text=True,
                                  env=dict(env, **(extra or {})), timeout=300)
        origin = os.path.join(tmp, "origin")
        os.makedirs(os.path.join(origin, "vaults"))
        ex = os.path.abspath(os.path.join(root, "scenarios", "ci-example"))
        p = sh(f"git init -q -b main . && cp {ex}/main/store.yaml vaults/ && git add -A && git commit -qm base && "
               f"git checkout -qb change && cp {ex}/branch/store.yaml vaults/ && git commit -qam change && git checkout -q main",
               origin)
        if p.returncode != 0:
            fail("the scratch repository", p)

        def clone(name):
            where = os.path.join(tmp, name)
            os.makedirs(where)
            q = sh(f"git clone -q {origin} work && cd work && git checkout -q change", where)
            if q.returncode != 0:
                fail("clone", q)
            return os.path.join(where, "work")

        # GitHub Actions: every `run` step but installing and building sscs.
        job = recipe(root, "github")["jobs"]["check"]
        work = clone("github")
        jenv = dict(job["env"], SSCS=os.path.abspath(sscs), GITHUB_BASE_REF="main",
                    GITHUB_STEP_SUMMARY=os.path.join(tmp, "summary.md"))
        outputs = {}
        for step in job["steps"]:
            if "run" in step and step["name"] not in ("Tools the steps use", "Set up sscs"):
                outputs[step["name"]] = q = sh(step["run"], work, jenv)
                if q.returncode != (1 if step["name"].startswith("Check") else 0):
                    fail(f"GitHub step '{step['name']}'", q)
        check = outputs["Check the pull request's vaults"].stdout
        for line in ("vaults/store.yaml:23:5: fail: cart passes the door",  # the text report, whole despite --quiet
                     "::error file=vaults/store.yaml,line=23,col=5::cart passes the door [MainDoor, Cart1]",
                     "::warning file=vaults/store.yaml,line=19,col=5::still failing: door clear height",
                     "::notice file=vaults/store.yaml,line=18,col=5::fixed: aisle at least 1.5 m",
                     "1 new failure, 1 fixed, 1 still failing, 2 unchanged, 1 renamed, 1 removed"):
            if line not in check:
                fail(f"the GitHub check step does not print {line!r}", outputs["Check the pull request's vaults"])
        if "[new failure]" not in open(jenv["GITHUB_STEP_SUMMARY"]).read():
            fail("the GitHub step summary")
        uploads = [s["with"] for s in job["steps"] if s.get("uses", "").startswith("github/codeql-action/upload-sarif")]
        sarif = json.load(open(os.path.join(work, uploads[0]["sarif_file"])))
        if sorted(r.get("baselineState") for r in sarif["runs"][0]["results"]) != ["absent", "new", "unchanged"]:
            fail(f"the SARIF the workflow uploads: {sarif['runs'][0]['results']}")
        # The artifact holds the HTML report (the page itself is tested in chromium: web.reports).
        artifact = [s["with"]["path"] for s in job["steps"] if s.get("uses", "").startswith("actions/upload-artifact")][0]
        html_report(os.path.join(work, "sscs.html"), "sscs.html" in artifact.split())

        # GitLab CI: the job's script, one shell as GitLab runs it.
        job = recipe(root, "gitlab")["sscs-check"]
        work = clone("gitlab")
        genv = dict({k: str(v) for k, v in job["variables"].items()}, SSCS=os.path.abspath(sscs),
                    CI_MERGE_REQUEST_TARGET_BRANCH_NAME="main")
        q = sh("\n".join(job["script"]), work, genv)
        if q.returncode != 1 or "[new failure]" not in q.stdout:
            fail("the GitLab job: exit 1 for the new failure, the text report in the log", q)
        junit = os.path.join(work, job["artifacts"]["reports"]["junit"])
        check_junit(junit)
        if "[new failure]" not in open(junit).read():
            fail("the GitLab JUnit report has no [new failure]")
        html_report(os.path.join(work, "sscs.html"), "sscs.html" in job["artifacts"]["paths"])
    print("ok ci recipes")


def yaml_loader():
    """PyYAML with YAML 1.2 core booleans (true/false only), as yaml-cpp and editors read files:
    `standard_library: no` stays the string 'no'."""
    import re
    import yaml

    class Loader(yaml.SafeLoader):
        pass
    Loader.yaml_implicit_resolvers = {k: [(t, r) for t, r in v if t != "tag:yaml.org,2002:bool"]
                                      for k, v in yaml.SafeLoader.yaml_implicit_resolvers.items()}
    Loader.add_implicit_resolver("tag:yaml.org,2002:bool", re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"), list("tTfF"))
    return lambda path: yaml.load(open(path, encoding="utf-8"), Loader=Loader)


def schema_validators(root):
    """Draft-07 validators of schemas/*.schema.json by file kind (relative $refs to common)."""
    import warnings
    import jsonschema
    warnings.filterwarnings("ignore", category=DeprecationWarning)
    sd = os.path.join(root, "schemas")
    docs = {n[:-len(".schema.json")]: json.load(open(os.path.join(sd, n))) for n in os.listdir(sd) if n.endswith(".schema.json")}
    base = "file://" + os.path.abspath(sd) + "/"
    store = {base + "common.schema.json": docs["common"]}
    out = {}
    for kind, doc in docs.items():
        jsonschema.Draft7Validator.check_schema(doc)
        resolver = jsonschema.RefResolver(base_uri=base + kind + ".schema.json", referrer=doc, store=store)
        out[kind] = jsonschema.Draft7Validator(doc, resolver=resolver)
    return docs, out


def expanded_size(path):
    """How many nodes a YAML file amounts to once its aliases are expanded (shared nodes counted
    once per use, without expanding them); 0 when it is not YAML."""
    import yaml
    try:
        root = yaml.compose(open(path, encoding="utf-8", errors="replace"))
    except yaml.YAMLError:
        return 0
    memo = {}

    def size(node):
        if id(node) not in memo:
            memo[id(node)] = 1  # a cycle counts once
            if isinstance(node, yaml.SequenceNode):
                memo[id(node)] = 1 + sum(size(n) for n in node.value)
            elif isinstance(node, yaml.MappingNode):
                memo[id(node)] = 1 + sum(size(k) + size(v) for k, v in node.value)
        return memo[id(node)]
    return size(root) if root is not None else 0


def kind_of(doc):
    if isinstance(doc, dict):
        for k in ("sweep", "campaign", "scenario", "type", "vault", "cameras"):  # (a sweep names its campaign or scenario)
            if k in doc:
                return k
    return None


def schemas(sscs, root):
    """The JSON Schemas: valid draft-07, a description and examples on every property; every YAML
    file of library/, scenarios/ and tests/data/good/ valid; and the schemas agree with the
    loader on tests/data/bad/ (each bad file is rejected by its schema or listed, with the reason
    a schema cannot say it, in tests/data/schema-agreement.txt)."""
    import glob
    docs, validators = schema_validators(root)

    def walk(node, where):
        if isinstance(node, dict):
            for name, prop in node.get("properties", {}).items():
                if "description" not in prop or "examples" not in prop:
                    fail(f"schema property {where}/{name} lacks a description or examples")
            for k, v in node.items():
                if k not in ("if", "not"):  # conditions, not properties a user writes
                    walk(v, f"{where}/{k}")
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, f"{where}/{i}")
    for kind, doc in docs.items():
        walk(doc, kind)
    load = yaml_loader()
    good = [f for pattern in ("library/**/*.yaml", "scenarios/**/*.yaml", "tests/data/good/**/*.yaml", "tests/data/vendor/**/*.yaml", "tests/data/plugins/*.yaml", "tests/data/sweeps/*.yaml")
            for f in glob.glob(os.path.join(root, pattern), recursive=True)]
    if len(good) < 40:
        fail(f"only {len(good)} good files found")
    for f in sorted(good):
        doc = load(f)
        errors = list(validators[kind_of(doc)].iter_errors(doc))
        if errors:
            fail(f"{f} does not validate against {kind_of(doc)}.schema.json: {errors[0].message} at {list(errors[0].absolute_path)}")
    # The other way round: the loader accepts every good vault (exit 0 or 1, never 2).
    plugins = os.path.join(build_dir(sscs), "plugins")
    for f in sorted(good):
        if kind_of(load(f)) == "vault":
            # broken.yaml names the class of the deliberately broken test plugins.
            extra = os.path.join(build_dir(sscs), "tests", "plugins", "nan") if f.endswith("broken.yaml") else plugins
            # containers.yaml takes its type from the library folder a sweep varies.
            library = ["--library", os.path.join(root, "tests/data/sweeps/libraries/small")] if f.endswith("containers.yaml") else []
            p = run(sscs, root, ["check", f, "--quiet", "--plugins", extra] + library)
            if p.returncode not in (0, 1):
                fail(f"the loader rejects {f}, which its schema accepts", p)
    listed = {}
    for line in open(os.path.join(root, "tests/data/schema-agreement.txt"), encoding="utf-8"):
        if line.strip() and not line.startswith("#"):
            name, _, reason = line.partition(": ")
            listed[name.strip()] = reason.strip()
    bad_dir = os.path.join(root, "tests/data/bad")
    bad = sorted(glob.glob(os.path.join(bad_dir, "*.yaml")) + glob.glob(os.path.join(bad_dir, "libs/*/types/*.yaml")))
    rejected = 0
    for f in bad:
        rel = os.path.relpath(f, bad_dir)
        if expanded_size(f) > 100000:  # an alias bomb: a validator would walk it without end
            if rel not in listed:
                fail(f"{rel} is an alias bomb; list it in tests/data/schema-agreement.txt")
            continue
        try:
            doc = load(f)
        except Exception:
            doc = None  # not YAML at all: rejected by any schema
        kind = kind_of(doc)
        errors = list(validators[kind].iter_errors(doc)) if kind else ["no file kind"]
        if errors:
            rejected += 1
            if rel in listed:
                fail(f"{rel} is listed in schema-agreement.txt but its schema rejects it now: remove the line")
        elif rel not in listed:
            fail(f"the schema accepts {rel}, which the loader rejects; make the schema reject it, or list it in "
                 f"tests/data/schema-agreement.txt with the reason a schema cannot")
    missing = [n for n in listed if not os.path.exists(os.path.join(bad_dir, n))]
    if missing:
        fail(f"schema-agreement.txt lists files that do not exist: {missing}")
    # Files sscs writes name their schema in a modeline, and validate against it.
    with tempfile.TemporaryDirectory() as tmp:
        p = run(sscs, root, ["simulate", "scenarios/drum-transfer/arm-loads-drum.yaml", "--out", tmp + "/run", "--quiet"])
        if p.returncode != 0:
            fail("simulate for the modeline", p)
        for kind in ("vault", "scenario"):
            f = os.path.join(tmp, "run", "resolved", kind + ".yaml")
            first = open(f, encoding="utf-8").readline()
            prefix = "# yaml-language-server: $schema="
            named = first[len(prefix):].strip()
            if not first.startswith(prefix) or os.path.realpath(named) != os.path.realpath(os.path.join(root, "schemas", kind + ".schema.json")):
                fail(f"resolved/{kind}.yaml starts with {first!r}, not a modeline naming schemas/{kind}.schema.json")
            errors = list(validators[kind].iter_errors(load(f)))
            if errors:
                fail(f"resolved/{kind}.yaml does not validate: {errors[0].message} at {list(errors[0].absolute_path)}")
    print(f"ok schemas ({len(good)} good files valid; {rejected} bad files rejected by the schemas, {len(listed)} listed)")


def fenced_blocks(text):
    """The fenced code blocks of a Markdown text, in order: (language, body) with the indentation
    of the fence removed."""
    blocks, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        stripped = lines[i].lstrip()
        if stripped.startswith("```"):
            indent = len(lines[i]) - len(stripped)
            lang, body = stripped[3:].strip(), []
            i += 1
            while i < len(lines) and not lines[i].lstrip().startswith("```"):
                body.append(lines[i][indent:] if lines[i][:indent].strip() == "" else lines[i])
                i += 1
            blocks.append((lang, "\n".join(body) + "\n"))
        i += 1
    return blocks


def section(text, heading):
    start = text.index(heading)
    end = text.find("\n## ", start + len(heading))
    return text[start:end if end >= 0 else len(text)]


def tutorials(sscs, root):
    """Every tutorial step as written in the docs (issue 17): the YAML blocks of README's tutorial
    and of docs/simulation.md's are taken out of the Markdown, written where the text says, and run;
    what the text says they do is checked."""
    readme = section(open(os.path.join(root, "README.md")).read(), "## Tutorial: a type, a vault")
    blocks = fenced_blocks(readme)
    with tempfile.TemporaryDirectory() as tmp:
        # 1. A type, 2. a vault: as written the last line is an input error, as the text says.
        type_yaml, vault_yaml = [b for lang, b in blocks if lang == "yaml"][:2]
        os.makedirs(os.path.join(tmp, "mylib", "types"))
        open(os.path.join(tmp, "mylib", "types", "crate.yaml"), "w").write(type_yaml)
        open(os.path.join(tmp, "store.yaml"), "w").write(vault_yaml)
        p = run(sscs, tmp, ["check", "store.yaml"])
        if p.returncode != 2 or "use an expr constraint for expressions" not in p.stderr:
            fail("README step 2: the bound with arithmetic should be an input error", p)
        fix = re.search(r"change it to\s+`(expr: \"[^`]*\")`", readme).group(1)
        bad_line = [l for l in vault_yaml.splitlines() if "last crate leaves a 2 m bay" in l][0]
        fixed = vault_yaml.replace(bad_line, re.sub(r"bound: \[.*\], severity", fix + ", severity", bad_line))
        open(os.path.join(tmp, "store.yaml"), "w").write(fixed)
        # 3. Check it: passes; --set aisle=3 prints what the text shows.
        p = run(sscs, tmp, ["check", "store.yaml"])
        if p.returncode != 0 or p.stdout.strip() != "3 passed, 0 failed, 0 warnings":
            fail("README step 3: the fixed vault should pass", p)
        shown = [b for lang, b in blocks if lang == "" and "--set" not in b][0]
        p = run(sscs, tmp, ["check", "store.yaml", "--set", "aisle=3"])
        if p.stdout != shown:
            fail(f"README step 3: --set aisle=3 prints\n{p.stdout}\nthe README shows\n{shown}", p)
        # 5. A robot that must reach: the objects and constraints added as the text says, then
        # every command of the block with its output as shown.
        robot = [b for lang, b in blocks if lang == "yaml"][2]
        obj = [l for l in robot.splitlines() if l.strip().startswith("- {type: arm6")]
        cons = [l for l in robot.splitlines() if l.strip().startswith("- {name:")]
        text = fixed.replace("constraints:\n", "\n".join(obj) + "\nconstraints:\n") + "\n".join(cons) + "\n"
        open(os.path.join(tmp, "store.yaml"), "w").write(text)
        session = [b for lang, b in blocks if lang == "" and "$ build/src/sscs" in b][0]
        for chunk in re.split(r"^\$ ", session, flags=re.M)[1:]:
            command, *expected = chunk.splitlines()
            args = shlex.split(command.split("#")[0])[1:]
            p = run(sscs, tmp, args)
            if p.stdout.splitlines() != expected:
                fail(f"README step 5: {command} prints\n{p.stdout}\nthe README shows\n" + "\n".join(expected), p)

    # docs/simulation.md: "Tutorial: your first scenario".
    sim = section(open(os.path.join(root, "docs", "simulation.md")).read(), "## Tutorial: your first scenario")
    steps = [b for lang, b in fenced_blocks(sim) if lang == "yaml"]
    with tempfile.TemporaryDirectory() as tmp:
        shutil.copy(os.path.join(root, "scenarios", "drum-transfer", "cell.yaml"), tmp)
        p = run(sscs, tmp, ["check", "cell.yaml"])
        if p.returncode != 0:
            fail("the tutorial's cell should pass its checks", p)
        header = steps[0][:steps[0].index("steps:\n") + len("steps:\n")]

        def simulate(name, text):
            open(os.path.join(tmp, "my-first.yaml"), "w").write(text)
            out = os.path.join(tmp, name)
            p = run(sscs, tmp, ["simulate", "my-first.yaml", "--out", out, "--quiet", "--no-frames"])
            events = [json.loads(l) for l in open(os.path.join(out, "events.jsonl"))] if os.path.isdir(out) else []
            summary = json.load(open(os.path.join(out, "summary.json"))) if os.path.isdir(out) else {}
            return p, events, summary

        # 1. Move joints: ok, 1.97 s; with j2: 20 the wrist strikes the drum twice.
        p, events, summary = simulate("step1", steps[0])
        if p.returncode != 0 or summary.get("status") != "ok" or round(summary["cycle_time"], 2) != 1.97:
            fail(f"simulation tutorial step 1: {summary.get('status')}, {summary.get('cycle_time')}", p)
        p, events, summary = simulate("step1b", steps[0].replace("j2: -20", "j2: 20"))
        hits = sorted((e["a"], e["b"]) for e in events if e["kind"] == "collision")
        if p.returncode != 1 or hits != [("Robot.link5", "Drum_1"), ("Robot.link6", "Drum_1")]:
            fail(f"simulation tutorial step 1 with j2: 20: collisions {hits}", p)
        # A move blocked by the drum: the tracking_error event says how far the tool ended from
        # its plan (over 1 m), not the 5 mm it first passed.
        p, events, summary = simulate("blocked", steps[0].replace("{j1: 0, j2: -20}", "{j1: 0, j2: 70, j3: 0}"))
        lags = [e for e in events if e["kind"] == "tracking_error"]
        if p.returncode != 1 or not lags or lags[0]["deviation"] < 0.5 or lags[0]["largest_at"] <= lags[0]["t"]:
            fail(f"simulation tutorial, a blocked move: tracking_error events {lags}", p)
        # It never arrived: its step ends short of the target, and the run has no cycle time (its
        # planned 1.97 s was said before).
        short = [st for st in summary.get("steps", []) if st.get("short_by")]
        ends = [e for e in events if e["kind"] == "step_end" and e.get("short_by")]
        if summary.get("cycle_time") is not None or not short or short[0]["short_by"] < 0.5 or len(ends) != len(short) or \
                "no cycle time (Robot's move_joints (step 1) ended" not in p.stdout:
            fail(f"simulation tutorial, a blocked move: cycle time {summary.get('cycle_time')}, steps short {short}", p)
        # 2. Move the tool: ok; a misspelt frame is an input error with "did you mean".
        p, events, summary = simulate("step2", header + steps[1])
        if p.returncode != 0 or summary.get("status") != "ok" or any(e["kind"] == "collision" for e in events):
            fail(f"simulation tutorial step 2: {[e for e in events if e['kind'] != 'step_start' and e['kind'] != 'step_end']}", p)
        p, _, _ = simulate("step2b", header + steps[1].replace("Drum_1.top", "Drum_1.tpo", 1))
        if p.returncode != 2 or "did you mean 'top'" not in p.stderr or "my-first.yaml:5:" not in p.stderr:
            fail("simulation tutorial step 2 with a misspelt frame", p)
        # 3. Pick and place: grasp, release, landed on the rack, at rest; ok.
        p, events, summary = simulate("step3", header + steps[2])
        kinds = [e["kind"] for e in events]
        landed = [e for e in events if e["kind"] == "landed"]
        if p.returncode != 0 or summary.get("status") != "ok" or not all(k in kinds for k in ("grasp", "release", "at_rest")) or \
                len(landed) != 1 or landed[0]["on"] != "Rack_A":
            fail(f"simulation tutorial step 3: {[e for e in events if e['kind'] not in ('step_start', 'step_end')]}", p)

    # docs/devices.md: "Tutorial: using a vendor's robot package" (issue 19).
    dev = section(open(os.path.join(root, "docs", "devices.md")).read(), "## Tutorial: using a vendor's robot package")
    blocks = fenced_blocks(dev)
    type_yaml, vault_yaml = [b for lang, b in blocks if lang == "yaml"][:2]
    sessions = [b for lang, b in blocks if lang == "" and b.startswith("$ sscs")]
    with tempfile.TemporaryDirectory() as tmp:
        # 1. The packages as they come, 2. the type, 3. the vault.
        for pkg in ("acme_rx6_support", "acme_rx6_moveit_config"):
            shutil.copytree(os.path.join(root, "tests", "data", "vendor", pkg), os.path.join(tmp, "vendor", pkg))
        type_path = os.path.join(tmp, "library", "types", "rx6.yaml")
        os.makedirs(os.path.dirname(type_path))
        open(type_path, "w").write(type_yaml)
        open(os.path.join(tmp, "cell.yaml"), "w").write(vault_yaml)

        def session(text, step):
            for chunk in re.split(r"^\$ ", text, flags=re.M)[1:]:
                command, *expected = chunk.splitlines()
                p = run(sscs, tmp, shlex.split(command)[1:])
                if p.stdout.splitlines() != expected:
                    fail(f"devices.md tutorial step {step}: {command} prints\n{p.stdout}\nthe text shows\n" + "\n".join(expected), p)

        # 4. It passes; without the srdf: line the forearm/wrist overlap fails both checks.
        session(sessions[0], 4)
        open(type_path, "w").write("".join(l for l in type_yaml.splitlines(True) if not l.startswith("srdf:")))
        session(sessions[1], "4 without the SRDF")
        # 2. joint_1 has its soft limits, ±2.5 rad; joint_limits: hard gives the hard ±2.967 rad.
        def joint_1(text):
            open(type_path, "w").write(text)
            p = run(sscs, tmp, ["types", "--library", "library"])
            return ([l for l in p.stdout.splitlines() if l.strip().startswith("joint_1 ")] + [""])[0]
        if "[-143.239448783, 143.239448783]" not in joint_1(type_yaml):
            fail(f"devices.md tutorial step 2: joint_1 should have its soft limits: {joint_1(type_yaml)}")
        if "[-169.996577815, 169.996577815]" not in joint_1(type_yaml + "joint_limits: hard\n"):
            fail(f"devices.md tutorial step 2: joint_limits: hard: {joint_1(type_yaml + 'joint_limits: hard' + chr(10))}")
        open(type_path, "w").write(type_yaml)
        # 6. The render shows the visuals (DAE material colours, the wrist's texture) as the
        # docs' picture does; the run's resolved/ holds the vendor files and reruns from anywhere.
        session(sessions[2], 6)
        compare_image(os.path.join(tmp, "rx6.png"), os.path.join(root, "docs", "img", "vendor-rx6.png"))
        _, _, rows = read_png(os.path.join(tmp, "rx6.png"))
        yellow = sum(1 for row in rows for x in range(0, len(row), 3)
                     if row[x] > 100 and 0.7 < row[x + 1] / row[x] < 0.9 and row[x + 2] < 40)
        if yellow < 1000:
            fail(f"devices.md tutorial step 6: the wrist's yellow texture colour covers {yellow} pixels")
        open(os.path.join(tmp, "move.yaml"), "w").write([b for lang, b in blocks if lang == "yaml"][2])
        command, *expected = sessions[3][2:].splitlines()
        p = run(sscs, tmp, shlex.split(command)[1:])
        mask = lambda lines: [re.sub(r"cycle time [0-9.]+ s", "cycle time T s", l) for l in lines]
        if p.returncode != 0 or mask(p.stdout.splitlines()) != mask(expected):
            fail(f"devices.md tutorial step 6: {command} prints\n{p.stdout}\nthe text shows\n" + "\n".join(expected), p)
        run1 = os.path.join(tmp, "run1")
        summary = json.load(open(os.path.join(run1, "summary.json")))
        copied = sorted(os.path.relpath(os.path.join(d, f), os.path.join(run1, "resolved"))
                        for d, _, fs in os.walk(os.path.join(run1, "resolved")) for f in fs)
        vendor = "library/urdf/vendor/acme_rx6_"
        want = [vendor + f for f in ("moveit_config/config/rx6.srdf", "support/meshes/visual/link_2.dae",
                                     "support/meshes/visual/link_3.dae", "support/meshes/visual/link_3.png",
                                     "support/urdf/rx6.urdf")]
        if "inputs_not_in_resolved" in summary or not all(w in copied for w in want):
            fail(f"devices.md tutorial step 6: resolved/ holds {copied}; not copied: {summary.get('inputs_not_in_resolved')}")
        if not any(i["path"].endswith("link_3.png") for i in summary["inputs"]):
            fail("devices.md tutorial step 6: the texture image is no input of the run")
        elsewhere = os.path.join(tmp, "elsewhere")
        os.makedirs(elsewhere)
        p = run(sscs, elsewhere, ["simulate", os.path.join(run1, "resolved", "scenario.yaml"), "--out", "run2", "--quiet", "--no-frames"])
        if p.returncode != 0:
            fail("devices.md tutorial step 6: the rerun from resolved/ in another folder", p)
        for f in ["events.jsonl", "trajectories/Robot.csv", "resolved/library/types/rx6.yaml"]:
            if open(os.path.join(run1, f), "rb").read() != open(os.path.join(elsewhere, "run2", f), "rb").read():
                fail(f"devices.md tutorial step 6: {f} differs between the run and its rerun")
        # A DAE naming its texture by absolute path (file://) names the copy in resolved/, so the
        # rerun from elsewhere reads the copy even after the vendor's folder is gone.
        dae = os.path.join(tmp, "vendor", "acme_rx6_support", "meshes", "visual", "link_3.dae")
        png = os.path.join(os.path.dirname(dae), "link_3.png")
        text = open(dae).read()
        open(dae, "w").write(text.replace("<init_from>link_3.png</init_from>", f"<init_from>file://{png}</init_from>"))
        p = run(sscs, tmp, ["simulate", "move.yaml", "--out", "run3", "--quiet", "--no-frames"])
        copy = os.path.join(tmp, "run3", "resolved", vendor + "support/meshes/visual/link_3.dae")
        if p.returncode != 0 or not os.path.exists(copy) or "<init_from>link_3.png</init_from>" not in open(copy).read():
            fail("devices.md tutorial step 6: a DAE naming its texture by absolute path keeps it in resolved/", p)
        shutil.move(os.path.join(tmp, "vendor"), os.path.join(tmp, "vendor-moved"))
        p = run(sscs, elsewhere, ["render", os.path.join(tmp, "run3", "resolved", "vault.yaml"), "--out", "rerun3.png"])
        if p.returncode != 0 or "warning" in p.stderr:
            fail("devices.md tutorial step 6: the resolved/ copy with a rewritten texture path renders", p)
        shutil.move(os.path.join(tmp, "vendor-moved"), os.path.join(tmp, "vendor"))
        # A warning of the import (a degenerate shape skipped) is in the reports CI reads: the text
        # summary's count, JSON's input_warnings and a SARIF warning at the type's urdf: line.
        urdf = os.path.join(tmp, "vendor", "acme_rx6_support", "urdf", "rx6.urdf")
        text = open(urdf).read()
        open(urdf, "w").write(text.replace('<link name="base_link">', '<link name="base_link">\n    <collision><geometry>'
                                           '<cylinder radius="0.1" length="0"/></geometry></collision>', 1))
        p = run(sscs, tmp, ["check", "cell.yaml"])
        if p.returncode != 0 or "; 1 input warning" not in p.stdout or "cylinder has length 0" not in p.stderr:
            fail("an import warning is counted in the text report", p)
        report = json.loads(run(sscs, tmp, ["check", "cell.yaml", "--format", "json"]).stdout)
        warned = report.get("input_warnings", [])
        if len(warned) != 1 or warned[0]["file"] != "vendor/acme_rx6_support/urdf/rx6.urdf" or warned[0]["line"] != 13 or "cylinder has length 0" not in warned[0]["message"]:
            fail(f"an import warning in the JSON report: {warned}")
        sarif = json.loads(run(sscs, tmp, ["check", "cell.yaml", "--format", "sarif"]).stdout)
        results = [r for r in sarif["runs"][0]["results"] if r["ruleId"] == "sscs/input-warning"]
        if len(results) != 1 or results[0]["level"] != "warning" or \
                results[0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] != "vendor/acme_rx6_support/urdf/rx6.urdf":
            fail(f"an import warning in the SARIF report: {results}")
        open(urdf, "w").write(text)
    print("ok tutorials")


def type_library(folder, types):
    """Writes each {name: text} type file into folder/lib/types (a vault's `library: [lib]`)."""
    os.makedirs(os.path.join(folder, "lib", "types"), exist_ok=True)
    for name, text in types.items():
        with open(os.path.join(folder, "lib", "types", f"{name}.yaml"), "w") as f:
            f.write(text)


def arrival(sscs, root):
    """A move arrives when its tool is where the plan puts it, in position and in orientation
    (review 22, F3: an arm's wrist spinning a held bar was stopped 90 deg short by a plate, its
    tool point on the wrist's axis, and the run gave a cycle time). Blocked: no cycle time, the
    step's `short_by` and `turned_by`, a tracking_error with its `turn`; free: ok, none."""
    block = ("sscs: 1\ntype: block\ndescription: a box from its origin corner\nattributes:\n"
             "  sx: {type: length, default: 0.05}\n  sy: {type: length, default: 0.05}\n  sz: {type: length, default: 1.5}\n"
             "geometry:\n  - box: {size: [sx, sy, sz], xyz: [\"sx/2\", \"sy/2\", \"sz/2\"]}\n")
    with tempfile.TemporaryDirectory() as tmp:
        type_library(tmp, {"block": block})
        for plate in (True, False):
            with open(os.path.join(tmp, "vault.yaml"), "w") as f:
                f.write("sscs: 1\nvault: ArmBar\nlibrary: [lib]\nobjects:\n"
                        "  - {type: room, name: Hall, length: 8 m, width: 8 m, height: 5 m, location: [-4, -4, 0]}\n"
                        "  - {type: arm6, name: R}\n" +
                        # (free: a bar 0.6 m long, that the wrist spins clear of the arm)
                        ("  - {type: block, name: Bar, location: [0.943, -1.2, 0.96], sx: 0.004, sy: 2.4, sz: 0.05}\n" if plate else
                         "  - {type: block, name: Bar, location: [0.943, -0.3, 0.96], sx: 0.004, sy: 0.6, sz: 0.05}\n") +
                        ("  - {type: block, name: Plate, location: [1.945, -0.0015, 0.9], sx: 0.15, sy: 0.003, sz: 0.1}\n" if plate else ""))
            for mode in ("physics", "fast"):
                scenario = os.path.join(tmp, f"{mode}.yaml")
                with open(scenario, "w") as f:
                    f.write(f"sscs: 1\nscenario: arm-bar\nvault: vault.yaml\nsim: {{mode: {mode}, timestep: 1 ms, limit: 30 s}}\n"
                            "steps:\n  - {device: R, grasp: Bar}\n  - {device: R, move_joints: {j6: 180}}\n")
                out = os.path.join(tmp, f"out-{mode}-{plate}")
                p = run(sscs, root, ["simulate", scenario, "--out", out, "--no-frames", "--quiet"])
                summary = json.load(open(os.path.join(out, "summary.json")))
                events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
                ends = [e for e in events if e["kind"] == "step_end" and e["step"] == 1]
                lags = [e for e in events if e["kind"] == "tracking_error"]
                what = f"the wrist spinning a held bar {'into a plate' if plate else 'in free space'} ({mode} mode)"
                if plate and mode == "physics":
                    if p.returncode != 1 or summary.get("cycle_time") is not None or not ends or \
                            not 80 < ends[0].get("turned_by", 0) < 100 or not lags or not lags[0]["turn"] > 80:
                        fail(f"{what}: stopped about 90 deg short, no cycle time, turned_by and a tracking_error: {summary.get('cycle_time')} {events}", p)
                if plate and mode == "fast":
                    # Handed to the physics from before the step that met the plate, as physics mode
                    # meets it: stopped as far, with the same collisions (review 22, F2: it was handed
                    # over a step's travel into the plate, pushed on 8 deg and hit its own link2).
                    pairs = lambda evs: sorted({tuple(sorted((e["a"], e["b"]))) for e in evs if e["kind"] == "collision"})
                    if summary.get("cycle_time") is not None or abs(ends[0].get("turned_by", 0) - physics_turn) > 1 or \
                            pairs(events) != physics_pairs:
                        fail(f"{what}: as physics mode, turned {physics_turn} deg off with {physics_pairs}: {events}", p)
                if plate and mode == "physics":
                    physics_turn = ends[0].get("turned_by", 0)
                    if summary["steps"][1].get("turned_by") != physics_turn:
                        fail(f"{what}: summary.json's step says turned_by as its step_end does: {summary['steps'][1]}", p)
                    physics_pairs = sorted({tuple(sorted((e["a"], e["b"]))) for e in events if e["kind"] == "collision"})
                if not plate and (p.returncode != 0 or lags or "turned_by" in ends[0] or summary.get("cycle_time") is None):
                    fail(f"{what}: ok, it arrived: {events}", p)
    print("ok arrival")


def reach_turning(sscs, root):
    """The margin of a failing reach target for a device that turns (review 22, F4): minus the
    closest a pose free of collision comes, never better than the truth (it read the closest
    pose's error in collision, up to 0.43 m better) and within 1 % of it here. Truths by a brute
    force over the swing's two joints (tests/data/reach-turning: a swing arm with a hoist, a
    pedestal in its way, a drum carried)."""
    data = "tests/data/reach-turning"
    cases = [("swing.yaml", [], {"far": 1.05168, "farm": 1.05168}),
             ("carry.yaml", [], {"over": 0.7423, "overm": 0.7423}),
             ("carry.yaml", ["--set", "ty=0.3"], {"over": 0.4577, "overm": 0.4577}),
             ("order.yaml", [], {"far": 1.05168, "side": 0.197056, "sidec": 0.5852})]
    for vault, extra, truth in cases:
        p = run(sscs, root, ["check", f"{data}/{vault}", "--format", "json"] + extra)
        margins = {r["constraint"]: r["margin"] for r in json.loads(p.stdout)["results"]}
        for name, error in truth.items():
            got = -margins.get(name, 0)
            if got < error - 2e-4 or got > error * 1.01:
                fail(f"{vault} {' '.join(extra)} {name}: margin -{got}, the closest free pose is {error} m off (by brute force)", p)
    print("ok reach_turning")


def worst_margin(sscs, root):
    """A broken rule's event says the worst margin of its episode and when, not only the first
    (review 22, D1: a carried drum passing another 15 mm away under a 20 mm rule said -0.1 mm,
    where it started failing; the truth is -5 mm). At 1 and 1000 Hz, in both modes: the worst
    is the pair's certified closest approach less the gap, within a physics step's travel of the
    truth, and never above it."""
    with tempfile.TemporaryDirectory() as tmp:
        for rate in (1, 1000):
            for mode in ("physics", "fast"):
                text = open(os.path.join(root, "tests/data/rules/gantry-past-drum-run.yaml")).read()
                text = text.replace("rate: 1 Hz", f"rate: {rate} Hz").replace("mode: physics", f"mode: {mode}")
                text = text.replace("vault: gantry-past-drum.yaml", f"vault: {os.path.join(root, 'tests/data/rules/gantry-past-drum.yaml')}")
                scenario = os.path.join(tmp, f"{mode}-{rate}.yaml")
                open(scenario, "w").write(text)
                out = os.path.join(tmp, f"out-{mode}-{rate}")
                p = run(sscs, root, ["simulate", scenario, "--out", out, "--no-frames", "--quiet", "--allow-outside-root"])
                events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
                rules = [e for e in events if e["kind"] == "constraint"]
                if p.returncode != 1 or len(rules) != 1 or not -0.0065 <= rules[0].get("worst_margin", 0) <= -0.005 + 1e-6 or \
                        not 7.0 <= rules[0].get("worst_at", 0) <= 7.2 or rules[0]["worst_margin"] > rules[0]["margin"]:
                    fail(f"{mode} at {rate} Hz: one rule event, its worst margin about -0.005 m near 7.1 s: {rules}", p)
        # A drum let go exactly 50 mm above the floor is set down, not dropped (it sinks 0.27 um
        # into the floor: it was `displaced`, falling 0.050000206 m; review 22).
        out = os.path.join(tmp, "set-down")
        p = run(sscs, root, ["simulate", "tests/data/rules/set-down-at-50mm.yaml", "--out", out, "--no-frames", "--quiet"])
        if p.returncode != 0 or any(json.loads(line)["kind"] == "displaced" for line in open(os.path.join(out, "events.jsonl"))):
            fail("a drum let go exactly 50 mm up is set down: ok, not displaced", p)
    print("ok worst_margin")


def tunnel(sscs, root):
    """A part or a carried load that goes through a thin obstacle within one physics step (no
    step sees them touch) is a collision all the same, in both modes (review 22, F1: a 4 mm blade
    turning through a 5 mm plate, and a sheet carried through a 3 mm plate at a 10 ms step, ran
    `ok`). Random speeds, plate angles and thicknesses: through the plate, a collision of the pair,
    no deeper than the overlap; a plate 1-5 mm beyond the blade's tip, none."""
    rng = random.Random(22)
    with tempfile.TemporaryDirectory() as tmp:
        type_library(tmp, {
            "blade": "sscs: 1\ntype: blade\nkind: device\ndescription: a fast turning arm, its outer part a 4 mm blade\n"
                     "parts:\n  - name: base\n    geometry: [{cylinder: {radius: 0.2, length: 0.9, xyz: [0, 0, 0.45]}}]\n    mass: 100\n"
                     "  - name: arm\n    parent: base\n    joint: {name: th, type: revolute, axis: [0, 0, 1], xyz: [0, 0, 1.0],\n"
                     "            limits: {min: -180, max: 180, velocity: 720, acceleration: 7200, effort: 100000}}\n"
                     "    geometry: [{box: {size: [1.8, 0.004, 0.2], xyz: [1.1, 0, 0]}}]\n    mass: 5\n"
                     "tool: {part: arm, xyz: [2.0, 0, 0]}\nhome: {th: 0}\n",
            "block": "sscs: 1\ntype: block\ndescription: a box from its origin corner\nattributes:\n"
                     "  sx: {type: length, default: 0.05}\n  sy: {type: length, default: 0.05}\n  sz: {type: length, default: 1.5}\n"
                     "geometry:\n  - box: {size: [sx, sy, sz], xyz: [\"sx/2\", \"sy/2\", \"sz/2\"]}\n"})
        def simulate(name, objects, steps, mode, timestep):
            with open(os.path.join(tmp, f"{name}-vault.yaml"), "w") as f:
                f.write(f"sscs: 1\nvault: Tunnel\nlibrary: [lib]\nobjects:\n{objects}")
            scenario = os.path.join(tmp, f"{name}.yaml")
            with open(scenario, "w") as f:
                f.write(f"sscs: 1\nscenario: {name}\nvault: {name}-vault.yaml\nsim: {{timestep: {timestep} ms, limit: 30 s, mode: {mode}}}\n"
                        f"record:\n  trajectory: {{rate: 1 Hz}}\nsteps:\n{steps}")
            out = os.path.join(tmp, f"out-{name}")
            p = run(sscs, root, ["simulate", scenario, "--out", out, "--no-frames", "--quiet", "--force"])
            if p.returncode not in (0, 1):
                fail(f"{name}: simulate exited {p.returncode}", p)
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            return [e for e in events if e["kind"] == "collision"], p
        cases = 0
        for case in range(6):
            # The blade turns from 0 to 170 degrees at up to 360-720 deg/s (its tip 13-25 mm a step).
            speed = rng.uniform(50, 100)
            ang, thick = rng.uniform(20, 150), rng.uniform(0.003, 0.006)
            a = math.radians(ang)
            through = case < 4
            r0 = 1.6 if through else 2.0 + rng.uniform(0.001, 0.005)
            plate = (f"  - {{type: block, name: Plate, sx: 0.3, sy: {thick:.4f}, sz: 1.2, orientation: [0, 0, {ang:.3f} deg], "
                     f"location: [{r0 * math.cos(a) + thick / 2 * math.sin(a):.6f}, {r0 * math.sin(a) - thick / 2 * math.cos(a):.6f}, 0]}}\n")
            objects = "  - {type: room, name: Hall, length: 8 m, width: 8 m, height: 5 m, location: [-4, -4, 0]}\n  - {type: blade, name: B}\n" + plate
            for mode in ("physics", "fast"):
                found, p = simulate(f"blade-{case}-{mode}", objects, f"  - {{device: B, move_joints: {{th: 170}}, speed: {speed:.1f}%}}\n", mode, 1)
                what = f"blade case {case} ({speed:.0f}% of 720 deg/s, plate at {ang:.1f} deg, {thick * 1000:.1f} mm, {'through' if through else 'beyond the tip'}, {mode})"
                pairs = {(e["a"], e["b"]) for e in found}
                if through and pairs != {("B.arm", "Plate")}:
                    fail(f"{what}: the blade went through the plate, collisions {pairs}", p)
                if through and not (0 < max(e["depth"] for e in found) <= (0.004 + thick) / 2 + 1e-4):
                    fail(f"{what}: depth {[e['depth'] for e in found]}, the overlap is {(0.004 + thick) / 2:.4f} m deep", p)
                if not through and found:
                    fail(f"{what}: no collision expected, found {found}", p)
                cases += 1
        for case in range(3):
            # Slower (90-200 deg/s), the blade is stopped by the plate in physics mode; fast mode,
            # handed over from before the step that met it, stops as far (review 22, F2: it went
            # through, cycle time 0.97 s, against 3.55 m short).
            speed, ang = rng.uniform(12.5, 28), rng.uniform(20, 150)
            a = math.radians(ang)
            plate = (f"  - {{type: block, name: Plate, sx: 0.3, sy: 0.005, sz: 1.2, orientation: [0, 0, {ang:.3f} deg], "
                     f"location: [{1.6 * math.cos(a) + 0.0025 * math.sin(a):.6f}, {1.6 * math.sin(a) - 0.0025 * math.cos(a):.6f}, 0]}}\n")
            objects = "  - {type: room, name: Hall, length: 8 m, width: 8 m, height: 5 m, location: [-4, -4, 0]}\n  - {type: blade, name: B}\n" + plate
            short = {}
            for mode in ("physics", "fast"):
                found, p = simulate(f"stopped-{case}-{mode}", objects, f"  - {{device: B, move_joints: {{th: 170}}, speed: {speed:.1f}%}}\n", mode, 1)
                ends = [json.loads(line) for line in open(os.path.join(tmp, f"out-stopped-{case}-{mode}", "events.jsonl"))]
                short[mode] = next((e.get("short_by") for e in ends if e["kind"] == "step_end" and e["step"] == 0), None)
                cases += 1
            if short["physics"] is None or short["fast"] is None or abs(short["physics"] - short["fast"]) > 0.01:
                fail(f"blade stopped by a plate at {ang:.1f} deg ({speed:.0f}%): short by {short} in the two modes")
        for case in range(2):
            # A gantry carries a sheet on edge through a 3 mm plate at a 10 ms step (10 mm a step).
            sheet = rng.uniform(0.002, 0.004)
            objects = ("  - {type: room, name: Hall, length: 10 m, width: 8 m, height: 5 m}\n"
                       "  - {type: gantry, name: G, parent: Hall, location: [1, 1, 0]}\n"
                       "  - {type: block, name: Stand, parent: Hall, location: [1.6, 1.0, 0], sx: 0.6, sy: 1.0, sz: 0.3}\n"
                       f"  - {{type: block, name: Sheet, parent: Hall, location: [{1.9 - sheet / 2:.4f}, 1.2, 0.3], sx: {sheet:.4f}, sy: 0.6, sz: 0.6}}\n"
                       f"  - {{type: block, name: Plate, parent: Hall, location: [{rng.uniform(3.5, 4.2):.4f}, 0.5, 0], sx: 0.003, sy: 2.0, sz: 1.5}}\n")
            steps = (f"  - {{device: G, move_to: {{target: Sheet, offset: {{xyz: [{sheet / 2:.4f}, 0.3, 0.6], rpy: [180, 0, 0]}}}}}}\n"
                     "  - {device: G, grasp: Sheet}\n  - {device: G, move_joints: {z: 0.3}}\n  - {device: G, move_joints: {x: 4.5}}\n")
            for mode in ("physics", "fast"):
                found, p = simulate(f"sheet-{case}-{mode}", objects, steps, mode, 10)
                if ("Sheet", "Plate") not in {(e["a"], e["b"]) for e in found} and ("Plate", "Sheet") not in {(e["a"], e["b"]) for e in found}:
                    fail(f"sheet case {case} ({sheet * 1000:.1f} mm, {mode}): carried through a 3 mm plate, collisions {found}", p)
                cases += 1
    print(f"ok tunnel: {cases} runs")


def sweep_reuse(sscs, root):
    """A sweep worker reuses collision answers of shapes a variant did not move (issue 20): every
    variant's report.json, with one worker and with two, is byte-identical to the report of its
    own `sscs check --set ...` process, which remembers nothing. The demo vault's variants move
    racks into the robot's reach, so reach, no_overlap and clearance all hit remembered answers."""
    variants = [(a, r, b) for a in ("1.4", "2.2") for r in (2, 4) for b in (3,)]  # (a crowded variant's reach costs seconds)
    with tempfile.TemporaryDirectory() as tmp:
        study = os.path.join(tmp, "reuse.yaml")
        open(study, "w").write("sscs: 1\nsweep: reuse\nvault: " + os.path.join(root, "scenarios/demo/demo.yaml") + "\n"
                               "vary:\n  aisle: {values: [1.4 m, 2.2 m]}\n  rows: {values: [2, 4]}\n  bays: {values: [3]}\n"
                               "metrics:\n  min_margin: \"min_margin()\"\n")
        alone = []
        for i, (a, r, b) in enumerate(variants):
            out = os.path.join(tmp, f"check-{i}.json")
            p = run(sscs, root, ["check", os.path.join(root, "scenarios/demo/demo.yaml"), "--set", f"aisle={a} m", "--set", f"rows={r}", "--set", f"bays={b}",
                                 "--format", "json", "--out", out, "--quiet"])
            if p.returncode != 1:
                fail(f"check of variant {i}", p)
            alone.append(open(out, "rb").read())
        for jobs in ("1", "2"):
            out = os.path.join(tmp, f"jobs{jobs}")
            p = run(sscs, root, ["sweep", study, "--out", out, "--jobs", jobs, "--quiet", "--allow-outside-root"])
            if p.returncode != 1 or "swept 4 variants: 0 pass, 4 fail, 0 error" not in p.stdout:
                fail(f"the reuse sweep with --jobs {jobs}", p)
            for i, (a, r, b) in enumerate(variants):
                report = open(os.path.join(out, f"{i}-aisle={a}m-rows={r}-bays={b}", "report.json"), "rb").read()
                if report != alone[i]:
                    fail(f"--jobs {jobs}: variant {i} (aisle {a} m, rows {r}, bays {b}): its report.json differs from "
                         f"its own check's (a remembered answer that is not what the check computes)")
    print("ok sweep_reuse")


def certified(sscs, root):
    """Issue 36, item 1: a run's min_clearance is a lower bound over the whole motion, not over
    its samples. Random fast moves of every standard device (gantry, bridge crane, both arms, AGV,
    forklift) past a 5 cm post standing beside the tool's path: logged at 1-4 Hz (the samples straddle the post) the certified bound is
    never above the reference logged at the physics rate (1000 Hz, 250-1000x the sample rate) by
    more than half a physics step's travel, and never far below it. And a 5 mm plate where the
    tool is half-way: across the path, going through it is a collision event and a negative
    min_clearance at any log rate; beside it along the path, the bound holds as for the post."""
    rng = random.Random(36)
    devices = [
        ("gantry", "{type: gantry, name: D, parent: Cell, location: [1, 1, 0], x_stroke: 6 m, y_stroke: 3 m}",
         lambda: ({"x": rng.uniform(0, 1), "y": rng.uniform(0, 3), "z": rng.uniform(0, 1.2)}, {"x": rng.uniform(4, 6)})),
        ("bridge_crane", "{type: bridge_crane, name: D, parent: Cell, location: [0.3, 0.3, 0], runway_length: 11 m, span: 7 m, rail_height: 4.2 m, lift: 3 m}",
         lambda: ({"travel": rng.uniform(0, 2), "traverse": rng.uniform(0, 4), "hoist": rng.uniform(1, 2.5)}, {"travel": rng.uniform(6, 7.9)})),
        ("arm6", "{type: arm6, name: D, parent: Cell, location: [6, 4, 0]}",
         lambda: ({"j1": rng.uniform(-150, -90), "j2": rng.uniform(-10, 20), "j3": rng.uniform(0, 40)}, {"j1": rng.uniform(90, 150)})),
        ("ur5", "{type: ur5, name: D, parent: Cell, location: [6, 4, 0.8]}",
         lambda: ({"shoulder_pan": rng.uniform(-150, -90), "shoulder_lift": rng.uniform(-100, -80), "elbow": rng.uniform(30, 80)},
                  {"shoulder_pan": rng.uniform(90, 150)})),
        ("agv", "{type: agv, name: D, parent: Cell, location: [1.5, 4, 0]}",
         lambda: ({"x": rng.uniform(0, 0.5), "y": rng.uniform(-0.5, 0.5)}, {"x": rng.uniform(6, 8)})),
        ("forklift", "{type: forklift, name: D, parent: Cell, location: [1.5, 4, 0]}",
         lambda: ({"x": rng.uniform(0, 0.5), "lift": rng.uniform(0, 1)}, {"x": rng.uniform(6, 8)})),
    ]
    # How far beside the tool the post stands: beyond the device's half-width (m).
    beside = {"gantry": (0.18, 0.3), "bridge_crane": (0.18, 0.3), "arm6": (0.18, 0.3), "ur5": (0.12, 0.25),
              "agv": (0.7, 0.9), "forklift": (0.9, 1.2)}
    # The tool point moves at most this fast in these moves (m/s): half a 1-ms step's travel is
    # how far a sampled reference may lie above the bound.
    slack = 3.0 * 0.001 / 2
    checked = plates = 0
    with tempfile.TemporaryDirectory() as tmp:
        type_library(tmp, {"plate": "sscs: 1\ntype: plate\ndescription: a thin plate centred on its origin, x along it, y through it\n"
                                    "attributes:\n  length: {type: length, default: 0.6, min: 0.01}\n"
                                    "  thickness: {type: length, default: 0.005, min: 0.001}\n  height: {type: length, default: 1, min: 0.01}\n"
                                    "geometry:\n  - box: {size: [length, thickness, height], xyz: [0, 0, \"height/2\"]}\n"})
        def simulate(name, vault, start, end, rate, mode="physics"):
            with open(os.path.join(tmp, "vault.yaml"), "w") as f:
                f.write(vault)
            scenario = os.path.join(tmp, f"{name}.yaml")
            with open(scenario, "w") as f:
                f.write(f"sscs: 1\nscenario: {name}\nvault: vault.yaml\nsim: {{timestep: 1 ms, limit: 60 s, mode: {mode}}}\n"
                        f"record:\n  trajectory: {{rate: {rate} Hz}}\nsteps:\n"
                        f"  - {{device: D, move_joints: {json.dumps(start)}}}\n  - {{device: D, move_joints: {json.dumps(end)}}}\n")
            out = os.path.join(tmp, f"out-{name}")
            p = run(sscs, root, ["simulate", scenario, "--out", out, "--no-frames", "--quiet", "--force"])
            if p.returncode not in (0, 1):
                fail(f"{name}: simulate exited {p.returncode}", p)
            summary = json.load(open(os.path.join(out, "summary.json")))
            return summary, os.path.join(out, "trajectories", "D.csv")
        for kind, device, moves in devices:
            for case in range(3):
                start, end = moves()
                room = "sscs: 1\nvault: Certified\nobjects:\n  - {type: room, name: Cell, length: 12 m, width: 8 m, height: 6 m}\n  - " + device + "\n"
                # Where the tool is half-way through the second move: a post beside it there.
                _, csv_path = simulate(f"{kind}-{case}-probe", room, start, end, 1000)
                rows = list(csv.DictReader(open(csv_path)))
                moving = [r for r in rows if float(r["t"]) > 0.5 * float(rows[-1]["t"])]
                at = moving[len(moving) // 4]
                side = rng.choice([-1, 1]) * rng.uniform(*beside[kind])
                post = (f"  - {{type: wall, name: Post, parent: Cell, location: [{float(at['tool_x']) + side:.4f}, "
                        f"{float(at['tool_y']) + side:.4f}, 0], length: 0.1 m, thickness: 0.05 m, height: {max(0.5, float(at['tool_z']) + 0.3):.3f} m}}\n")
                vault = room + post
                reference, _ = simulate(f"{kind}-{case}-ref", vault, start, end, 1000)
                low_rate = rng.choice([1, 2, 4])
                for mode in ("physics", "fast"):  # fast mode certifies the motion as physics mode does
                    sampled, _ = simulate(f"{kind}-{case}-low", vault, start, end, low_rate, mode)
                    ref, low = reference["min_clearance"], sampled["min_clearance"]
                    what = f"{kind} case {case} ({start} -> {end}, post {side:+.3f} m beside, {low_rate} Hz, {mode} mode)"
                    if not ref or not low or not low.get("certified") or not ref.get("certified"):
                        fail(f"{what}: no certified min_clearance: {ref} / {low}")
                    if low["distance"] > ref["distance"] + slack + 1e-9:
                        fail(f"{what}: the bound at {low_rate} Hz, {low['distance']} m ({low['a']} / {low['b']}), is above "
                             f"the reference at 1000 Hz, {ref['distance']} m: the motion between samples was not certified")
                    if low["distance"] < ref["distance"] - 0.002:
                        fail(f"{what}: the bound at {low_rate} Hz, {low['distance']} m, is far below the reference {ref['distance']} m")
                    checked += 1
                # A 5 mm plate where the tool is then: across its path (the move goes through it: a
                # collision event, whatever the log rate, and a negative min_clearance), or beside
                # it along the path (the bound as for the post).
                # Where the tool is a third into the second move, and its heading there.
                probe_events = [json.loads(line) for line in open(os.path.join(tmp, f"out-{kind}-{case}-probe", "events.jsonl"))]
                second = next(e["t"] for e in probe_events if e["kind"] == "step_start" and e.get("step") == 1)
                in_second = [r for r in rows if float(r["t"]) >= second]
                k = rows.index(in_second[len(in_second) // 3])
                here, before, after = rows[k], rows[max(0, k - 20)], rows[min(len(rows) - 1, k + 20)]
                dx, dy = float(after["tool_x"]) - float(before["tool_x"]), float(after["tool_y"]) - float(before["tool_y"])
                heading = math.atan2(dy, dx)
                through = case % 2 == 0
                cx, cy = float(here["tool_x"]), float(here["tool_y"])
                if through:
                    yaw = math.degrees(heading) + 90  # its length across the path
                else:
                    off = side * 1.5 + math.copysign(0.1, side)  # the plate is long: clear of the device's widest part
                    if kind in ("arm6", "ur5") and (-math.sin(heading) * (cx - 6) + math.cos(heading) * (cy - 4)) * off < 0:
                        off = -off  # an arm's tool sweeps a circle: the plate outside it, not across the arm
                    cx, cy = cx - off * math.sin(heading), cy + off * math.cos(heading)
                    yaw = math.degrees(heading)
                plate = (f"  - {{type: plate, name: Plate, parent: Cell, location: [{cx:.4f}, {cy:.4f}, 0], orientation: [0, 0, {yaw:.3f}], "
                         f"length: 0.6 m, height: {max(0.5, float(here['tool_z']) + 0.3):.3f} m}}\n")
                vault = room.replace("objects:\n", "library: [lib]\nobjects:\n") + plate
                low_rate = rng.choice([1, 2, 4])
                if not through:
                    reference, _ = simulate(f"{kind}-{case}-plate-ref", vault, start, end, 1000)
                for mode in ("physics", "fast"):
                    sampled, _ = simulate(f"{kind}-{case}-plate-low", vault, start, end, low_rate, mode)
                    events = [json.loads(line) for line in open(os.path.join(tmp, f"out-{kind}-{case}-plate-low", "events.jsonl"))]
                    hits = [e for e in events if e["kind"] == "collision" and "Plate" in (e["a"], e["b"])]
                    low = sampled["min_clearance"]
                    what = (f"{kind} case {case} ({start} -> {end}, a 5 mm plate {'across' if through else 'beside'} the path, "
                            f"{low_rate} Hz, {mode} mode)")
                    if through:
                        if not hits or sampled["status"] == "ok" or not low or low["distance"] >= 0:
                            fail(f"{what}: going through the plate is a collision and a negative min_clearance: {sampled['status']}, {low}, {events}")
                    else:
                        ref = reference["min_clearance"]
                        if hits or not ref or not low or not low.get("certified"):
                            fail(f"{what}: passing beside the plate touches nothing and is certified: {low} / {ref} {hits}")
                        if low["distance"] > ref["distance"] + slack + 1e-9 or low["distance"] < ref["distance"] - 0.002:
                            fail(f"{what}: the bound {low['distance']} m against the reference at 1000 Hz {ref['distance']} m")
                    plates += 1
        # Review 21: an arm6's link5 (its farthest corner 1.0181478 m from the j1 axis) swings
        # j1 0 -> 90 deg past a 2 cm post whose near face stands 1.018148 + 0.03 m from the axis at
        # 45 deg: 0.030000 m by hand. Fast mode's figure is within its 0.1 mm tolerance of that at
        # 1, 10 and 1000 Hz (it read 0.029814, 0.029696 and 0.028364: a step a run takes instead
        # of gliding kept its whole-step bound, and the halving stopped at an eighth of a step).
        truth = 1.018148 + 0.03 - math.hypot(1.015, 0.08)
        r0 = 1.018148 + 0.01 + 0.03
        arm = ("sscs: 1\nvault: ArmPost\nlibrary: [lib]\nobjects:\n  - {type: room, name: Cell, length: 12 m, width: 8 m, height: 6 m}\n"
               "  - {type: arm6, name: D, parent: Cell, location: [6, 4, 0]}\n"
               f"  - {{type: plate, name: Post, parent: Cell, location: [{6 + r0 * math.cos(math.pi / 4):.9f}, {4 + r0 * math.sin(math.pi / 4):.9f}, 0], "
               "orientation: [0, 0, 45], length: 0.02 m, thickness: 0.02 m, height: 2 m}\n")
        for rate in (1, 10, 1000):
            summary, _ = simulate(f"arm-post-{rate}", arm, {"j1": 0}, {"j1": 90}, rate, "fast")
            mc = summary["min_clearance"]
            if not mc or not mc.get("certified") or {mc["a"], mc["b"]} != {"D.link5", "Post"} or not truth - 1.2e-4 <= mc["distance"] <= truth + 1e-6:
                fail(f"an arm past a post {truth:.6f} m away, logged at {rate} Hz in fast mode: min_clearance {mc}")
    # A clearance rule broken between samples (issue 36's example: a gantry's gripper passing a
    # post 2 cm beside its path, "keep 3 cm from the post"): at 1-4 Hz the run finds what it finds
    # at 1000 Hz, the rule's constraint event at the same time and margin, over random posts and
    # rule gaps (some kept, some broken).
    rules = agreed = 0
    with tempfile.TemporaryDirectory() as tmp:
        def constraint_events(name, vault, steps):
            """The constraint events and exit status of `steps` in `vault` logged at 1000 Hz, then
            at a random 1, 2 or 4 Hz."""
            open(os.path.join(tmp, "vault.yaml"), "w").write(vault)
            found = []
            for rate in (1000, rng.choice([1, 2, 4])):
                path, out = os.path.join(tmp, f"{name}{rate}.yaml"), os.path.join(tmp, f"out-{name}{rate}")
                open(path, "w").write(f"sscs: 1\nscenario: {name}-{rate}\nvault: vault.yaml\nsim: {{timestep: 1 ms, limit: 60 s}}\n"
                                      f"record:\n  trajectory: {{rate: {rate} Hz}}\nsteps:\n{steps}")
                p = run(sscs, root, ["simulate", path, "--out", out, "--quiet", "--no-frames", "--force"])
                found.append(([json.loads(line) for line in open(os.path.join(out, "events.jsonl")) if json.loads(line)["kind"] == "constraint"],
                              p.returncode))
            return found
        for case in range(8):
            gap = round(rng.uniform(0.005, 0.06), 4)
            y = round(2.67 + rng.uniform(-0.02, 0.03), 4)
            vault = ("sscs: 1\nvault: PostRule\nobjects:\n  - {type: room, name: Cell, length: 12 m, width: 8 m, height: 6 m}\n"
                     "  - {type: gantry, name: G, parent: Cell, location: [1, 1, 0], x_stroke: 6 m, y_stroke: 3 m}\n"
                     f"  - {{type: wall, name: Post, parent: Cell, location: [{rng.uniform(3.5, 5):.3f}, {y}, 0], length: 0.1 m, "
                     "thickness: 0.05 m, height: 1.5 m}\n"
                     f"constraints:\n  - {{name: keep off the post, clearance: {{a: G, b: Post, min: {gap} m}}}}\n"
                     # A second rule on the same pair, wider and a warning: a pose that breaks it
                     # alone breaks only it (a new user saw the narrower one reported broken).
                     f"  - {{name: keep well off the post, clearance: {{a: G, b: Post, min: {round(gap * 1.7, 4)} m}}, severity: warning}}\n")
            (ref, ref_rc), (low, low_rc) = constraint_events(
                "post", vault, f"  - {{device: G, move_joints: {{x: 0.5, y: 1.0, z: 1.0}}}}\n  - {{device: G, move_joints: {{x: {rng.uniform(5, 5.9):.3f}}}}}\n")
            ref, low = (sorted(events, key=lambda e: (e["constraint"], e["t"])) for events in (ref, low))
            what = f"post rule case {case} (min {gap} m):\n{vault}"
            if len(ref) != len(low) or ref_rc != low_rc:
                fail(f"{what}the rule's events at 1000 Hz {ref} and at a low rate {low} differ")
            for a, b in zip(ref, low):
                if a["constraint"] != b["constraint"] or a["margin"] >= 0 or b["margin"] >= 0:
                    fail(f"{what}the rules' events differ or pass: {ref} / {low}")
                if abs(a["t"] - b["t"]) > 0.02 or abs(a["margin"] - b["margin"]) > 5e-4:
                    fail(f"{what}the rule broken at {a['t']} s by {a['margin']} m at 1000 Hz, at {b['t']} s by {b['margin']} m at a low rate")
            rules += 1
            agreed += bool(ref)
        # Two devices moving at once: two arms facing each other swing their links past each
        # other (link5's corner 1.01815 m from each axis, so the closest approach is `gap`), with a
        # 5 cm rule on the pair. At 1 Hz, in both modes, the rule's event and the min_clearance
        # are those of 1000 Hz (the other device was once bounded standing where it ended: 0.5 m
        # "into" each other at 1 Hz, and the rule unseen).
        for case in range(3):
            gap = round(rng.uniform(0.03, 0.07), 4)
            vault = ("sscs: 1\nvault: TwoArms\nobjects:\n  - {type: room, name: Hall, length: 8 m, width: 6 m, height: 4 m}\n"
                     "  - {type: arm6, name: A, parent: Hall, location: [3, 3, 0], j1: -60}\n"
                     f"  - {{type: arm6, name: B, parent: Hall, location: [{3 + 2 * 1.01815 + gap:.5f}, 3, 0], orientation: [0, 0, 180], j1: 60}}\n"
                     "constraints:\n  - {name: arms apart, clearance: {a: A, b: B, min: 0.05 m}}\n")
            steps = "  - parallel:\n    - {device: A, move_joints: {j1: 60}}\n    - {device: B, move_joints: {j1: -60}}\n"
            found = {}
            for rate, mode in ((1000, "physics"), (1, "physics"), (1, "fast")):
                open(os.path.join(tmp, "vault.yaml"), "w").write(vault)
                path, out = os.path.join(tmp, f"arms{rate}{mode}.yaml"), os.path.join(tmp, f"out-arms{rate}{mode}")
                open(path, "w").write(f"sscs: 1\nscenario: arms\nvault: vault.yaml\nsim: {{timestep: 1 ms, limit: 60 s, mode: {mode}}}\n"
                                      f"record:\n  trajectory: {{rate: {rate} Hz}}\nsteps:\n{steps}")
                run(sscs, root, ["simulate", path, "--out", out, "--quiet", "--no-frames", "--force"])
                events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl")) if json.loads(line)["kind"] == "constraint"]
                found[(rate, mode)] = (events, json.load(open(os.path.join(out, "summary.json")))["min_clearance"])
            ref_events, ref_mc = found[(1000, "physics")]
            for key in ((1, "physics"), (1, "fast")):
                events, mc = found[key]
                what = f"two arms, gap {gap} m, at {key[0]} Hz in {key[1]} mode"
                # (At 1000 Hz the rule may break twice, two corners passing 52 ms apart; between
                # two samples it starts failing once: the first is compared.)
                if bool(events) != (gap < 0.05) or bool(ref_events) != (gap < 0.05):
                    fail(f"{what}: the 5 cm rule is broken exactly when the gap is under 5 cm: {events} (1000 Hz: {ref_events})")
                for a, b in zip(ref_events[:1], events[:1]):
                    if abs(a["t"] - b["t"]) > 0.02 or abs(a["margin"] - b["margin"]) > 5e-4:
                        fail(f"{what}: the rule broken at {b['t']} s by {b['margin']} m, at 1000 Hz at {a['t']} s by {a['margin']} m")
                # Never above the true closest approach (`gap`, and the 2.2 µm link5's corner lies
                # inside the 1.01815 m written), nor far below 1000 Hz's; a device's bound in fast
                # mode is halved below the step, with both arms' plans, so it may lie above physics
                # mode's by more than one device's half-step (0.046904 against 0.043560 for 0.047).
                if not mc or not mc["certified"] or mc["distance"] > gap + 1e-5 or mc["distance"] < ref_mc["distance"] - 0.002:
                    fail(f"{what}: min_clearance {mc} against the gap {gap} m ({ref_mc} at 1000 Hz)")
            rules += 1
            agreed += bool(ref_events)
        # Bounds and expressions that read the motion, checked at every physics step: a gantry
        # carrying a drum travels 2 m while lowering it to a random height, and turns straight
        # back up, with a rule on the drum's bounding box and one on the bridge's travel, both
        # broken only around that instant; at 1-4 Hz the samples straddle it, and the run reports
        # the same events, at the same step and margin, as at 1000 Hz.
        values = 0
        for case in range(6):
            bottom = round(rng.uniform(0.4, 1.0), 3)  # the drum's bottom at the lowest point (m)
            x_limit = round(2 - rng.uniform(0.005, 0.1), 4)
            drum_floor = round(bottom + rng.uniform(0.005, 0.08), 4)
            vault = ("sscs: 1\nvault: ValueRules\nobjects:\n  - {type: room, name: Cell, length: 12 m, width: 8 m, height: 6 m}\n"
                     "  - {type: gantry, name: G, parent: Cell, location: [1, 1, 0], x_stroke: 6 m, y_stroke: 3 m}\n"
                     "  - {type: drum, name: D, parent: Cell, location: [1.9, 1.5, 0]}\n"
                     f"constraints:\n  - {{name: drum kept high, bound: [D.bbox.min.z, GE, {drum_floor} m]}}\n"
                     f"  - {{name: bridge travel, expr: \"G.x + 0 * G.z <= {x_limit}\"}}\n")
            (ref, ref_rc), (low, low_rc) = constraint_events(
                "values", vault, "  - {device: G, move_joints: {x: 0, y: 0, z: 1.049}}\n  - {device: G, grasp: D}\n"
                f"  - {{device: G, move_joints: {{z: 0}}}}\n  - {{device: G, move_joints: {{x: 2, z: {1.049 - bottom:.3f}}}}}\n"
                "  - {device: G, move_joints: {x: 0.5, z: 0}}\n")
            what = f"value rule case {case}:\n{vault}"
            if ref_rc != low_rc or [(e["constraint"], e["t"], e["margin"]) for e in ref] != [(e["constraint"], e["t"], e["margin"]) for e in low]:
                fail(f"{what}the rules' events at 1000 Hz {ref} and at a low rate {low} differ")
            if not any(e.get("between_samples") for e in low) and ref:
                fail(f"{what}no event between the samples at the low rate: {low}")
            values += len(ref)
        if values < 6:
            fail(f"the value rules should break in most cases: {values} events")
        # `inside` rules between samples: the drum carried 2 m must stay in a bay (a room) whose
        # far wall it passes by a few millimetres around the turning instant; judged by the bound
        # from its travel and exactly where that no longer clears, the events are those of 1000 Hz.
        insides = 0
        for case in range(4):
            over = round(rng.uniform(0.003, 0.05), 4)
            length = round(4.186 - 1.5 - over, 4)
            vault = ("sscs: 1\nvault: InsideRule\nobjects:\n  - {type: room, name: Cell, length: 12 m, width: 8 m, height: 6 m}\n"
                     "  - {type: gantry, name: G, parent: Cell, location: [1, 1, 0], x_stroke: 6 m, y_stroke: 3 m}\n"
                     "  - {type: drum, name: D, parent: Cell, location: [1.9, 1.5, 0]}\n"
                     f"  - {{type: room, name: Bay, parent: Cell, location: [1.5, 1.0, 0], length: {length} m, width: 2 m, height: 3 m}}\n"
                     # Every other case counts only some faces, not the one the drum passes (x+): it
                     # still must not stick out through it, judged between samples by each part's
                     # distance to the uncounted faces too.
                     "constraints:\n  - {name: drum stays in the bay, inside: {objects: D, container: Bay"
                     + (", faces: [x-, y-, y+, z+]" if case % 2 else "") + "}}\n")
            (ref, ref_rc), (low, low_rc) = constraint_events(
                "inside", vault, "  - {device: G, move_joints: {x: 0, y: 0, z: 1.049}}\n  - {device: G, grasp: D}\n"
                f"  - {{device: G, move_joints: {{z: {rng.uniform(0.3, 0.6):.3f}}}}}\n  - {{device: G, move_joints: {{x: 2}}}}\n"
                "  - {device: G, move_joints: {x: 0.5}}\n")
            what = f"inside rule case {case}:\n{vault}"
            if not ref or ref_rc != low_rc or [(e["t"], e["margin"]) for e in ref] != [(e["t"], e["margin"]) for e in low]:
                fail(f"{what}the rule's events at 1000 Hz {ref} and at a low rate {low} differ (or none)")
            if not -over - 0.005 <= ref[0]["margin"] < 0:
                fail(f"{what}the drum passes the wall by about {over} m at most, the event says {ref[0]['margin']}")
            insides += 1
    print(f"certified: {checked} random moves (physics and fast mode) of {len(devices)} devices past posts, the bound at 1-4 Hz within [-2 mm, "
          f"+{slack * 1000:g} mm] of 1000 Hz; {plates} past or through 5 mm plates; {rules} post rules ({agreed} broken) "
          f"judged at 1-4 Hz as at 1000 Hz; bound and expr rules broken between samples at the same step and margin ({values} events); {insides} inside rules likewise")


def rider_cases(rnd, count):
    """(label, vault, scenario) of `count` random AGV loads: a pallet with one to four drums of
    two sizes at random places (overhanging its edge or not), some with a small drum stacked on
    them, some lying on their side, driven along x and y and turned by random amounts, then set
    down on the deck."""
    cases = []
    for n in range(count):
        lines = ["sscs: 1", f"vault: Riders_{n}", "objects:",
                 "  - {type: room, name: Hall, length: 10, width: 8, height: 4}",
                 "  - {type: agv, name: Agv, parent: Hall, location: [2, 4, 0], deck_height: 0.2}",
                 "  - {type: pallet, name: P, parent: Hall, location: [1.4, 3.6, 0.2]}"]
        placed = []  # (x, y, radius) on the pallet, its own frame
        for k in range(rnd.choice([1, 2, 3, 4])):
            big = rnd.random() < 0.6
            r = 0.235 if big else 0.15
            for _ in range(200):
                x, y = rnd.uniform(r * 0.6, 1.2 - r * 0.6), rnd.uniform(r * 0.6, 0.8 - r * 0.6)
                if all(math.hypot(x - ox, y - oy) > r + orr + 0.01 for ox, oy, orr in placed):
                    placed.append((x, y, r))
                    break
            else:
                continue
            name = f"D{len(placed)}"
            if big:
                lines.append(f"  - {{type: drum_30gal, name: {name}, parent: P, location: [{x:.4f}, {y:.4f}, 0.144], fill_mass: 20 kg}}")
                if rnd.random() < 0.3:
                    lines.append(f"  - {{type: drum, name: {name}s, parent: {name}, location: [0, 0, 0.737], diameter: 0.3, height: 0.4, tare_mass: 5}}")
            elif rnd.random() < 0.25:  # lying on its side, along y: it rolls along x
                lines.append(f"  - {{type: drum, name: {name}, parent: P, location: [{x:.4f}, {y - 0.2:.4f}, {0.144 + r:.4f}], "
                             "orientation: [-90, 0, 0], diameter: 0.3, height: 0.4, tare_mass: 5}")
            else:
                lines.append(f"  - {{type: drum, name: {name}, parent: P, location: [{x:.4f}, {y:.4f}, 0.144], diameter: 0.3, height: 0.4, tare_mass: 5}}")
        steps = ["  - {device: Agv, grasp: P}"]
        q = {"x": 0.0, "y": 0.0, "yaw": 0.0}
        for _ in range(rnd.choice([2, 3])):
            joint = rnd.choice(["x", "x", "y", "yaw"])
            if joint == "x":
                q["x"] = round(min(5, max(-1, q["x"] + rnd.choice([-1, 1]) * rnd.uniform(0.5, 2))), 3)
            elif joint == "y":
                q["y"] = round(min(2, max(-2, q["y"] + rnd.choice([-1, 1]) * rnd.uniform(0.3, 1))), 3)
            else:
                q["yaw"] = round(q["yaw"] + rnd.choice([-1, 1]) * rnd.uniform(30, 90), 1)
            steps.append(f"  - {{device: Agv, move_joints: {{{joint}: {q[joint]}}}}}")
        steps.append("  - {device: Agv, release: {}}")
        scenario = ["sscs: 1", f"scenario: riders-{n}", "vault: vault.yaml", "sim: {timestep: 1 ms, limit: 60 s}", "steps:", *steps]
        cases.append((f"riders-{n}", "\n".join(lines) + "\n", "\n".join(scenario) + "\n"))
    return cases


def riders(sscs, root):
    """Riders welded to what carries them (PhysicsWorld::ride) against riders on their contacts
    (SSCS_WELD_RIDERS=0), over random configurations from a fixed seed: an AGV carrying a pallet
    with one to four drums of two sizes at random places (overhanging its edge or not), some with
    a small drum stacked on them, some lying on their side (a line of contacts: never welded, it
    rolls), driven along x and y and turned about its axis by random amounts, then setting the
    pallet down on its deck. Both runs end with the same status and the same events (collisions,
    shifted loads, displacements, landings, bodies not at rest), and every object within 5 mm of
    where the other run left it (also where ODE's solver gave up on a step on contacts: its
    physics_messages, said in the failure). And a weld that must break: a tall drum on a pallet a
    gantry accelerates tips and falls off, welded or not (tests/data/riders/tall-rider.yaml)."""
    cases = rider_cases(random.Random(36), 8)
    kinds = ("collision", "load_shifted", "displaced", "not_at_rest", "landed", "propped")
    with tempfile.TemporaryDirectory() as tmp:
        def one(job):
            (label, vault, scenario), weld = job
            d = os.path.join(tmp, label)
            os.makedirs(d, exist_ok=True)
            open(os.path.join(d, "vault.yaml"), "w").write(vault)
            open(os.path.join(d, "scenario.yaml"), "w").write(scenario)
            out = os.path.join(d, f"weld-{weld}")
            p = run(sscs, root, ["simulate", os.path.join(d, "scenario.yaml"), "--out", out, "--quiet", "--no-frames"],
                    {"SSCS_WELD_RIDERS": weld})
            if not os.path.exists(os.path.join(out, "summary.json")):
                fail(f"{label} (SSCS_WELD_RIDERS={weld}): no run\n{vault}\n{scenario}", p)
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            return json.load(open(os.path.join(out, "summary.json"))), events, last_positions(out)
        jobs = [(case, weld) for case in cases for weld in ("1", "0")]
        with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            results = list(pool.map(one, jobs))
    compared = skipped = 0
    for i, (label, vault, scenario) in enumerate(cases):
        (s1, e1, last1), (s0, e0, last0) = results[2 * i], results[2 * i + 1]
        where = f"{label}:\n{vault}\n{scenario}"
        if s0.get("physics_messages"):  # the reference's solver gave up on a step: said if they differ
            where += f"(on contacts ODE's solver gave up on {s0['physics_messages']['steps']} steps)\n"
            skipped += 1
        if s1["status"] != s0["status"]:
            fail(f"{where}welded riders end {s1['status']}, riders on contacts {s0['status']}: {e1} / {e0}")
        def kinds_of(events):
            return sorted((e["kind"], e.get("object", ""), e.get("on", "")) for e in events if e["kind"] in kinds)
        if kinds_of(e1) != kinds_of(e0):
            fail(f"{where}welded riders' events {kinds_of(e1)} differ from those on contacts {kinds_of(e0)}")
        for obj, at in last0.items():
            if obj not in last1 or math.dist(at, last1[obj]) > 0.005:
                fail(f"{where}{obj} ends at {last1.get(obj)} welded, at {at} on contacts (more than 5 mm apart)")
        compared += 1
    # A weld that must break: a tall drum on a pallet a gantry accelerates at 0.5 m/s^2 tips over
    # and falls to the floor, welded or not (a weld without its patch check would carry it upright).
    for weld in ("1", "0"):
        with tempfile.TemporaryDirectory() as tmp:
            p = run(sscs, root, ["simulate", "tests/data/riders/tall-rider.yaml", "--out", tmp + "/run", "--quiet", "--no-frames"],
                    {"SSCS_WELD_RIDERS": weld})
            events = [json.loads(line) for line in open(os.path.join(tmp, "run", "events.jsonl"))]
            last = last_positions(tmp + "/run")
        shifted = [e for e in events if e["kind"] == "load_shifted" and e["object"] == "T"]
        fell = [e for e in events if e["kind"] == "collision" and {e["a"], e["b"]} == {"floor", "T"}]
        if p.returncode != 1 or not shifted or not fell or last["T"][2] > 0.1:
            fail(f"tall-rider (SSCS_WELD_RIDERS={weld}): the tall drum must tip off the pallet onto the floor "
                 f"(load_shifted, a collision with the floor, lying at the end): {events} {last}", p)
        if math.dist(last["S"], [3.75, 2.2, 0.444]) > 0.005:
            fail(f"tall-rider (SSCS_WELD_RIDERS={weld}): the squat drum rides where it stood on the pallet: {last['S']}", p)
    print(f"riders: {compared} random AGV loads agree welded and on contacts ({skipped} of them with solver messages "
          "on contacts); a tall rider tips off an accelerating pallet either way")


def carrying(sscs, root):
    """Issue 36, item 2: `reach` with `carrying:` checks the load's shape where the tool holds it.
    A gantry sets a drum (three sizes) into level 1 of a random one-bay pallet rack, from above
    between the level-2 beams: the empty gripper always fits; with the drum, the verdict is the
    drum's overlap with the level-2 beams worked out by hand (its side reaching over a beam and its
    top above the beams' underside; touching passes), its depth the lesser of the two, and the
    margin minus the closest a free pose comes (vault-format.md): no nearer than that depth (every
    free pose separates the drum from the beam it is in), no farther than the free poses worked
    out by hand (out of the rack's side, depth/2 + radius; over the level-2 beams, level_height
    up), less up to the 1 mm a load may touch its target (the round drum also slips past the beams'
    ends along them, which the unit tests' simpler bay pins exactly); a drum standing on a carried
    pallet (its parent) counts as the pallet does."""
    rng = random.Random(362)
    drums = {"drum": (0.572, 0.851), "drum_30gal": (0.470, 0.737), "drum_85gal": (0.711, 0.902)}
    fails = passes = 0
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "vault.yaml")
        for case in range(30):
            kind = rng.choice(sorted(drums))
            diameter, height = drums[kind]
            depth = rng.uniform(0.5, 0.95)
            beam_w = rng.uniform(0.04, 0.12)
            beam_h = rng.uniform(0.08, 0.15)
            first = rng.uniform(0.15, 0.4)
            level = rng.uniform(0.75, 1.15)
            x, y = rng.uniform(1.5, 3.5), rng.uniform(1.0, 2.2)
            depth, beam_w, beam_h, first, level = (round(v, 4) for v in (depth, beam_w, beam_h, first, level))
            lateral = beam_w - (depth / 2 - diameter / 2)   # how far the drum's side reaches over a beam
            vertical = height - (level - beam_h)             # its top above the level-2 beams' underside
            if min(abs(lateral), abs(vertical)) < 1e-4:
                continue
            expect = min(lateral, vertical) if lateral > 1e-6 and vertical > 1e-6 else None
            free_move = min(depth / 2 + diameter / 2, level)
            rack = (f"{{type: pallet_rack, name: R, parent: Cell, location: [{x:.4f}, {y:.4f}, 0], bays: 1, positions: 1, "
                    f"bay_width: 0.9 m, depth: {depth:.4f} m, beam_width: {beam_w:.4f} m, beam_height: {beam_h:.4f} m, "
                    f"first_beam_height: {first:.4f} m, levels: 2, level_height: {level:.4f} m}}")
            reach = "{device: G, targets: R.slot_1_1_1, orientation: match, offset: {xyz: [0, 0, %.4f], rpy: [180, 0, 0]}" % height
            with open(path, "w") as f:
                f.write("sscs: 1\nvault: Carry\nobjects:\n  - {type: room, name: Cell, length: 10 m, width: 8 m, height: 6 m}\n"
                        "  - {type: gantry, name: G, parent: Cell, location: [0, 0, 0]}\n"
                        f"  - {{type: {kind}, name: Load, parent: Cell, location: [5.2, 3.0, 0]}}\n  - {rack}\n"
                        f"constraints:\n  - {{name: empty, reach: {reach}}}}}\n  - {{name: carried, reach: {reach}, carrying: Load}}}}\n")
            p = run(sscs, root, ["check", path, "--format", "json"])
            if p.returncode not in (0, 1):
                fail(f"case {case}: check exited {p.returncode}", p)
            results = {r["constraint"]: r for r in json.loads(p.stdout)["results"]}
            if results["empty"]["status"] != "pass":
                fail(f"case {case}: the empty gripper does not fit: {results['empty']['message']}", p)
            got = results["carried"]
            if "Load" not in got["subject"]:
                fail(f"case {case}: the carried load is not a subject: {got['subject']}", p)
            if expect is None:
                if got["status"] != "pass":
                    fail(f"case {case}: {kind} in a rack {depth:.3f} deep, levels {level:.3f} apart: expected to fit, got {got['message']}", p)
                passes += 1
            else:
                if got["status"] != "fail" or f"Load (carried) hits R by {expect:.6g} m" not in got["message"] or \
                        not expect - 1.1e-3 <= -got["margin"] <= free_move + 1e-4:
                    fail(f"case {case}: {kind} in a rack {depth:.3f} deep, levels {level:.3f} apart: expected the load to hit R "
                         f"by {expect:.6f} m, free {free_move:.6f} m away, got {got['status']} margin {got['margin']}: {got['message']}", p)
                fails += 1
        # A drum standing on a carried pallet (its parent) moves with it: the pallet, centred in
        # a bay 0.9 m deep, fits between the beams; the drum on it, 0.25 m from the pallet's
        # front edge, reaches 0.036 m over the level-2 front beam (and its top 0.197 m above it).
        with open(path, "w") as f:
            f.write("sscs: 1\nvault: Carry\nobjects:\n  - {type: room, name: Cell, length: 10 m, width: 8 m, height: 6 m}\n"
                    "  - {type: gantry, name: G, parent: Cell, location: [0, 0, 0]}\n"
                    "  - {type: pallet, name: P, parent: Cell, location: [4.6, 2.6, 0]}\n"
                    "  - {type: drum, name: D, parent: P, location: [0.3, 0.25, 0.144]}\n"
                    "  - {type: pallet_rack, name: R, parent: Cell, location: [2, 1.5, 0], bays: 1, positions: 1, bay_width: 1.4 m, "
                    "depth: 0.9 m, levels: 2, level_height: 0.9 m}\n"
                    "constraints:\n  - {name: carried, reach: {device: G, targets: {xyz: [2.176, 1.55, 0.15]}, orientation: match, "
                    "offset: {xyz: [0.6, 0.4, 1.2], rpy: [180, 0, 0]}, carrying: P}}\n")
        p = run(sscs, root, ["check", path, "--format", "json"])
        got = json.loads(p.stdout)["results"][0]
        # Backed 0.036 m out of the rack the drum is clear (the pallet, 0.8 m wide in a 0.9 m
        # frame, meets no beam on the way): the margin, less up to the 1 mm a load may touch.
        if got["status"] != "fail" or "D (carried) hits R by 0.036 m" not in got["message"] or not 0.0349 <= -got["margin"] <= 0.0361:
            fail(f"a drum on a carried pallet: expected it to hit the level-2 beam by 0.036 m, margin -0.036, got {got['message']}", p)
        # Beyond the gantry's x travel (its tool stops at x = 6.9 m, 0.2 m short), carrying a drum
        # to where another stands: the closest pose has the two drums in each other, so the
        # margin is the closest free pose's, worked out by hand: the carried drum sidesteps in y
        # until the drums' centres are a diameter apart (a new user found the 0.2 m of the
        # colliding pose reported).
        for case in range(5):
            x2 = round(rng.uniform(6.36, 6.5), 3)
            sidestep = math.sqrt(0.572 ** 2 - (6.9 - x2) ** 2)
            expect = math.sqrt(0.2 ** 2 + sidestep ** 2)
            with open(path, "w") as f:
                f.write("sscs: 1\nvault: Beyond\nobjects:\n  - {type: room, name: Hall, length: 12 m, width: 8 m, height: 5 m}\n"
                        "  - {type: gantry, name: G, parent: Hall, location: [1, 1, 0]}\n"
                        "  - {type: drum, name: Drum_1, parent: Hall, location: [3, 3, 0]}\n"
                        f"  - {{type: drum, name: Drum_2, parent: Hall, location: [{x2}, 3, 0]}}\n"
                        "constraints:\n  - {name: c, reach: {device: G, targets: {xyz: [7.1, 3, 0]}, orientation: match, "
                        "offset: {xyz: [0, 0, 0.851], rpy: [180, 0, 0]}, carrying: Drum_1}}\n")
            p = run(sscs, root, ["check", path, "--format", "json"])
            got = json.loads(p.stdout)["results"][0]
            if got["status"] != "fail" or abs(got["margin"] + expect) > 1e-4:
                fail(f"beyond the travel, Drum_2 at x {x2}: expected margin {-expect:.6f} (the closest free pose), got {got['margin']}: "
                     f"{got['message']}", p)
        # A forklift's pallet (a drum on it, through parent) clears a rack upright only turned by
        # about 8 degrees: with the tool's turn free the target is reached (a new user found it
        # failing by -0.097 where the match at that turn passed), with the turn matched it is not.
        with open(path, "w") as f:
            f.write("sscs: 1\nvault: Turned\nobjects:\n  - {type: room, name: Hall, length: 12 m, width: 8 m, height: 5 m}\n"
                    "  - {type: forklift, name: Truck, parent: Hall, location: [2, 1, 0], yaw: 90}\n"
                    "  - {type: pallet_rack, name: R, parent: Hall, location: [4, 3, 0], bays: 1, levels: 2, positions: 1, bay_width: 1.4, "
                    "depth: 0.7, first_beam_height: 0.3, level_height: 1.0, upright_extension: 0.3}\n"
                    "  - {type: pallet, name: Pallet, parent: Hall, location: [8, 1, 0]}\n"
                    "  - {type: drum, name: Drum_B, parent: Pallet, location: [0.9, 0.45, 0.144]}\n"
                    "constraints:\n"
                    "  - {name: match, reach: {device: Truck, targets: {xyz: [4.176, 2.95, 0.3]}, orientation: match, "
                    "offset: {xyz: [0.6, 0.4, 0.1], rpy: [0, 0, 90]}, carrying: Pallet}}\n"
                    "  - {name: free, reach: {device: Truck, targets: {xyz: [4.176, 2.95, 0.3]}, orientation: free, "
                    "offset: {xyz: [0.6, 0.4, 0.1], rpy: [0, 0, 90]}, carrying: Pallet}}\n")
        p = run(sscs, root, ["check", path, "--format", "json"])
        got = {r["constraint"]: r for r in json.loads(p.stdout)["results"]}
        if got["free"]["status"] != "pass" or got["match"]["status"] != "fail" or abs(got["match"]["margin"] + 0.036) > 1e-6:
            fail(f"the forklift's turned pallet: free should pass, match fail by 0.036: {got}", p)
    if fails < 8 or passes < 8:
        fail(f"the random racks should both fit and not fit the drum often: {passes} fit, {fails} did not")
    print(f"carrying: {passes} racks fit the carried drum, {fails} did not, depths as worked out by hand, margins between the depth and the free poses by hand; a pallet's rider counted; 5 closest free poses beyond the travel as by hand")


def pick_place_cases(rnd):
    """(label, vault, scenario) of random pick-and-place operations of the standard devices that
    carry loads from above: a gantry, a bridge crane and an arm take a drum from the floor and
    set it down elsewhere (on the floor or on a pallet), past a post standing at a random place
    and height, low enough to pass over or in the way (a collision: fast mode hands the device
    over to physics there). Some targets are out of reach (the plan fails, in both modes)."""
    cases = []
    down = "rpy: [180, 0, 0]"
    def steps(device, pick, place, carry_z, place_z, speed):
        px, py = pick
        tx, ty = place
        return [f"  - {{device: {device}, move_to: {{target: D.top, offset: {{xyz: [0, 0, 0.3], {down}}}}}}}",
                f"  - {{device: {device}, move_to: {{target: D.top, offset: {{{down}}}}}, path: linear, speed: 0.2 m/s}}",
                f"  - {{device: {device}, grasp: D}}",
                f"  - {{device: {device}, move_to: {{target: {{xyz: [{px:.4f}, {py:.4f}, {carry_z:.4f}], {down}}}}}, path: linear, speed: 0.3 m/s}}",
                f"  - {{device: {device}, move_to: {{target: {{xyz: [{tx:.4f}, {ty:.4f}, {carry_z:.4f}], {down}}}}}, path: linear, speed: {speed} m/s}}",
                f"  - {{device: {device}, move_to: {{target: {{xyz: [{tx:.4f}, {ty:.4f}, {place_z:.4f}], {down}}}}}, path: linear, speed: 0.2 m/s}}",
                f"  - {{device: {device}, release: {{}}}}",
                f"  - {{device: {device}, move_to: {{target: {{xyz: [{tx:.4f}, {ty:.4f}, {place_z + 0.3:.4f}], {down}}}}}, path: linear, speed: 0.3 m/s}}"]
    devices = [
        # kind, the device, the room, the drum, its height, where picks and places lie, carry height, speed
        ("gantry", "{type: gantry, name: R, parent: Hall, location: [1, 1, 0], x_stroke: 6 m, y_stroke: 3 m}",
         "length: 9 m, width: 6 m, height: 4 m", "{type: drum_30gal, name: D, parent: Hall, location: [PX, PY, 0]}", 0.737,
         lambda: (rnd.uniform(1.6, 6.4), rnd.uniform(1.5, 3.7)), (1.5, 2.2), 0.8),
        ("bridge_crane", "{type: bridge_crane, name: R, parent: Hall, location: [0.3, 0.3, 0], runway_length: 11 m, span: 7 m, "
         "rail_height: 4.2 m, lift: 3 m}", "length: 12 m, width: 8 m, height: 5 m",
         "{type: drum, name: D, parent: Hall, location: [PX, PY, 0]}", 0.851, lambda: (rnd.uniform(2, 10), rnd.uniform(1.5, 6)),
         (1.6, 2.6), 1.0),
        ("arm6", "{type: arm6, name: R, parent: Hall, location: [4, 3, 0]}", "length: 8 m, width: 6 m, height: 4 m",
         "{type: drum, name: D, parent: Hall, location: [PX, PY, 0], diameter: 0.3, height: 0.4, tare_mass: 5}", 0.4,
         lambda: (lambda a, r: (4 + r * math.cos(a), 3 + r * math.sin(a)))(rnd.uniform(-math.pi, math.pi), rnd.uniform(0.8, 1.6)),
         (0.7, 1.1), 0.5),
    ]
    for kind, device, room, drum, height, where, carry, speed in devices:
        for n in range(6):
            pick, place = where(), where()
            if math.dist(pick, place) < 0.9:
                place = (place[0] + 1.0, place[1])
            on_pallet = rnd.random() < 0.4
            lines = ["sscs: 1", f"vault: PickPlace_{kind}_{n}", "objects:", f"  - {{type: room, name: Hall, {room}}}", f"  - {device}",
                     "  - " + drum.replace("PX", f"{pick[0]:.4f}").replace("PY", f"{pick[1]:.4f}")]
            place_z = height
            if on_pallet:  # a pallet (1.2 x 0.8 m, 0.144 m high) centred under the target
                lines.append(f"  - {{type: pallet, name: P, parent: Hall, location: [{place[0] - 0.6:.4f}, {place[1] - 0.4:.4f}, 0]}}")
                place_z += 0.144
            carry_z = rnd.uniform(*carry) + (0.144 if on_pallet else 0)
            # A post part way along the carry, beside or in the path, lower or higher than the
            # drum's bottom there.
            f = rnd.uniform(0.3, 0.7)
            side = rnd.choice([0.0, rnd.uniform(-0.6, 0.6)])
            dx, dy = place[0] - pick[0], place[1] - pick[1]
            norm = math.hypot(dx, dy)
            cx, cy = pick[0] + f * dx - side * dy / norm, pick[1] + f * dy + side * dx / norm
            post_h = rnd.uniform(0.5, max(0.6, carry_z - height + 0.3))
            lines.append(f"  - {{type: wall, name: Post, parent: Hall, location: [{cx:.4f}, {cy:.4f}, 0], length: 0.1 m, "
                         f"thickness: 0.05 m, height: {post_h:.3f} m}}")
            scenario = ["sscs: 1", f"scenario: pick-place-{kind}-{n}", "vault: vault.yaml", "sim: {timestep: 1 ms, limit: 90 s}",
                        "steps:", *steps("R", pick, place, carry_z, place_z, speed)]
            cases.append((f"{kind}-{n}", "\n".join(lines) + "\n", "\n".join(scenario) + "\n"))
    return cases


# Events whose keys fast mode must reproduce: what happened to what (not when, or how deep).
OUTCOME_KINDS = ("collision", "landed", "displaced", "not_at_rest", "propped", "load_shifted", "grasp_missed", "unreachable",
                 "constraint", "keep_out", "joint_limit", "tracking_error", "time_limit")


def outcome_keys(events):
    """The set of (kind, what) of a run's outcome events: collision pairs either way round,
    landings with what they landed on, constraints by name."""
    keys = set()
    for e in events:
        k = e["kind"]
        if k not in OUTCOME_KINDS:
            continue
        if k == "collision":
            keys.add((k, *sorted((e["a"], e["b"]))))
        elif k == "landed":
            keys.add((k, e["object"], e["on"]))
        else:
            keys.add((k, e.get("object") or e.get("constraint") or e.get("zone") or e.get("device") or ""))
    return keys


def campaigns(sscs, root):
    """Issue 37: campaigns (tests/data/campaigns) whose figures are computed by hand from the
    gantry's profiles (a 2 m move at 1 m/s and 1 m/s^2: 3 s; to 2 m and back: 6 s): one gantry
    doing three jobs (ends 6, 12, 18 s; waits 0, 6, 12); six jobs on one gantry (36 s) and on two
    (18 s: concurrency halves the makespan); a claim both gantries' jobs hold (one at a time, in
    the queue's order); an unreachable target that fails its job alone (on_failure: continue: the
    device is out, its next job never starts, the other gantry's jobs go on); slots filled in
    the order each choice gives, every drum landing on its pad; the same seed, the same bytes."""
    import csv
    def campaign(name, tmp, extra=None):
        out = os.path.join(tmp, name)
        path = extra or f"tests/data/campaigns/{name}.yaml"
        p = run(sscs, root, ["simulate", path, "--out", out, "--no-frames", "--quiet"])
        if not os.path.exists(os.path.join(out, "summary.json")):
            fail(f"{name}: no run", p)
        summary = json.load(open(os.path.join(out, "summary.json")))
        jobs = list(csv.DictReader(open(os.path.join(out, "jobs.csv"))))
        events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
        return p, summary, jobs, events
    def campaign_in(name, mode, tmp):
        """tests/data/campaigns/NAME.yaml run in `mode`, its vault named absolutely: (the process,
        the copy run, the run's folder)."""
        text = open(os.path.join(root, f"tests/data/campaigns/{name}.yaml")).read()
        text = re.sub(r"mode: \w+", f"mode: {mode}", text, count=1)
        text = re.sub(r"^vault: (\S+)", lambda m: f"vault: {root}/tests/data/campaigns/{m.group(1)}", text, count=1, flags=re.M)
        path = os.path.join(tmp, f"{name}-{mode}.yaml")
        open(path, "w").write(text)
        out = os.path.join(tmp, f"{name}-{mode}-run")
        return run(sscs, root, ["simulate", path, "--out", out, "--no-frames", "--quiet", "--allow-outside-root"]), path, out
    def expect(name, what, got, want):
        if got != want:
            fail(f"{name}: {what} is {got}, by hand {want}")
    def times(jobs):
        return [(j["object"], j["device"], j["start"], j["end"], j["wait"], j["status"]) for j in jobs]
    with tempfile.TemporaryDirectory() as tmp:
        p, s, jobs, _ = campaign("one-device", tmp)
        expect("one-device", "exit status", p.returncode, 0)
        expect("one-device", "the jobs", times(jobs), [("Mark_1", "G1", "0", "6", "0", "done"), ("Mark_2", "G1", "6", "12", "6", "done"),
                                                        ("Mark_3", "G1", "12", "18", "12", "done")])
        c = s["campaign"]
        expect("one-device", "the campaign block", c, {
            "jobs": {"done": 3, "failed": 0, "not_started": 0}, "makespan": 18.0, "throughput": 600.0,
            "devices": {"G1": {"jobs": 3, "busy": 18.0, "utilization": 1.0}},
            "wait": {"mean": 6.0, "p95": 12.0, "max": 12.0}, "queue_max": 2, "slots": {"used": 0, "free_at_end": 0}})
        _, one, _, _ = campaign("six-on-one", tmp)
        _, two, jobs2, _ = campaign("six-on-two", tmp)
        expect("six-on-one", "makespan", one["campaign"]["makespan"], 36.0)
        expect("six-on-two", "makespan", two["campaign"]["makespan"], 18.0)
        expect("six-on-two", "the devices", two["campaign"]["devices"], {"G1": {"jobs": 3, "busy": 18.0, "utilization": 1.0},
                                                                        "G2": {"jobs": 3, "busy": 18.0, "utilization": 1.0}})
        expect("six-on-two", "who did what", [(j["object"], j["device"], j["start"]) for j in jobs2],
               [("Mark_1", "G1", "0"), ("Mark_2", "G2", "0"), ("Mark_3", "G1", "6"), ("Nark_1", "G2", "6"), ("Nark_2", "G1", "12"),
                ("Nark_3", "G2", "12")])
        # sscs compare puts two campaigns' figures side by side (one gantry against two).
        p = run(sscs, root, ["compare", os.path.join(tmp, "six-on-one"), os.path.join(tmp, "six-on-two"), "--format", "csv"])
        table = list(csv.DictReader(p.stdout.splitlines()))
        expect("compare (campaigns)", "its figures", [(r["makespan (s)"], r["throughput (jobs/h)"], r["jobs done"], r["G1 utilization"],
                                                       r["G2 utilization"], r["G2 jobs"], r["wait max (s)"]) for r in table],
               [("36", "600", "6", "1", "", "", "30"), ("18", "1200", "6", "1", "1", "3", "12")])
        p = run(sscs, root, ["compare", os.path.join(tmp, "six-on-one"), os.path.join(tmp, "six-on-two")])
        if "throughput (jobs/h)" not in p.stdout or "G2 utilization" not in p.stdout:
            fail(f"compare (campaigns): the text table has no campaign figures:\n{p.stdout}")
        p = run(sscs, root, ["compare", os.path.join(tmp, "six-on-one"), os.path.join(tmp, "six-on-two"), "--format", "json"])
        expect("compare (campaigns)", "its JSON", [r["campaign"]["makespan"] for r in json.loads(p.stdout)["runs"]], [36.0, 18.0])
        _, s, jobs, _ = campaign("claims", tmp)
        expect("claims", "starts", [(j["object"], j["start"], j["wait"]) for j in jobs],
               [("Mark_1", "0", "0"), ("Mark_2", "6", "6"), ("Mark_3", "12", "12"), ("Nark_1", "18", "18"), ("Nark_2", "24", "24"),
                ("Nark_3", "30", "30")])
        c = s["campaign"]
        expect("claims", "figures", (c["makespan"], c["wait"], c["queue_max"], c["devices"]["G1"]["utilization"]),
               (36.0, {"mean": 15.0, "p95": 30.0, "max": 30.0}, 5, 0.5))
        p, s, jobs, events = campaign("failure", tmp)
        expect("failure", "exit status and status", (p.returncode, s["status"]), (1, "failed"))
        expect("failure", "the jobs", [(j["object"], j["status"], j["end"]) for j in jobs],
               [("Mark_2", "failed", "2"), ("Mark_3", "not_started", ""), ("Nark_1", "done", "6"), ("Nark_2", "done", "12"),
                ("Nark_3", "done", "18")])
        unreachable = [e for e in events if e["kind"] == "unreachable"]
        expect("failure", "its unreachable event", [(e["t"], e.get("job")) for e in unreachable], [(2.0, "reach Mark_2")])
        if "stopped" in s:
            fail(f"failure: on_failure continue, yet the run stopped: {s['stopped']}")
        # on_failure: stop ends the campaign at the failure: G2's job under way then fails, the rest never start.
        stop = os.path.join(tmp, "failure-stop.yaml")
        open(stop, "w").write(open(os.path.join(root, "tests/data/campaigns/failure.yaml")).read()
                              .replace("on_failure: continue", "on_failure: stop").replace("vault: cell.yaml",
                                                                                           f"vault: {root}/tests/data/campaigns/cell.yaml"))
        p = run(sscs, root, ["simulate", stop, "--out", os.path.join(tmp, "stop"), "--no-frames", "--quiet", "--allow-outside-root"])
        jobs = list(csv.DictReader(open(os.path.join(tmp, "stop", "jobs.csv"))))
        expect("failure (stop)", "the jobs", [(j["object"], j["status"]) for j in jobs],
               [("Mark_2", "failed"), ("Mark_3", "not_started"), ("Nark_1", "failed"), ("Nark_2", "not_started"), ("Nark_3", "not_started")])
        # A failure the run finds, not the plan (tests/data/campaigns/grasp-missed.yaml): a block
        # hangs over D_2, G1's tool is held back on it and its grasp misses; with continue that job
        # fails alone, G1 is out (D_3 never starts), G2 lifts both its drums. Fast mode hands G1 to
        # the physics where it meets the block, and agrees.
        for mode in ("physics", "fast"):
            p, path, out = campaign_in("grasp-missed", mode, tmp)
            s = json.load(open(os.path.join(out, "summary.json")))
            jobs = list(csv.DictReader(open(os.path.join(out, "jobs.csv"))))
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            expect(f"grasp missed ({mode})", "the jobs", [(j["object"], j["device"], j["status"]) for j in jobs],
                   [("D_1", "G1", "done"), ("D_2", "G1", "failed"), ("D_3", "", "not_started"), ("E_1", "G2", "done"), ("E_2", "G2", "done")])
            expect(f"grasp missed ({mode})", "status", (p.returncode, s["status"], "stopped" in s), (1, "failed", False))
            # G1's move down onto D_2 ends on the block, 0.55 m short of its target: its step fails,
            # and the job with it (the grasp after it would miss).
            short = [e["job"] for e in events if e["kind"] == "step_end" and e.get("short_by")]
            expect(f"grasp missed ({mode})", "the step that ended short", short, ["lift_1 D_2"])
            if "short of its target" not in jobs[1]["message"] or "every device that may do it failed a job" not in jobs[2]["message"]:
                fail(f"grasp missed ({mode}): the messages say {jobs[1]['message']!r} and {jobs[2]['message']!r}")
            # G1 did nothing after it: the run ends with G2's last job, G1 stands still where it stopped.
            expect(f"grasp missed ({mode})", "the makespan and G1's busy time", (s["campaign"]["makespan"], s["campaign"]["devices"]["G1"]["busy"]),
                   (float(jobs[4]["end"]), round(float(jobs[0]["duration"]) + float(jobs[1]["duration"]), 9)))
            # final.yaml has what was set back on the floor on it, not 0.27 µm into it (the vault's
            # inside rules failed on it; in physics mode the drum's bounds, those of its bounding
            # sphere when it stands a hair off upright, had it 0.16 m under the floor, and it was
            # not lifted).
            sunk = [(o["name"], o["location"][2]) for o in yaml_loader()(os.path.join(out, "final.yaml"))["objects"] if o["type"] == "drum" and float(o["location"][2]) < 0]
            if sunk:
                fail(f"grasp missed ({mode}): final.yaml has drums under the floor: {sunk}")
            # The same with on_failure: stop: final.yaml has G1 where the run left it, held back on
            # the block (it had the planned grasp pose, inside the block).
            if mode == "physics":
                stop = os.path.join(tmp, "gm-stop.yaml")
                open(stop, "w").write(open(path).read().replace("on_failure: continue", "on_failure: stop"))
                run(sscs, root, ["simulate", stop, "--out", os.path.join(tmp, "gm-stop"), "--no-frames", "--quiet", "--allow-outside-root"])
                g1 = next(o for o in yaml_loader()(os.path.join(tmp, "gm-stop", "final.yaml"))["objects"] if o["name"] == "G1")
                last = list(csv.DictReader(open(os.path.join(tmp, "gm-stop", "trajectories", "G1.csv"))))[-1]
                got = [float(str(g1[j]).split()[0]) for j in ("x", "y", "z")]
                if max(abs(a - float(last[j])) for a, j in zip(got, ("x", "y", "z"))) > 1e-3:
                    fail(f"grasp missed (stop): final.yaml has G1 at {got}, the run left it at {[last[j] for j in ('x', 'y', 'z')]}")
            # A failure the run finds, not the plan, with on_failure: continue: the device is out
            # and the jobs the plan had given it go to other devices (campaign-format.md,
            # "Failure"; tests/data/campaigns/hood-redispatch.yaml): the visit due at 30 s, which
            # the plan gave the gantry, is G2's, 30 to 34 s by hand (it stayed not started).
            p, _, out = campaign_in("hood-redispatch", mode, tmp)
            rows = [(j["job"], j["object"], j["device"], j["start"], j["end"], j["status"]) for j in csv.DictReader(open(os.path.join(out, "jobs.csv")))]
            expect(f"re-dispatch after a failure in the run ({mode})", "the jobs", [(r[0], r[1], r[2], r[5]) for r in rows],
                   [("lift", "D_1", "Gantry", "done"), ("lift", "D_2", "Gantry", "failed"), ("visit", "Slab", "G2", "done")])
            expect(f"re-dispatch after a failure in the run ({mode})", "the visit's times", (float(rows[2][3]), float(rows[2][4])), (30.0, 34.0))
            short = [e["job"] for e in (json.loads(line) for line in open(os.path.join(out, "events.jsonl")))
                     if e["kind"] == "step_end" and e.get("short_by")]
            expect(f"re-dispatch after a failure in the run ({mode})", "the step that ended short", short, ["lift D_2"])
            # Slots free at the end: a 2 cm pad's own origin, 2 cm under its top frame, is no load
            # standing there (tests/data/campaigns/thin-pads-run.yaml: the drum on Pad_1, Pad_2 free;
            # a new user's review read 0 free).
            _, _, out = campaign_in("thin-pads-run", mode, tmp)
            expect(f"thin pads ({mode})", "the slots used and free at the end",
                   json.load(open(os.path.join(out, "summary.json")))["campaign"]["slots"], {"used": 1, "free_at_end": 1})
            # A device held back by what it pressed on sinks into it by the contact solver's
            # softness (11 µm, a new user's review): final.yaml has it backed out of that and keeps
            # its vault's no_overlap rule (tests/data/campaigns/hood-stop.yaml, the gantry pressed
            # against a slab).
            _, _, out = campaign_in("hood-stop", mode, tmp)
            p = run(sscs, root, ["check", os.path.join(out, "final.yaml"), "--allow-outside-root"])
            if p.returncode != 0:
                fail(f"a device pressed on a slab ({mode}): final.yaml does not check", p)
            late = [e for e in events if e["kind"].startswith("step_") and e.get("device") == "G1" and e["t"] > float(jobs[1]["end"])]
            if late:
                fail(f"grasp missed ({mode}): G1 is out, yet it went on: {late[:2]}")
        # final.yaml: the vault as the campaign left it. It checks; the drums stand on the pads
        # the jobs chose (pad tops (5, 1.5, 0.7), (4.5, 2.5, 0.6), (4, 3.5, 0.5)); the next
        # campaign starts from it and finds every drum where it says (each grasp holds).
        slots_final = None
        # Slots: pads' top frames; Pad_1 is the farthest and highest, Pad_3 the nearest and lowest
        # (tests/data/campaigns/store.yaml: pad tops (5, 1.5, 0.7), (4.5, 2.5, 0.6), (4, 3.5, 0.5);
        # drums at (1.5, 1.5), (1.5, 2.5), (1.5, 3.5)): nearest to D_1 is Pad_2 (3.219 m against
        # 3.240 and 3.569), then to D_2 Pad_3 (2.739 against 3.707).
        order = {"first": ["Pad_1", "Pad_2", "Pad_3"], "lowest": ["Pad_3", "Pad_2", "Pad_1"], "nearest": ["Pad_2", "Pad_3", "Pad_1"]}
        for choice, pads in order.items():
            path = os.path.join(tmp, f"slots-{choice}.yaml")
            open(path, "w").write(open(os.path.join(root, "tests/data/campaigns/slots.yaml")).read()
                                  .replace("choose: first", f"choose: {choice}").replace("vault: store.yaml",
                                                                                         f"vault: {root}/tests/data/campaigns/store.yaml"))
            out = os.path.join(tmp, f"slots-{choice}")
            p = run(sscs, root, ["simulate", path, "--out", out, "--no-frames", "--quiet", "--allow-outside-root"])
            s = json.load(open(os.path.join(out, "summary.json")))
            jobs = list(csv.DictReader(open(os.path.join(out, "jobs.csv"))))
            landed = {e["object"]: e["on"] for e in map(json.loads, open(os.path.join(out, "events.jsonl"))) if e["kind"] == "landed"}
            expect(f"slots ({choice})", "status", (p.returncode, s["status"]), (0, "ok"))
            expect(f"slots ({choice})", "the places", [j["place"] for j in jobs], [f"{pad}.top" for pad in pads])
            expect(f"slots ({choice})", "where the drums landed", landed, {f"D_{k + 1}": pad for k, pad in enumerate(pads)})
            expect(f"slots ({choice})", "slots", s["campaign"]["slots"], {"used": 3, "free_at_end": 0})
            if choice == "nearest":
                slots_final = out
        # slot.from as a list of frame globs: the same frames, in natural order whatever the list's.
        path = os.path.join(tmp, "slots-list.yaml")
        open(path, "w").write(open(os.path.join(root, "tests/data/campaigns/slots.yaml")).read()
                              .replace('from: "Pad_*.top"', 'from: "[Pad_3.top, Pad_?.top, Pad_1.top]"')
                              .replace("vault: store.yaml", f"vault: {root}/tests/data/campaigns/store.yaml"))
        p = run(sscs, root, ["simulate", path, "--out", os.path.join(tmp, "slots-list"), "--no-frames", "--quiet", "--allow-outside-root"])
        jobs = list(csv.DictReader(open(os.path.join(tmp, "slots-list", "jobs.csv")))) if p.returncode == 0 else []
        expect("slots (a list)", "the places", (p.returncode, [j["place"] for j in jobs]), (0, [f"{pad}.top" for pad in order["first"]]))
        listed = open(path).read().replace('from: "[Pad_3.top, Pad_?.top, Pad_1.top]"', "from: [Pad_3.top, Pad_1.top, Pad_2.top]")
        open(path, "w").write(listed)
        p = run(sscs, root, ["simulate", path, "--out", os.path.join(tmp, "slots-yaml-list"), "--no-frames", "--quiet", "--allow-outside-root"])
        jobs = list(csv.DictReader(open(os.path.join(tmp, "slots-yaml-list", "jobs.csv")))) if p.returncode == 0 else []
        expect("slots (a YAML list)", "the places", (p.returncode, [j["place"] for j in jobs]), (0, [f"{pad}.top" for pad in order["first"]]))
        final = os.path.join(slots_final, "final.yaml")
        p = run(sscs, root, ["check", final, "--allow-outside-root"])
        expect("final.yaml", "its check", (p.returncode, p.stdout.strip().splitlines()[-1:] if p.stdout else []), (0, ["1 passed, 0 failed, 0 warnings"]))
        placed = {o["name"]: o for o in yaml_loader()(final)["objects"]}
        tops = {"Pad_1": (5, 1.5, 0.7), "Pad_2": (4.5, 2.5, 0.6), "Pad_3": (4, 3.5, 0.5)}
        for drum, pad in zip(("D_1", "D_2", "D_3"), order["nearest"]):
            if math.dist(placed[drum]["location"], tops[pad]) > 0.005:
                fail(f"final.yaml: {drum} stands at {placed[drum]['location']}, its pad's top is {tops[pad]}")
        nxt = os.path.join(slots_final, "next.yaml")
        open(nxt, "w").write("sscs: 1\ncampaign: next\nvault: final.yaml\nsim: {mode: fast, limit: 300 s}\njobs:\n"
                             "  - name: lift\n    each: \"D_*\"\n    devices: [G1]\n    steps:\n"
                             "      - {move_to: {target: \"{load}.top\", offset: {xyz: [0, 0, 0.5], rpy: [180, 0, 0]}}}\n"
                             "      - {move_to: {target: \"{load}.top\", offset: {rpy: [180, 0, 0]}}, path: linear}\n"
                             "      - {grasp: \"{load}\"}\n"
                             "      - {release: {}}\n"
                             "      - {move_to: {target: \"{load}.top\", offset: {xyz: [0, 0, 0.5], rpy: [180, 0, 0]}}, path: linear}\n")
        p = run(sscs, root, ["simulate", nxt, "--out", os.path.join(tmp, "next"), "--no-frames", "--quiet", "--allow-outside-root"])
        jobs = list(csv.DictReader(open(os.path.join(tmp, "next", "jobs.csv")))) if os.path.exists(os.path.join(tmp, "next", "jobs.csv")) else []
        expect("final.yaml", "the next campaign from it", (p.returncode, [j["status"] for j in jobs], p.stderr[-300:]), (0, ["done"] * 3, p.stderr[-300:]))
        # Arriving loads (tests/data/campaigns/receive.yaml): due every 20 s at one spot, each waits
        # for the one before it to be lifted away (the end of the move after its grasp): In_4, due
        # at 60 s, arrives when In_3 is lifted. Physics and fast mode agree on the jobs and where
        # the drums rest (within 5 mm).
        runs = {}
        for mode in ("fast", "physics"):
            path = os.path.join(tmp, f"receive-{mode}.yaml")
            text = open(os.path.join(root, "tests/data/campaigns/receive.yaml")).read().replace(
                "vault: dock.yaml", f"vault: {root}/tests/data/campaigns/dock.yaml")
            open(path, "w").write(text if mode == "fast" else text.replace("mode: fast, ", ""))
            out = os.path.join(tmp, f"receive-{mode}")
            p = run(sscs, root, ["simulate", path, "--out", out, "--no-frames", "--quiet", "--allow-outside-root"])
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            jobs = list(csv.DictReader(open(os.path.join(out, "jobs.csv"))))
            runs[mode] = (p, events, jobs)
            expect(f"receive ({mode})", "status", (p.returncode, [j["status"] for j in jobs]), (0, ["done"] * 4))
            arrived = {e["object"]: e["t"] for e in events if e["kind"] == "arrived"}
            lifted = [e["t"] for e in events if e["kind"] == "step_end" and e.get("job") == "store In_3" and e["step"] == 3 + 2 * 8]
            expect(f"receive ({mode})", "arrivals", [arrived.get(f"In_{k}") for k in (1, 2, 3)], [0.0, 20.0, 40.0])
            if not lifted or abs(arrived.get("In_4", -1) - lifted[0]) > 1e-9 or lifted[0] <= 60:
                fail(f"receive ({mode}): In_4 should arrive when In_3 is lifted away ({lifted}), not at {arrived.get('In_4')}")
            expect(f"receive ({mode})", "places", [j["place"] for j in jobs], ["Pad_1.top", "Pad_2.top", "Pad_3.top", "Pad_4.top"])
            if any(e["kind"] == "collision" for e in events):
                fail(f"receive ({mode}): a collision (loads not arrived yet are not there): {[e for e in events if e['kind'] == 'collision']}")
        rest = {m: {e["object"]: e["position"] for e in runs[m][1] if e["kind"] == "at_rest"} for m in runs}
        for o, at in rest["physics"].items():
            if o not in rest["fast"] or math.dist(at, rest["fast"][o]) > 0.005:
                fail(f"receive: {o} rests at {at} in physics, at {rest['fast'].get(o)} in fast mode")
        expect("receive", "the jobs in fast and physics mode", [r[2] for r in [runs["fast"]]], [runs["physics"][2]])
        # A sweep of a campaign (tests/data/campaigns/receive-pads.yaml): each row's campaign
        # metrics are those of the campaign run alone with that value.
        sweep = os.path.join(tmp, "sweep")
        p = run(sscs, root, ["sweep", "tests/data/campaigns/receive-pads.yaml", "--out", sweep, "--jobs", "2", "--quiet"])
        rows = list(csv.DictReader(open(os.path.join(sweep, "results.csv")))) if os.path.exists(os.path.join(sweep, "results.csv")) else []
        expect("receive-pads (sweep)", "variants", (p.returncode, len(rows)), (0, 3))
        # The check judges the vault as written (its no_overlap rule), not the four loads that
        # arrive one at a time standing on InPad at once.
        expect("receive-pads (sweep)", "the checks", [(r["status"], r["passed"], r["failed"]) for r in rows], [("pass", "1", "0")] * 3)
        for r in rows:
            out = os.path.join(tmp, f"alone-{r['pad_x']}")
            run(sscs, root, ["simulate", "tests/data/campaigns/receive.yaml", "--set", f"pad_x={r['pad_x']} m", "--out", out, "--no-frames", "--quiet"])
            c = json.load(open(os.path.join(out, "summary.json")))["campaign"]
            want = {"makespan": c["makespan"], "throughput": c["throughput"], "busy": c["devices"]["G1"]["utilization"],
                    "waited": c["wait"]["max"], "done": c["jobs"]["done"]}
            got = {k: float(r[k]) for k in want}
            if any(abs(got[k] - want[k]) > 1e-9 * max(1, abs(want[k])) for k in want):
                fail(f"receive-pads (sweep): pad_x = {r['pad_x']} gives {got}, the campaign alone {want}")
        if len({r["makespan"] for r in rows}) != 3:
            fail(f"receive-pads (sweep): the pads' distance should change the makespan: {rows}")
        # A load that never arrives is never ready: its row has no ready time, and the makespan,
        # throughput and queue count only what arrived (receive.yaml with a 50 s limit: In_1..3
        # arrive at 0, 20, 40 s; In_2 waits from 20 to 27.562, In_3 from 40 to the end; the job
        # under way at 50 s fails there). By hand: makespan 50, 1 done, queue at most 1.
        path = os.path.join(tmp, "receive-50.yaml")
        open(path, "w").write(open(os.path.join(root, "tests/data/campaigns/receive.yaml")).read()
                              .replace("limit: 600 s", "limit: 50 s").replace("vault: dock.yaml", f"vault: {root}/tests/data/campaigns/dock.yaml"))
        p = run(sscs, root, ["simulate", path, "--out", os.path.join(tmp, "r50"), "--no-frames", "--quiet", "--allow-outside-root"])
        s = json.load(open(os.path.join(tmp, "r50", "summary.json")))
        jobs = list(csv.DictReader(open(os.path.join(tmp, "r50", "jobs.csv"))))
        expect("receive (limit 50 s)", "the jobs", [(j["object"], j["ready"], j["start"], j["end"], j["status"]) for j in jobs],
               [("In_1", "0", "0", "27.562", "done"), ("In_2", "20", "27.562", "50", "failed"), ("In_3", "40", "", "", "not_started"),
                ("In_4", "", "", "", "not_started")])
        c = s["campaign"]
        expect("receive (limit 50 s)", "its figures", (p.returncode, s["status"], c["makespan"], c["throughput"], c["queue_max"],
                                                       c["devices"]["G1"]["utilization"]), (1, "failed", 50.0, 72.0, 1, 1.0))
        # Every load due after the limit: the campaign runs to its limit and fails there (it
        # ended at 0 s, "ok").
        path = os.path.join(tmp, "receive-late.yaml")
        open(path, "w").write(open(os.path.join(root, "tests/data/campaigns/receive.yaml")).read()
                              .replace("arrive: {every: 20 s}", "arrive: {every: 20 s, first: 700 s}")
                              .replace("vault: dock.yaml", f"vault: {root}/tests/data/campaigns/dock.yaml"))
        p = run(sscs, root, ["simulate", path, "--out", os.path.join(tmp, "late"), "--no-frames", "--quiet", "--allow-outside-root"])
        s = json.load(open(os.path.join(tmp, "late", "summary.json")))
        expect("receive (all after the limit)", "its verdict", (p.returncode, s["status"], s.get("stopped", {}).get("by"), s["simulated_time"],
                                                                s["campaign"]["jobs"]["not_started"], s["campaign"]["queue_max"]),
               (1, "failed", "time_limit", 600.0, 4, 0))
        # The reference store at work (scenarios/drum-store/receiving.yaml, fast mode): all 40
        # drums stored by the crane and the 8 pallets by the forklift at once, without a
        # collision; every pallet on a place of its own of the goods rack; the closest approach
        # the forks lowered out of a set-down pallet's pockets, their bottoms 25 mm over the beam
        # (certified: at most 0.5 mm under it); its final.yaml keeps every rule of the store.
        out = os.path.join(tmp, "store-receiving")
        p = run(sscs, root, ["simulate", "scenarios/drum-store/receiving.yaml", "--out", out, "--no-frames", "--quiet"])
        s = json.load(open(os.path.join(out, "summary.json")))
        mc = s.get("min_clearance") or {}
        devices = {d: v["jobs"] for d, v in s["campaign"]["devices"].items()}
        expect("store receiving", "its verdict", (p.returncode, s["status"], s["events"].get("collision", 0), s["campaign"]["jobs"]["done"], devices, mc.get("certified")),
               (0, "ok", 0, 48, {"Crane": 40, "Truck": 8}, True))
        # (The forks in a pallet's pockets stand 25 mm over the beam both where they take it, the
        # in-stand, and where they set it down, the goods rack: a tie either bound may name.)
        if not 0.0245 <= mc.get("distance", 0) <= 0.025 or {mc.get("a"), mc.get("b")} not in ({"Truck.carriage", "GoodsRack"},
                                                                                             {"Truck.carriage", "InStand"}):
            fail(f"store receiving: the closest approach is {mc}; the forks lowered from a set-down pallet are 0.025 m over the beam")
        rows = list(csv.DictReader(open(os.path.join(out, "jobs.csv"))))
        # The next pallet comes when the last is clear of the stand, not at the end of its 10 cm
        # lift (it appeared under the lifted pallet: ODE gave up on the meshes, exit 3): two due
        # 5 s apart, the second arrives when the truck has backed out with the first, at
        # 3.0828 (x 2.376 m at 1 m/s2: 2 sqrt(2.376)) + 2.7 + 0.45 + 1.2 + 2.8 = 10.2328 s.
        text = open(os.path.join(root, "scenarios/drum-store/receiving.yaml")).read()
        text = re.sub(r'  - name: "In_\{n\}".*?(?=  # Pallets of supplies)', "", text, flags=re.S)
        text = re.sub(r'  - name: store_odd.*?(?=  # The forklift stores)', "", text, flags=re.S)
        text = text.replace("count: 8", "count: 2").replace("arrive: {every: 15 min, first: 2 min}", "arrive: {times: [0 s, 5 s]}")
        text = text.replace("vault: store.yaml", f"vault: {root}/scenarios/drum-store/store.yaml")
        path = os.path.join(tmp, "two-pallets.yaml")
        open(path, "w").write(text)
        p = run(sscs, root, ["simulate", path, "--out", os.path.join(tmp, "two-pallets"), "--no-frames", "--quiet", "--allow-outside-root"])
        arrived = {e["object"]: e["t"] for e in map(json.loads, open(os.path.join(tmp, "two-pallets", "events.jsonl"))) if e["kind"] == "arrived"} \
            if p.returncode == 0 else {}
        expect("two pallets 5 s apart", "the run and the arrivals", (p.returncode, round(arrived.get("Supplies_2", -1), 3)), (0, 10.233))
        places = [r["place"] for r in rows if r["device"] == "Truck"]
        if len(set(places)) != 8 or not all(p.startswith("GoodsRack.pallet_") for p in places):
            fail(f"store receiving: the pallets went to {places}, 8 places of the goods rack expected")
        # Each pallet rests centred on its place: GoodsRack (2 bays of 2.743 m between 76 mm
        # uprights, 0.7 m deep, beams at 0.15 m and every 1.524 m) turned 180 deg at (9, 2): a
        # pallet_{level}_{bay}_{position} frame is the corner of a 1.2 x 0.8 m pallet, 0.6 m
        # before the position's middle along the run and 0.4 m before the rack's mid-depth.
        rest = {e["object"]: e["position"] for e in map(json.loads, open(os.path.join(out, "events.jsonl"))) if e["kind"] == "at_rest"}
        for r in rows:
            if r["device"] != "Truck":
                continue
            level, bay, position = (int(v) for v in r["place"].rsplit("_", 3)[1:])
            along = 0.076 + (bay - 1) * (2.743 + 0.076) + (position - 0.5) * 2.743 / 2 - 0.6
            want = (9 - along, 2.0 - (0.35 - 0.4), 0.15 + (level - 1) * 1.524)
            if r["object"] not in rest or math.dist(rest[r["object"]], want) > 0.005:
                fail(f"store receiving: {r['object']} rests at {rest.get(r['object'])}, its place {r['place']} is at {want}")
        if any(float(r["start"]) - float(r["ready"]) > 1e-6 for r in rows):
            fail("store receiving: the crane and the forklift do not share anything: no job should wait")
        p = run(sscs, root, ["check", os.path.join(out, "final.yaml")])
        expect("store receiving", "its final.yaml's check", (p.returncode, p.stdout.strip().splitlines()[-1:]), (0, ["12 passed, 0 failed, 0 warnings"]))
        # The same seed, the same bytes (random choices).
        path = os.path.join(tmp, "slots-random.yaml")
        open(path, "w").write(open(os.path.join(tmp, "slots-first.yaml")).read().replace("choose: first", "choose: random")
                              .replace("limit: 300 s}", "limit: 300 s, seed: 11}"))
        for k in (1, 2):
            run(sscs, root, ["simulate", path, "--out", os.path.join(tmp, f"random-{k}"), "--no-frames", "--quiet", "--allow-outside-root"])
        for f in ("jobs.csv", "events.jsonl", "summary.json", "objects.csv"):
            if open(os.path.join(tmp, "random-1", f), "rb").read() != open(os.path.join(tmp, "random-2", f), "rb").read():
                fail(f"slots (random, seed 11): two runs wrote different {f}")
    print("campaigns: hand-computed makespans, waits, utilizations and queues; concurrency, claims, a failure alone "
          "(planned and in the run), slot choices, final.yaml, repeatable runs")


def fast(sscs, root):
    """Issue 36, item 4: `sim: {mode: fast}` agrees with physics mode. Every scenario of
    scenarios/ and tests/data (the standard devices: arms, gantry, crane, AGV, forklift, carts;
    loads, riders, falls, collisions, keep-out zones, rules), the `riders` test's random AGV
    loads, the `loads` test's every standard load on a gantry, and random pick-and-place runs of
    a gantry, a bridge crane and an arm past posts in and out of their way, each simulated in
    both modes: the same status, the same outcome events (collision pairs, landings, shifted,
    displaced and unsettled objects, failed grasps and plans, rules), cycle times within 1 %,
    and every object where the physics run left it within 5 mm, but those the physics itself
    threw about (one with a displaced, load_shifted or not_at_rest event: where a tipped drum
    ends is chaotic, compared by its events). summary.json says "mode": "fast", and which devices
    went on in physics and why."""
    cases = []  # (label, scenario path, extra args) or generated (label, vault, scenario)
    for folder in ("scenarios", "tests/data"):
        for dirpath, _, files in sorted(os.walk(os.path.join(root, folder))):
            if "/bad" in dirpath or "plugins" in dirpath:
                continue
            for f in sorted(files):
                path = os.path.join(dirpath, f)
                if f.endswith(".yaml") and re.search(r"^scenario:", open(path).read(), re.M):
                    cases.append((os.path.relpath(path, root), path, None))
    generated = ([(f"riders-{c[0]}", c[1], c[2]) for c in rider_cases(random.Random(3636), 8)] +
                 [(f"loads-{c[0]}", c[1], c[2]) for c in load_cases(random.Random(19))[::2]] +
                 pick_place_cases(random.Random(36)))
    with tempfile.TemporaryDirectory() as tmp:
        def one(job):
            (label, a, b), mode = job
            d = os.path.join(tmp, re.sub(r"[^A-Za-z0-9_.-]", "_", label), mode)  # one folder a run: they run at once
            os.makedirs(d, exist_ok=True)
            if b is None:  # a scenario of the repository, with sim.mode set and its vault named absolutely
                doc = yaml_loader()(a)
                doc.setdefault("sim", {})["mode"] = mode
                doc["vault"] = os.path.normpath(os.path.join(os.path.dirname(a), doc["vault"]))
                scenario = os.path.join(d, f"{mode}.yaml")
                with open(scenario, "w") as f:
                    f.write(json.dumps(doc))  # JSON is YAML
            else:
                open(os.path.join(d, "vault.yaml"), "w").write(a)
                scenario = os.path.join(d, f"{mode}.yaml")
                open(scenario, "w").write(b.replace("sim: {", f"sim: {{mode: {mode}, "))
            out = os.path.join(d, "run")
            p = run(sscs, root, ["simulate", scenario, "--out", out, "--quiet", "--no-frames", "--force", "--allow-outside-root"])
            if not os.path.exists(os.path.join(out, "summary.json")):
                fail(f"{label} ({mode}): no run", p)
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            return json.load(open(os.path.join(out, "summary.json"))), events, last_positions(out)
        jobs = [(case, mode) for case in cases + generated for mode in ("physics", "fast")]
        with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            results = list(pool.map(one, jobs))
    handed = statuses = 0
    seen = collections.Counter()
    for i, case in enumerate(cases + generated):
        (s0, e0, last0), (s1, e1, last1) = results[2 * i], results[2 * i + 1]
        where = f"{case[0]}" + ("" if case[2] is None else f":\n{case[1]}\n{case[2]}")
        if s1.get("mode") != "fast" or s0.get("mode") != "physics":
            fail(f"{where}: summary.json's mode is {s0.get('mode')} / {s1.get('mode')}")
        if s1["status"] != s0["status"]:
            fail(f"{where}\nfast mode ends {s1['status']}, physics {s0['status']}: {outcome_keys(e1)} / {outcome_keys(e0)}")
        if outcome_keys(e1) != outcome_keys(e0):
            fail(f"{where}\nfast mode's outcome {sorted(outcome_keys(e1))} differs from physics' {sorted(outcome_keys(e0))}")
        c0, c1 = s0["cycle_time"], s1["cycle_time"]
        if (c0 is None) != (c1 is None) or (c0 is not None and abs(c1 - c0) > 0.01 * c0):
            fail(f"{where}\ncycle time {c1} in fast mode, {c0} in physics")
        # The certified figure is the same in both modes (a lower bound within the tolerance of
        # the truth: a glide's sub-step once went unfound and fast mode said 0.3417 m where the
        # drum passed 0.429 m over a post). Where nothing collided: a contact's depth is the
        # physics' own, and where a device was stopped the modes stop it differently.
        m0, m1 = s0.get("min_clearance"), s1.get("min_clearance")
        collided = any(e["kind"] == "collision" for e in e0 + e1)
        if not collided and m0 and m1 and m0.get("certified") and m1.get("certified") and min(m0["distance"], m1["distance"]) > 0 \
                and abs(m0["distance"] - m1["distance"]) > 0.005:
            fail(f"{where}\nmin_clearance {m1} in fast mode, {m0} in physics (more than 5 mm apart)")
        thrown = {e.get("object") for e in e0 if e["kind"] in ("displaced", "load_shifted", "not_at_rest")}
        for obj, at in last0.items():
            if obj in thrown:
                continue
            if obj not in last1 or math.dist(at, last1[obj]) > 0.005:
                fail(f"{where}\n{obj} ends at {last1.get(obj)} in fast mode, at {at} in physics (more than 5 mm apart)")
        handed += bool(s1.get("handed_to_physics"))
        seen[s0["status"]] += 1
        statuses += 1
    # The log rate changes no certified figure: the store's crane run logged at 1 Hz in fast mode
    # has the min_clearance of its 20 Hz physics run (a stretch left coarse beside a set-down's
    # approach, excused later, once said 0.1005 m against 0.1368 m, both below the 0.1392 m of
    # 500 Hz).
    store = next(i for i, c in enumerate(cases) if c[0] == "scenarios/drum-store/store-drum.yaml")
    ref = results[2 * store][0]["min_clearance"]
    with tempfile.TemporaryDirectory() as tmp:
        doc = yaml_loader()(os.path.join(root, "scenarios/drum-store/store-drum.yaml"))
        doc["sim"]["mode"] = "fast"
        doc["record"] = {"trajectory": {"rate": "1 Hz"}}
        doc["vault"] = os.path.join(root, "scenarios/drum-store/store.yaml")
        open(os.path.join(tmp, "s.yaml"), "w").write(json.dumps(doc))
        run(sscs, root, ["simulate", os.path.join(tmp, "s.yaml"), "--out", os.path.join(tmp, "run"), "--quiet", "--no-frames", "--allow-outside-root"])
        low = json.load(open(os.path.join(tmp, "run", "summary.json")))["min_clearance"]
    # (Inbound is lowered between Drum_2_4_3 and Drum_2_6_3, each 0.139333 m from it: a tie,
    # which either names.)
    flanks = ({"Inbound", "Drum_2_4_3"}, {"Inbound", "Drum_2_6_3"})
    if abs(low["distance"] - ref["distance"]) > 0.001 or {low["a"], low["b"]} not in flanks or {ref["a"], ref["b"]} not in flanks:
        fail(f"the store's crane run: min_clearance {low} at 1 Hz in fast mode, {ref} at 20 Hz in physics")
    # And the cases of tests/data/fast logged at 1 Hz have the figure of 50 Hz (a drum woken
    # mid-interval by a forklift's grasp read -0.175 m at 1 Hz for a 43 mm gap).
    for name in ("forklift-lift", "crane-over-post"):
        i = next(i for i, c in enumerate(cases) if c[0] == f"tests/data/fast/{name}.yaml")
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(root, "tests/data/fast", name + ".yaml")
            doc = yaml_loader()(path)
            doc["record"] = {"trajectory": {"rate": "50 Hz"}}
            doc["vault"] = os.path.normpath(os.path.join(os.path.dirname(path), doc["vault"]))
            open(os.path.join(tmp, "s.yaml"), "w").write(json.dumps(doc))
            run(sscs, root, ["simulate", os.path.join(tmp, "s.yaml"), "--out", os.path.join(tmp, "run"), "--quiet", "--no-frames", "--allow-outside-root"])
            ref = json.load(open(os.path.join(tmp, "run", "summary.json")))["min_clearance"]
        for mode, result in (("physics", results[2 * i]), ("fast", results[2 * i + 1])):
            low = result[0]["min_clearance"]
            if not low or not low.get("certified") or abs(low["distance"] - ref["distance"]) > 0.002 or {low["a"], low["b"]} != {ref["a"], ref["b"]}:
                fail(f"tests/data/fast/{name}.yaml: min_clearance {low} at 1 Hz in {mode} mode, {ref} at 50 Hz in physics")
    # One pass through a plate is one collision at 1 Hz in both modes (ODE finds no contact while
    # the 5 mm plate is wholly inside the drum: it was three). Its depth is measured at the
    # samples: at 44 s the drum is 0.097 m past the plate's face; min_clearance, certified
    # between samples, has the pass's 0.151 m.
    i = next(i for i, c in enumerate(cases) if c[0] == "tests/data/fast/crane-through-plate.yaml")
    for mode, result in (("physics", results[2 * i]), ("fast", results[2 * i + 1])):
        episodes = [c for c in result[0].get("collisions") or [] if {c["a"], c["b"]} == {"D", "Plate"}]
        low = result[0].get("min_clearance") or {}
        if len(episodes) != 1 or not 0.09 < episodes[0]["depth"] < 0.154 or episodes[0]["deepest_at"] > episodes[0]["end"] \
                or episodes[0]["end"] - episodes[0]["start"] < 0.9 or not -0.154 < low.get("distance", 0) < -0.148:
            fail(f"tests/data/fast/crane-through-plate.yaml in {mode} mode: one collision of D and Plate from about 43.84 s "
                 f"to 44.80 s and min_clearance -0.151 m expected, found {episodes}, {low}")
    if seen["ok"] < 10 or seen["violations"] < 10 or seen["failed"] < 2 or handed < 5:
        fail(f"the cases should cover runs that pass, break and fail, and hand devices over: {dict(seen)}, {handed} handed over")
    print(f"fast: {statuses} runs agree with physics mode ({dict(seen)}; {handed} handed a device over to physics)")


def run_truth(sscs, root):
    """What a run says is what happened: tests/e2e/run_truth.py over tests/data/run-truth."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import run_truth as truth
    truth.run_truth(sscs, root, run, fail)


def live_serve(sscs, root):
    """sscs serve over HTTP: tests/e2e/live_serve.py."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import live_serve as live
    live.serve(sscs, root, fail)


MODES = {"serve": live_serve, "campaigns": campaigns, "fast": fast, "carrying": carrying, "riders": riders, "certified": certified, "tunnel": tunnel, "worst_margin": worst_margin, "reach_turning": reach_turning, "arrival": arrival, "run_truth": run_truth, "catalogue": catalogue, "zones": zones, "drum_store": drum_store, "simulate": simulate, "agreement": agreement, "loads": loads, "render": render, "plugins": plugins, "ci": ci, "ci_recipes": ci_recipes,
         "schemas": schemas, "sweep": sweep, "sweep_reuse": sweep_reuse, "cli": cli, "tutorials": tutorials}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sscs", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("mode", choices=["golden", "bad", *MODES])
    ap.add_argument("file", nargs="?")
    a = ap.parse_args()
    if a.mode == "golden":
        golden(a.sscs, a.root, a.file)
    elif a.mode == "bad":
        bad(a.sscs, a.root, a.file)
    else:
        MODES[a.mode](a.sscs, a.root)


if __name__ == "__main__":
    main()
