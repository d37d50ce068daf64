#!/usr/bin/env python3
"""What a run says is what happened (tests/data/run-truth): seven operations a designer writes,
from a bug report where the run's verdict and numbers were not the truth.

  crane-onto-occupied   a crane lowers a drum 0.8 m into the drum standing on the position and
                        lets go: min_clearance is the penetration (-0.572 m), a collision episode
                        of the two drums, and the released drum is no set-down (`displaced`, up).
  agv-pallet-arm-pick   an arm picks a drum off the pallet an AGV holds: min_clearance is the
                        drum beside it (0.13 m), not the gripper or the pallet; ODE stays quiet.
  forklift-through-drum a forklift drives its body 1.4 m through a drum: the collision's depth is
                        the episode's deepest (0.801 m), with `end` and `deepest_at`.
  agv-set-down-on-deck  an AGV releases the pallet on its own deck: ok, landed on the AGV, at rest.
  crane-beyond-travel   a target beyond the crane's travel: failed, and the steps it never ran
                        have no times.
  released-on-top       a drum released 40 mm into the one below is pushed up onto it: `displaced`
                        with its `rise`.
  feather-pallet        a 0.1 g pallet under four drums on an AGV, the drums on their contacts
                        (SSCS_WELD_RIDERS=0): ODE's solver gives up on steps ("LCP internal error"); summary.json says on how many, from when, and what
                        it means for the numbers. The clean runs above have no physics_messages.

Every expectation is checked and every one that fails is listed (not only the first), each
saying what a designer expects and what the run gave; RUN_TRUTH_VERBOSE=1 lists those that hold.

  run_truth.py --sscs BIN --root REPO     (or run_truth(sscs, root, run, fail) from run_case.py)
"""
import json
import math
import os
import tempfile
from concurrent.futures import ThreadPoolExecutor

DATA = "tests/data/run-truth"
SCENARIOS = ["crane-onto-occupied", "agv-pallet-arm-pick", "forklift-through-drum", "agv-set-down-on-deck",
             "crane-beyond-travel", "released-on-top", "feather-pallet"]


def collisions_between(events, a, b):
    """The collision events of a run between a and b (either way round)."""
    return [e for e in events if e["kind"] == "collision" and {e["a"], e["b"]} == {a, b}]


def episodes_between(summary, a, b):
    """summary.json's collision episodes between a and b (either way round)."""
    return [c for c in summary.get("collisions") or [] if {c["a"], c["b"]} == {a, b}]


def last_positions(run_dir):
    """{object: [x, y, z]} of each object's last row in a run's objects.csv."""
    last = {}
    for row in open(os.path.join(run_dir, "objects.csv")).read().splitlines()[1:]:
        cols = row.split(",")
        last[cols[1]] = [float(x) for x in cols[2:5]]
    return last


def near(got, want, tol):
    return got is not None and abs(got - want) <= tol


def run_truth(sscs, root, run, fail):
    problems = []
    verbose = bool(os.environ.get("RUN_TRUTH_VERBOSE"))  # also list the expectations that hold

    def expect(ok, name, msg):
        if not ok:
            problems.append(f"{name}: {msg}")
        elif verbose:
            print(f"pass {name}: {msg.split('; got')[0]}")

    with tempfile.TemporaryDirectory() as tmp:
        def one(name):
            out = os.path.join(tmp, name)
            # The drums on the feather pallet stay on their contacts (not welded to it, as after a
            # weld breaks): with welds the solver has no contacts there to give up on.
            env = {"SSCS_WELD_RIDERS": "0"} if name == "feather-pallet" else None
            p = run(sscs, root, ["simulate", f"{DATA}/{name}.yaml", "--out", out, "--quiet", "--no-frames"], env)
            return name, p, out

        with ThreadPoolExecutor(max_workers=min(len(SCENARIOS), os.cpu_count() or 2)) as pool:
            results = list(pool.map(one, SCENARIOS))
        runs = {}
        for name, p, out in results:
            if not os.path.exists(os.path.join(out, "summary.json")):
                fail(f"{name}: the run must write summary.json (exit {p.returncode})", p)
            summary = json.load(open(os.path.join(out, "summary.json")))
            events = [json.loads(line) for line in open(os.path.join(out, "events.jsonl"))]
            runs[name] = (p, summary, events, out)

        # 1. The crane lowers Carried 0.8 m into Standing (one axis) and lets go.
        name = "crane-onto-occupied"
        p, summary, events, out = runs[name]
        expect(p.returncode == 1 and summary["status"] == "violations", name,
               f"a drum driven into another is a violation (exit 1, status violations); got exit {p.returncode}, "
               f"status {summary['status']}")
        mc = summary["min_clearance"]
        expect(mc is not None and {mc["a"], mc["b"]} == {"Carried", "Standing"} and near(mc["distance"], -0.572, 0.03), name,
               "min_clearance is the two drums' penetration, about -0.572 m (the shortest push that separates two "
               f"coaxial drums of radius 0.286 overlapping 0.8 m is sideways, 2 x 0.286), Carried/Standing; got {mc}")
        hits = collisions_between(events, "Carried", "Standing")
        deepest = max((e["depth"] for e in hits), default=None)
        expect(hits and deepest >= 0.55, name,
               f"a collision episode of Carried and Standing at least 0.57 m deep; got {hits}")
        listed = episodes_between(summary, "Carried", "Standing")
        expect(listed and max(c["depth"] for c in listed) >= 0.55, name,
               f"summary.json's collisions list the Carried/Standing episode, at least 0.57 m deep; got {summary.get('collisions')}")
        # Pushed out, it leaves Standing (airborne from about 47.75 s) and lands back on its top
        # 0.2 s later: that is a landing and then support, not the collision going on (contacts
        # more than 0.1 s apart are two episodes).
        landed = [e for e in events if e["kind"] == "landed" and e["object"] == "Carried" and e["on"] == "Standing"]
        if landed and hits:
            expect(all(e["end"] < landed[0]["t"] for e in hits), name,
                   f"the collision episode ends before Carried lands back on Standing at {landed[0]['t']} s (resting on "
                   f"it is no collision); got {hits}")
        shown = [e for e in events if e["kind"] == "displaced" and e["object"] == "Carried"]
        last = last_positions(out).get("Carried")
        # Set down with its bottom at 0.051 m; wherever it ends more than 20 mm from there (up
        # included: pushed out onto the other drum, 0.8 m up) it is no set-down.
        moved = last is not None and (math.hypot(last[0] - 3.5, last[1] - 2.0) > 0.02 or abs(last[2] - 0.051) > 0.02)
        expect(not moved or len(shown) == 1, name,
               f"Carried ends at {last}, not where it was set down ([3.5, 2.0, 0.051]): a displaced event; got {shown}")
        if moved and last[2] > 0.071:
            expect(len(shown) == 1 and near(shown[0].get("rise"), last[2] - 0.051, 0.01), name,
                   f"Carried ends {last[2] - 0.051:.3f} m above where it was set down: displaced with that rise; got {shown}")

        # 2. The AGV holds the pallet; the arm picks D1 straight up beside D2.
        name = "agv-pallet-arm-pick"
        p, summary, events, out = runs[name]
        expect(p.returncode == 0 and summary["status"] == "ok", name,
               f"a clean pick runs ok (exit 0); got exit {p.returncode}, status {summary['status']}, events {summary['events']}")
        mc = summary["min_clearance"]
        expect(mc is not None and {mc["a"], mc["b"]} == {"D1", "D2"} and near(mc["distance"], 0.13, 0.005), name,
               "min_clearance is D1 lifted beside D2, 0.6 - 2 x 0.235 = 0.13 m (not the gripper on the drum it "
               f"grasps, nor the pallet the drum leaves); got {mc}")
        expect("LCP internal error" not in p.stderr, name,
               f"ODE prints no 'LCP internal error'; got stderr {p.stderr[-2000:]!r}")

        # 2b. The same with a pallet of 0.1 g: the solver gives up on steps, and the run says so.
        name = "feather-pallet"
        p, summary, events, out = runs[name]
        pm = summary.get("physics_messages")
        expect(pm is not None and pm["steps"] >= 1 and "LCP" in pm["first"] and 0 < pm["first_at"] < summary["simulated_time"]
               and "forces" in pm["meaning"], name,
               f"summary.json's physics_messages counts the steps ODE's solver gave up on, the first and when, and what "
               f"that means; got {pm}")
        expect(pm is not None and f"at {pm['first_at']:.3f} s" in p.stderr, name,
               f"stderr says when the first solver message came; got {p.stderr[-1000:]!r}")
        for clean in ["agv-pallet-arm-pick", "agv-set-down-on-deck", "crane-beyond-travel"]:
            expect("physics_messages" not in runs[clean][1], clean,
                   f"a run ODE had nothing to say about has no physics_messages; got {runs[clean][1].get('physics_messages')}")

        # 3. The forklift drives its body 1.4 m through the drum.
        name = "forklift-through-drum"
        p, summary, events, out = runs[name]
        expect(p.returncode == 1 and summary["status"] == "violations", name,
               f"driving through a drum is a violation (exit 1, status violations); got exit {p.returncode}, "
               f"status {summary['status']}")
        hits = collisions_between(events, "Truck.body", "D")
        expect(len(hits) == 1, name, f"one collision episode of Truck.body and D (they touch throughout); got {hits}")
        if hits:
            e = hits[0]
            expect("end" in e and "deepest_at" in e, name, f"the collision event has `end` and `deepest_at`; got {e}")
            expect(e["depth"] > 0.1, name,
                   f"the episode's depth is its deepest penetration, not the first contact's millimetre; got {e['depth']}")
            # The drum ends wholly inside the body, whose bottom is 0.05 m up: the shortest push
            # that separates them is 0.851 - 0.05 = 0.801 m down (0.861 sideways, 1.4 m along x).
            expect(near(e["depth"], 0.801, 0.03), name,
                   "the deepest penetration is 0.801 m (the drum inside the body, whose bottom is 0.05 m up: no "
                   f"push shorter separates them, and none is needed longer); got {e['depth']}")
            # The body has gone 0.801 m into the drum at 5.20 s and stays; it stops at 6.30 s and
            # the run ends at 6.80 s with the drum still inside.
            expect("deepest_at" in e and 5.15 <= e["deepest_at"] <= e.get("end", 0), name,
                   f"deepest_at is once the body is 0.8 m in (from 5.2 s) and within the episode; got {e}")
            expect("end" in e and near(e["end"], summary["simulated_time"], 0.01), name,
                   f"the episode ends with the run ({summary['simulated_time']} s): the drum is still inside; got {e}")
            listed = episodes_between(summary, "Truck.body", "D")
            same = len(listed) == 1 and listed[0].get("start") == e["t"] and \
                all(listed[0].get(k) == e.get(k) for k in ("end", "depth", "deepest_at"))
            expect(same, name,
                   f"summary.json's collisions list the same episode as events.jsonl {e}; got {summary.get('collisions')}")
        mc = summary["min_clearance"]
        expect(mc is not None and mc["distance"] < 0, name, f"min_clearance is negative (a penetration); got {mc}")
        expect(mc is not None and {mc["a"], mc["b"]} == {"Truck.body", "D"} and near(mc["distance"], -0.801, 0.03), name,
               f"min_clearance is the body's penetration of the drum, -0.801 m, Truck.body/D; got {mc}")

        # 4. The AGV lets go of the pallet on its own deck.
        name = "agv-set-down-on-deck"
        p, summary, events, out = runs[name]
        expect(p.returncode == 0 and summary["status"] == "ok", name,
               f"a pallet released on the AGV's deck is set down: ok (exit 0); got exit {p.returncode}, "
               f"status {summary['status']}, events {summary['events']}")
        propped = [e for e in events if e["kind"] == "propped"]
        expect(not propped, name, f"an AGV cannot lower its deck: nothing is propped; got {propped}")
        landed = [(e["object"], e["on"]) for e in events if e["kind"] == "landed"]
        expect(len(landed) == 1 and landed[0][0] == "P" and landed[0][1].split(".")[0] == "Agv", name,
               f"the pallet lands on the AGV; got {landed}")
        rest = {e["object"]: e["position"] for e in events if e["kind"] == "at_rest"}
        expect("P" in rest and math.dist(rest["P"], [3.4, 2.6, 0.35]) <= 0.005, name,
               f"the pallet rests on the deck where it was released, [3.4, 2.6, 0.35]; got at_rest {rest}")

        # 5. The crane is sent beyond its travel, with two steps after it.
        name = "crane-beyond-travel"
        p, summary, events, out = runs[name]
        expect(p.returncode == 1 and summary["status"] == "failed", name,
               f"an unreachable target fails the run (exit 1, status failed); got exit {p.returncode}, "
               f"status {summary['status']}")
        bad = [e for e in events if e["kind"] == "unreachable"]
        expect(len(bad) == 1 and bad[0]["step"] == 1 and bad[0]["device"] == "Crane", name,
               f"one unreachable event, at step 1, of the Crane; got {bad}")
        steps = summary.get("steps") or []
        expect(len(steps) == 4, name, f"summary.json lists all four steps; got {steps}")
        if len(steps) == 4:
            expect(steps[0]["start"] is not None and steps[0]["end"] is not None, name,
                   f"the step before the failure ran: a start and an end; got {steps[0]}")
            expect(steps[1]["start"] is not None and steps[1]["end"] is None, name,
                   f"the failed step began and never ended: a start and end null; got {steps[1]}")
            expect(all(s["start"] is None and s["end"] is None for s in steps[2:]), name,
                   f"the steps after the failure never ran: start and end null; got {steps[2:]}")
        ended = [e for e in events if e["kind"] == "step_end" and e["step"] >= 1]
        expect(not ended, name, f"no step_end for the failed step or after it; got {ended}")
        expect(summary.get("cycle_time") is None and (summary.get("stopped") or {}).get("by") == "unreachable", name,
               f"no cycle time, stopped by unreachable; got cycle_time {summary.get('cycle_time')}, stopped {summary.get('stopped')}")

        # 6. The small drum is released 40 mm into the big one and pushed up onto it.
        name = "released-on-top"
        p, summary, events, out = runs[name]
        last = last_positions(out).get("Small")
        expect(last is not None and near(last[2], 0.851, 0.005), name,
               f"the released drum ends on top of the big one (bottom at 0.851 m, 40 mm above its release); got {last}")
        rest = [e for e in events if e["kind"] in ("at_rest", "not_at_rest") and e["object"] == "Small"]
        expect(rest, name, f"the released drum is judged where it settles (at_rest or not_at_rest); got {rest}")
        shown = [e for e in events if e["kind"] == "displaced" and e["object"] == "Small"]
        expect(len(shown) == 1 and near(shown[0].get("rise"), 0.04, 0.01), name,
               f"released at 0.811 m and resting at 0.851 m: displaced with rise 0.04 m; got {shown}")
        expect(p.returncode == 1 and summary["status"] == "violations", name,
               f"a drum lowered into another is a violation (exit 1, status violations); got exit {p.returncode}, "
               f"status {summary['status']}")

    if problems:
        fail(f"{len(problems)} expectation(s) not met:\n" + "\n".join(problems))
    print("ok run_truth")


if __name__ == "__main__":
    import argparse
    import sys
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from run_case import run, fail
    ap = argparse.ArgumentParser()
    ap.add_argument("--sscs", required=True)
    ap.add_argument("--root", required=True)
    a = ap.parse_args()
    run_truth(a.sscs, a.root, run, fail)
