"""`sscs serve`, as a browser sees it over HTTP (e2e.serve): the page of a copy of the reference
store; a save pushes an update (Server-Sent Events) and the page then shows the new verdict; a
syntax error shows its file:line:col over the last good view; the fix recovers; nothing but the
page and its updates is served; a scenario is refused; Ctrl-C stops it."""
import html
import os
import re
import shutil
import signal
import subprocess
import tempfile
import threading
import time
import urllib.error
import urllib.request


def get(url, timeout=30):
    try:
        with urllib.request.urlopen(url, timeout=timeout) as r:
            return r.status, r.read().decode("utf-8", "replace")
    except urllib.error.HTTPError as e:
        return e.code, e.read().decode("utf-8", "replace")


def served_at(p, what, fail):
    """The URL a started `sscs serve` prints on its first line."""
    m = re.search(r"http://127\.0\.0\.1:(\d+)/", p.stdout.readline())
    if not m:
        fail(f"{what}: no URL")
    return f"http://127.0.0.1:{m.group(1)}"


def failed_count(page):
    found = re.findall(r'"failed":\s*(\d+)', page)
    return int(found[0]) if found else None


def serve(sscs, root, fail):
    with tempfile.TemporaryDirectory() as tmp:
        vault = os.path.join(tmp, "store.yaml")
        shutil.copy(os.path.join(root, "scenarios/drum-store/store.yaml"), vault)
        text = open(vault).read()
        p = subprocess.Popen([sscs, "serve", "store.yaml", "--port", "0"], cwd=tmp, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        try:
            first = p.stdout.readline()
            m = re.search(r"http://127\.0\.0\.1:(\d+)/", first)
            if not m:
                fail(f"sscs serve: no URL on its first line: {first!r}")
            base = f"http://127.0.0.1:{m.group(1)}"
            status, page = get(base + "/")
            if status != 200 or failed_count(page) != 0 or "racks keep 0.5 m from the walls" not in page or \
                    "connect-src 'self'" not in page or "EventSource" not in page:
                fail(f"sscs serve: the first page (status {status}, failed {failed_count(page)})")
            # Updates, as the page's EventSource gets them.
            updates = []
            def listen():
                with urllib.request.urlopen(base + "/events", timeout=120) as r:
                    for line in r:
                        if line.startswith(b"event: update"):
                            updates.append(time.monotonic())
            threading.Thread(target=listen, daemon=True).start()
            time.sleep(0.5)

            def save(new_text, what):
                n = len(updates)
                t0 = time.monotonic()
                with open(vault, "w") as f:
                    f.write(new_text)
                while len(updates) == n and time.monotonic() - t0 < 20:
                    time.sleep(0.01)
                if len(updates) == n:
                    fail(f"sscs serve: no update within 20 s of saving {what}")
                status, page = get(base + "/")
                if status != 200:
                    fail(f"sscs serve: status {status} after saving {what}")
                return page, updates[-1] - t0

            # The aisle 1 m narrower: the forklift cannot turn in it.
            page, took = save(text.replace("aisle: {value: 3.2 m", "aisle: {value: 2.2 m"), "a narrower aisle")
            if failed_count(page) != 1 or "aisles let the forklift turn" not in page or 'id="sscs-serve-errors"' in page:
                fail(f"sscs serve: after narrowing the aisle, failed {failed_count(page)}")
            print(f"serve: a save of the store to its update: {took * 1000:.0f} ms")
            # A typo: the error at its line and column, over the last good view (greyed).
            page, _ = save(text.replace("aisle: {value: 3.2 m", "aisle: {valu: 3.2 m"), "a typo")
            page = html.unescape(page)  # (the banner's text is escaped in the page)
            if 'id="sscs-serve-errors"' not in page or "store.yaml:9:11: error: unknown key 'valu'" not in page or \
                    "did you mean 'value'" not in page or failed_count(page) != 1 or "grayscale" not in page:
                fail("sscs serve: a typo's error at store.yaml:9:11 over the last good view")
            # Fixed: the page recovers.
            page, _ = save(text, "the fix")
            if 'id="sscs-serve-errors"' in page or failed_count(page) != 0:
                fail("sscs serve: the page after the fix")
            # Only the page and its updates: no file, inside the project or out.
            for path in ("/store.yaml", "/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/library/types/drum.yaml"):
                status, body = get(base + path)
                if status != 404 or "root:" in body or "type:" in body:
                    fail(f"sscs serve: GET {path} answered {status}")
            # Ctrl-C stops it.
            p.send_signal(signal.SIGINT)
            try:
                code = p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                fail("sscs serve: still running 10 s after Ctrl-C")
            if code != 0:
                fail(f"sscs serve: exit {code} after Ctrl-C")
        finally:
            if p.poll() is None:
                p.kill()
        serve_scenario(sscs, root, tmp, fail)
        serve_superseded(sscs, tmp, fail)
    print("ok serve")


def serve_scenario(sscs, root, tmp, fail):
    """A scenario served: its run's page (its vault, its motions animated, its events); a save of
    a slower move runs it again with the longer cycle; a typo in it shows where it is; its runs go
    to a folder of the server's own, removed when it stops."""
    cell = os.path.join(tmp, "cell")
    shutil.copytree(os.path.join(root, "scenarios/drum-transfer"), cell)
    path = os.path.join(cell, "arm-loads-drum.yaml")
    text = open(path).read()
    scratch_dirs = lambda: [d for d in os.listdir(tempfile.gettempdir()) if d.startswith("sscs-serve-")]
    before = set(scratch_dirs())
    p = subprocess.Popen([sscs, "serve", "arm-loads-drum.yaml", "--port", "0"], cwd=cell, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    try:
        base = served_at(p, "sscs serve of a scenario", fail)

        def cycle(page):
            found = re.search(r'"cycle_time":([0-9.]+)', page)
            return float(found.group(1)) if found else None

        def wait_for(check, what):
            t0 = time.monotonic()
            while time.monotonic() - t0 < 60:
                status, page = get(base + "/")
                if status == 200 and check(page):
                    return page
                time.sleep(0.2)
            fail(f"sscs serve of a scenario: {what} (the page: {page[:300]!r})")

        page = wait_for(lambda pg: cycle(pg) is not None, "no run page")
        first = cycle(page)
        time.sleep(0.5)  # (the watcher arms on the files the first run read)
        if '"kind":"run"' not in page or '"kind":"grasp"' not in page or not 9 < first < 11:
            fail(f"sscs serve of a scenario: the first run's page (cycle {first})")
        with open(path, "w") as f:  # the linear moves at half speed: a longer cycle
            f.write(text.replace("path: linear, speed: 0.2 m/s", "path: linear, speed: 0.1 m/s"))
        page = wait_for(lambda pg: (cycle(pg) or 0) > first + 1, "no longer cycle after a slower move was saved")
        with open(path, "w") as f:
            f.write(text.replace("move_joints: home", "move_joint: home"))
        page = html.unescape(wait_for(lambda pg: 'id="sscs-serve-errors"' in pg, "no error banner after a typo"))
        if not re.search(r"arm-loads-drum\.yaml:\d+:\d+: error: unknown step kind", page):
            fail("sscs serve of a scenario: the typo's place")
        ours = set(scratch_dirs()) - before  # the folder of this server's runs
        if len(ours) != 1:
            fail(f"sscs serve of a scenario: its runs' folder: {sorted(ours)}")
        p.send_signal(signal.SIGINT)
        if p.wait(timeout=10) != 0:
            fail(f"sscs serve of a scenario: exit {p.returncode} after Ctrl-C")
        if ours & set(scratch_dirs()):
            fail(f"sscs serve of a scenario: its runs' folder left behind: {sorted(ours)}")
        print(f"serve: a scenario's run: {first:.3f} s cycle, {cycle(page) or 0:.3f} after the slower move")
    finally:
        if p.poll() is None:
            p.kill()


def reach_vault(targets):
    """An arm reaching over a screen for `targets` points behind it: each is reached only in
    collision, after the search's every approach and turn (a fifth of a second each)."""
    points = ", ".join(f"{{xyz: [4.25, {3.4 + 1.2 * i / max(1, targets - 1):.4f}, {0.6 + 0.04 * (i % 10):.2f}]}}" for i in range(targets))
    return ("sscs: 1\nvault: Screen\nobjects:\n"
            "  - {type: room, name: Room1, length: 10 m, width: 8 m, height: 5 m}\n"
            "  - {type: arm6, name: Arm, parent: Room1, location: [3, 4, 0]}\n"
            "  - {type: wall, name: Screen, parent: Room1, location: [4.0, 2, 0], orientation: [0, 0, 90], length: 4 m, thickness: 0.1 m, height: 3 m}\n"
            f"constraints:\n  - {{name: over the screen, reach: {{device: Arm, targets: [{points}]}}}}\n")


def bounds_vault():
    """The same cell with two failing bounds and no reach: checked in no time."""
    return reach_vault(0).replace("  - {name: over the screen, reach: {device: Arm, targets: []}}\n",
                                  "  - {name: low, bound: [Screen.height, LT, 1 m]}\n  - {name: short, bound: [Screen.length, LT, 1 m]}\n")


def serve_superseded(sscs, tmp, fail):
    """A save made while a long check runs stops that check: the save is checked at once (the last
    save wins without waiting for a check of text that is already gone)."""
    folder = os.path.join(tmp, "screen")
    os.makedirs(folder)
    path = os.path.join(folder, "screen.yaml")
    with open(path, "w") as f:
        f.write(reach_vault(1))
    p = subprocess.Popen([sscs, "serve", "screen.yaml", "--port", "0"], cwd=folder, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    try:
        base = served_at(p, "sscs serve (superseded)", fail)
        status, page = get(base + "/")
        if status != 200 or failed_count(page) != 1:
            fail(f"sscs serve (superseded): the first page (status {status}, failed {failed_count(page)})")
        time.sleep(0.5)  # (the watcher arms on the files the first check read)
        with open(path, "w") as f:  # 400 targets: a check of a minute and more
            f.write(reach_vault(400))
        time.sleep(1.5)  # (that check under way)
        t0 = time.monotonic()
        with open(path, "w") as f:  # checked in no time: what is measured is how soon the long check stops
            f.write(bounds_vault())
        while time.monotonic() - t0 < 60:
            status, page = get(base + "/")
            if failed_count(page) == 2:
                break
            time.sleep(0.1)
        took = time.monotonic() - t0
        if failed_count(page) != 2 or took > 10:
            fail(f"sscs serve (superseded): the last save shown after {took:.1f} s (failed {failed_count(page)}): it waited for the long check")
        print(f"serve: a save made during a long check, shown after {took * 1000:.0f} ms")
        p.send_signal(signal.SIGINT)
        if p.wait(timeout=10) != 0:
            fail(f"sscs serve (superseded): exit {p.returncode} after Ctrl-C")
    finally:
        if p.poll() is None:
            p.kill()
