#!/usr/bin/env python3
"""The include layering of src/ (../shared/STYLE.md item 9): stages depend one way,
core <- load <- plugin <- inputs <- compile <- model <- geometry <- kinematics <- {check, simulate, render}
<- report <- pipeline <- {sweep, lsp} <- cli, and the stages after compile read the compiled model, never load/ or
compile's internals (compile/values.h, compile/compile.h). With a second argument (tests/unit), also that the unit
tests mirror src/: one folder per stage.

Fails on any include that goes against that order, on any stage-level cycle, and on any arrow
into load/ or compile internals from geometry, model, kinematics, check, simulate or render that
is not in KNOWN below. KNOWN lists the arrows that remain from before this test (issue 20 removes
them); an entry that no longer occurs fails too, so the list only shrinks."""
import os
import re
import sys

ORDER = ["core", "load", "plugin", "inputs", "compile", "model", "geometry", "kinematics", "check", "simulate", "render",
         "report", "pipeline", "sweep", "lsp", "cli"]
# Stages at the same level may not include each other either (simulate never includes render).
LEVEL = {"core": 0, "load": 1, "plugin": 2, "inputs": 2.5, "compile": 3, "model": 4, "geometry": 5, "kinematics": 6, "check": 7,
         "simulate": 8, "render": 8, "report": 9, "pipeline": 10, "sweep": 11, "lsp": 11, "cli": 12}
# pipeline assembles the stages for the commands, the HTML reports among them (report/html.h
# lays out the page, pipeline/html_report.h gathers what it shows): it may include report.
# Stages that read the compiled model only.
MODEL_READERS = {"model", "geometry", "kinematics", "check", "simulate", "render"}
INTERNALS = re.compile(r"^(load/.*|compile/values\.h|compile/compile\.h|plugin/.*)$")
# file -> included header: arrows that remain (issue 20 removed the last of them; keep it empty).
KNOWN = set()


def includes(src):
    """(file, header) for every `#include "stage/x.h"` under src/."""
    out = []
    for stage in sorted(os.listdir(src)):
        folder = os.path.join(src, stage)
        if not os.path.isdir(folder):
            continue
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".h", ".cpp")):
                continue
            for line in open(os.path.join(folder, name), encoding="utf-8"):
                m = re.match(r'\s*#\s*include\s+"([a-z_]+/[a-z_]+\.h)"', line)
                if m:
                    out.append((f"{stage}/{name}", m.group(1)))
    return out


# What touching the file system looks like in C++ source: std::filesystem queries and iteration,
# streams and stdio on files, and sscs's own calls that read, resolve or load files.
FILE_SYSTEM = re.compile(
    r"\b(?:fs|std::filesystem)::(?:exists|is_directory|is_regular_file|is_symlink|directory_iterator|"
    r"recursive_directory_iterator|weakly_canonical|canonical|file_size|status|symlink_status|last_write_time|"
    r"absolute|current_path|temp_directory_path)\b"
    r"|\b(?:std::)?[io]?fstream\b|\bfopen\s*\(|\bdlopen\s*\("
    r"|\b(?:read_source|read_file_bytes|load_type|load_vault|load_urdf|load_srdf|not_a_readable_reference|not_a_file|"
    r"outside_roots|resolve_mesh_path|join_path|project_root_of|standard_library_dir|load_folder|gather_vault|"
    r"gather_library)\s*\(")
FILE_SYSTEM_HEADERS = ("core/files.h", "core/data_dirs.h", "load/load.h", "<filesystem>", "<fstream>", "<dlfcn.h>")


def file_system_uses(src, stage):
    """Every line of src/<stage>/ that touches the file system, or includes a header for it."""
    out = []
    folder = os.path.join(src, stage)
    for name in sorted(os.listdir(folder)):
        if not name.endswith((".h", ".cpp")):
            continue
        for number, line in enumerate(open(os.path.join(folder, name), encoding="utf-8"), 1):
            code = line.split("//")[0]
            m = FILE_SYSTEM.search(code)
            inc = re.match(r'\s*#\s*include\s+["<]([^">]+)[">]', code)
            if m:
                out.append(f"src/{stage}/{name}:{number}: {m.group(0).strip()}: {stage} never touches the file system "
                           "(gather what it needs in src/inputs/)")
            elif inc and (inc.group(1) in FILE_SYSTEM_HEADERS or f"<{inc.group(1)}>" in FILE_SYSTEM_HEADERS):
                out.append(f"src/{stage}/{name}:{number}: includes {inc.group(1)}: {stage} never touches the file system")
    return out


def main():
    src = sys.argv[1]
    problems = []
    found = includes(src)
    stages = {f.split("/")[0] for f, _ in found}
    for s in stages:
        if s not in LEVEL:
            problems.append(f"src/{s}/ is no stage of the layering: add it to ORDER and LEVEL in {__file__}")
    edges = set()
    seen_known = set()
    for f, h in found:
        a, b = f.split("/")[0], h.split("/")[0]
        if a == b or a not in LEVEL or b not in LEVEL:
            continue
        edges.add((a, b))
        if LEVEL[b] >= LEVEL[a]:
            problems.append(f"src/{f} includes {h}: {a} may not include {b} (a later or parallel stage)")
        if (f, h) in KNOWN:
            seen_known.add((f, h))
        elif (a in MODEL_READERS or f == "compile/workcell.h") and INTERNALS.match(h):
            problems.append(f"src/{f} includes {h}: {a} reads the compiled model, never load/ or compile's internals")
    for f, h in sorted(KNOWN - seen_known):
        problems.append(f"src/{f} no longer includes {h}: remove it from KNOWN in {__file__}")
    # Stage-level cycles (the order check implies none; kept explicit for a clear message).
    graph = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
    def cycle_from(node, path):
        for nxt in sorted(graph.get(node, ())):
            if nxt in path:
                return path[path.index(nxt):] + [nxt]
            c = cycle_from(nxt, path + [nxt])
            if c:
                return c
        return None
    for s in sorted(graph):
        c = cycle_from(s, [s])
        if c:
            problems.append("include cycle between stages: " + " -> ".join(c))
            break
    # compile/ takes the inputs gathered (src/inputs/) and never touches the file system: no call
    # that reads, lists or looks at a file, no loader, no plugin loading (issue 38 item 3).
    problems += file_system_uses(src, "compile")
    # Unit tests mirror src/: tests/unit/<stage>/ for each stage they test, no test file loose.
    if len(sys.argv) > 2:
        unit = sys.argv[2]
        for name in sorted(os.listdir(unit)):
            path = os.path.join(unit, name)
            if os.path.isdir(path) and name not in stages:
                problems.append(f"tests/unit/{name}/ mirrors no folder of src/")
            if name.endswith("_test.cpp"):
                problems.append(f"tests/unit/{name} belongs in tests/unit/<stage>/, beside the tests of the stage it tests")
    for p in problems:
        print("FAIL:", p)
    if problems:
        return 1
    print(f"ok layering: {len(found)} includes across {len(stages)} stages, {len(KNOWN)} known arrows into load/compile internals left")
    return 0


if __name__ == "__main__":
    sys.exit(main())
