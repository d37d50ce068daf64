#!/usr/bin/env python3
"""How fast the live design loop answers (issue 38), for the reference store and a generated
10,000-object vault, a baseline binary and this one side by side (best and median of N edits):

  sscs serve   a save -> the update pushed (Server-Sent Events) -> the new page fetched (gzip)
  sscs lsp     a keystroke (didChange, unsaved) -> its diagnostics published

Targets (cli.md): the page shows a save's result within 300 ms for the reference store and 2 s
for a 10,000-object vault. The page's own part (parse, rebuild, model load in WebGL) is measured
in a browser by web.serve (about 240 ms in headless chromium with software WebGL, for the store).

  tools/bench/live_speed.py [--sscs build/src/sscs] [--baseline OLD_SSCS] [--runs 5]
"""
import argparse
import gzip
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def serve_times(sscs, vault_text, edits, workdir):
    """Save -> update pushed, and -> page fetched, for each edit of `vault_text` (seconds)."""
    path = os.path.join(workdir, "v.yaml")
    with open(path, "w") as f:
        f.write(vault_text)
    p = subprocess.Popen([sscs, "serve", "v.yaml", "--port", "0", "--quiet"], cwd=workdir, stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL, text=True)
    try:
        m = re.search(r"http://127\.0\.0\.1:(\d+)/", p.stdout.readline())
        base = f"http://127.0.0.1:{m.group(1)}"
        urllib.request.urlopen(base + "/", timeout=600).read()  # the first check done
        updates = []

        def listen():
            with urllib.request.urlopen(base + "/events", timeout=600) as r:
                for line in r:
                    if line.startswith(b"event: update"):
                        updates.append(time.monotonic())
        threading.Thread(target=listen, daemon=True).start()
        time.sleep(0.5)
        pushed, shown = [], []
        for text in edits:
            n = len(updates)
            t0 = time.monotonic()
            with open(path, "w") as f:
                f.write(text)
            while len(updates) == n and time.monotonic() - t0 < 600:
                time.sleep(0.002)
            pushed.append(updates[-1] - t0)
            req = urllib.request.Request(base + "/", headers={"Accept-Encoding": "gzip"})
            with urllib.request.urlopen(req, timeout=600) as r:
                body = r.read()
                if r.headers.get("Content-Encoding") == "gzip":
                    body = gzip.decompress(body)
            shown.append(time.monotonic() - t0)
            time.sleep(0.3)
        return pushed, shown
    finally:
        p.terminate()
        p.wait(timeout=10)


def lsp_times(sscs, vault_text, edits, workdir):
    """A didChange -> its publishDiagnostics, for each edit (seconds)."""
    path = os.path.join(workdir, "v.yaml")
    with open(path, "w") as f:
        f.write(vault_text)
    uri = "file://" + path
    p = subprocess.Popen([sscs, "lsp"], cwd=workdir, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)

    def send(m):
        b = json.dumps(m).encode()
        p.stdin.write(b"Content-Length: %d\r\n\r\n" % len(b) + b)
        p.stdin.flush()

    def published():
        while True:
            header = b""
            while not header.endswith(b"\r\n\r\n"):
                header += p.stdout.read(1)
            n = int(re.search(rb"Content-Length: (\d+)", header).group(1))
            m = json.loads(p.stdout.read(n))
            if m.get("method") == "textDocument/publishDiagnostics" and m["params"]["uri"] == uri:
                return m

    try:
        send({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}})
        send({"jsonrpc": "2.0", "method": "textDocument/didOpen",
              "params": {"textDocument": {"uri": uri, "languageId": "yaml", "version": 1, "text": vault_text}}})
        published()
        times = []
        for k, text in enumerate(edits):
            t0 = time.monotonic()
            send({"jsonrpc": "2.0", "method": "textDocument/didChange",
                  "params": {"textDocument": {"uri": uri, "version": k + 2}, "contentChanges": [{"text": text}]}})
            while published()["params"].get("version", k + 2) != k + 2:
                pass
            times.append(time.monotonic() - t0)
        send({"jsonrpc": "2.0", "id": 2, "method": "shutdown"})
        send({"jsonrpc": "2.0", "method": "exit"})
        return times
    finally:
        p.kill()
        p.wait(timeout=10)


def vaults(runs, tmp):
    store = open(os.path.join(ROOT, "scenarios/drum-store/store.yaml")).read()
    store_edits = [store.replace("aisle: {value: 3.2 m", f"aisle: {{value: {3.2 + 0.01 * (k + 1):.2f} m") for k in range(runs)]
    big_path = os.path.join(tmp, "big.yaml")
    subprocess.run([sys.executable, os.path.join(HERE, "gen_vault.py"), big_path, "--objects", "10000", "--constraints", "10000"],
                   check=True)
    big = open(big_path).read()
    first = re.search(r"name: R0, location: \[0\.000, 0\.000, 0\], height: ([0-9.]+)", big)
    big_edits = [big.replace(first.group(0), first.group(0).replace(first.group(1), f"{3 + 0.01 * (k + 1):.3f}"), 1)
                 for k in range(runs)]
    return [("reference store (143 drums)", store, store_edits, 0.3), ("10,000 objects, 10,000 constraints", big, big_edits, 2.0)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sscs", default=os.path.join(ROOT, "build/src/sscs"))
    ap.add_argument("--baseline")
    ap.add_argument("--runs", type=int, default=5)
    a = ap.parse_args()
    binaries = [("this", a.sscs)] + ([("baseline", a.baseline)] if a.baseline else [])
    with tempfile.TemporaryDirectory() as tmp:
        rows = []
        for name, text, edits, target in vaults(a.runs, tmp):
            for label, sscs in binaries:
                work = os.path.join(tmp, label)
                shutil.rmtree(work, ignore_errors=True)
                os.makedirs(work)
                pushed, shown = serve_times(sscs, text, edits, work)
                typed = lsp_times(sscs, text, edits, work)
                rows.append((name, label, pushed, shown, typed, target))
        print(f"{'vault':36} {'binary':9} {'serve: pushed':>15} {'page fetched':>14} {'lsp: keystroke':>15}   target (page)")
        for name, label, pushed, shown, typed, target in rows:
            f = lambda xs: f"{min(xs) * 1000:6.0f}/{statistics.median(xs) * 1000:<6.0f}"
            ok = "ok" if statistics.median(shown) <= target else "NOT MET"
            print(f"{name:36} {label:9} {f(pushed):>15} {f(shown):>14} {f(typed):>15}   <= {target * 1000:.0f} ms {ok}")
        print("(ms, best/median of", a.runs, "edits; the page's own rebuild in a browser comes on top: web.serve prints it)")


if __name__ == "__main__":
    main()
