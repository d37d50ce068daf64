#!/usr/bin/env python3
"""Writes the seed corpus of one fuzz target, and the dictionary of the file formats.

seeds.py TARGET OUT_DIR [--dict FILE]
Seeds come from the project's own files (library/, scenarios/, tests/data/), chosen by what the
target reads; the dictionary holds every key and enum value of schemas/*.json, the units, the
operators and functions of expressions, and URDF's element and attribute names.
"""
import base64
import glob
import json
import os
import re
import struct
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MESH_EXTENSIONS = ["stl", "obj", "ply", "glb", "gltf", "off", "dae"]  # as fuzz_mesh.cpp picks them


def project_files(pattern):
    out = []
    for top in ("library", "scenarios", "tests/data"):
        out += glob.glob(os.path.join(ROOT, top, "**", pattern), recursive=True)
    return sorted(out)


def top_key(path):
    """The file's kind from its top-level keys: vault, type, scenario, sweep, cameras or None."""
    try:
        text = open(path, encoding="utf-8", errors="replace").read()
    except OSError:
        return None
    for kind in ("campaign", "scenario", "sweep", "type", "vault"):
        if re.search(rf"^{kind}:", text, re.M):
            return kind
    return None


def cube_meshes():
    """A unit cube in each text and binary format the mesh target reads."""
    v = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    f = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
         (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    obj = "".join(f"v {a} {b} {c}\n" for a, b, c in v) + "".join(f"f {a+1} {b+1} {c+1}\n" for a, b, c in f)
    ply = ("ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 12\nproperty list uchar int vertex_indices\nend_header\n"
           + "".join(f"{a} {b} {c}\n" for a, b, c in v) + "".join(f"3 {a} {b} {c}\n" for a, b, c in f))
    off = "OFF\n8 12 0\n" + "".join(f"{a} {b} {c}\n" for a, b, c in v) + "".join(f"3 {a} {b} {c}\n" for a, b, c in f)
    stl_ascii = "solid cube\n" + "".join(
        "facet normal 0 0 0\nouter loop\n" + "".join("vertex %d %d %d\n" % v[i] for i in t) + "endloop\nendfacet\n"
        for t in f) + "endsolid cube\n"
    stl_binary = b"\0" * 80 + struct.pack("<I", len(f)) + b"".join(
        struct.pack("<12fH", 0, 0, 0, *[c for i in t for c in v[i]], 0) for t in f)
    positions = b"".join(struct.pack("<3f", *p) for p in v)
    indices = b"".join(struct.pack("<3H", *t) for t in f)
    buffer = positions + indices
    gltf = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(buffer),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(buffer).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(positions)},
                        {"buffer": 0, "byteOffset": len(positions), "byteLength": len(indices)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0,
    }
    gltf_text = json.dumps(gltf).encode()
    glb_json = json.dumps({**gltf, "buffers": [{"byteLength": len(buffer)}]}).encode()
    glb_json += b" " * (-len(glb_json) % 4)
    glb = (struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(glb_json) + 8 + len(buffer))
           + struct.pack("<I4s", len(glb_json), b"JSON") + glb_json + struct.pack("<I4s", len(buffer), b"BIN\0") + buffer)
    return {"obj": [obj.encode()], "ply": [ply.encode()], "off": [off.encode()], "gltf": [gltf_text],
            "stl": [stl_ascii.encode(), stl_binary], "glb": [glb]}


def expressions():
    found = set()
    for path in project_files("*.yaml"):
        for line in open(path, encoding="utf-8", errors="replace"):
            for m in re.finditer(r"expr:\s*\"([^\"]+)\"", line):
                found.add(m.group(1))
    found |= {"Room1.length / 0 > 1", "0/0 == 0/0", "p * 2 > 1 m", "R.height > 3 ? D.height < 1 : 1",
              "count(type:drum) == 1", "sum(type:drum.fill_mass) <= 1000", "!(R.length < 1) && R.width >= 2",
              "min(R.length, R.width) ^ 2", "atan2(1, 2) + deg(pi) - rad(90)", "1e306 km", "2.5 m", "-3 deg"}
    return sorted(found)


def seeds(target):
    """(name, bytes) pairs."""
    if target in ("vault", "type", "scenario", "sweep"):
        for path in project_files("*.yaml"):
            # A campaign file seeds the scenario target, which loads its input as both.
            if top_key(path) == target or (target == "scenario" and top_key(path) == "campaign"):
                yield os.path.relpath(path, ROOT).replace("/", "_"), open(path, "rb").read()
    elif target == "expr":
        for i, e in enumerate(expressions()):
            yield f"expr{i}", e.encode()
    elif target == "urdf":
        for path in project_files("*.urdf"):
            yield os.path.relpath(path, ROOT).replace("/", "_"), open(path, "rb").read()
    elif target == "mesh":
        for ext, blobs in cube_meshes().items():
            for i, blob in enumerate(blobs):
                yield f"cube{i}.{ext}", bytes([MESH_EXTENSIONS.index(ext)]) + blob
        for ext in MESH_EXTENSIONS:
            for path in project_files("*." + ext):
                if os.path.isfile(path) and os.path.getsize(path) < 1 << 20:
                    yield os.path.relpath(path, ROOT).replace("/", "_"), bytes([MESH_EXTENSIONS.index(ext)]) + open(path, "rb").read()
    else:
        sys.exit(f"seeds.py: unknown target '{target}'")


def dictionary():
    words = set()

    def walk(node):
        if isinstance(node, dict):
            for k, v in node.items():
                if k == "properties" and isinstance(v, dict):
                    words.update(v.keys())
                if k in ("enum",) and isinstance(v, list):
                    words.update(str(x) for x in v if isinstance(x, str))
                if k == "const" and isinstance(v, str):
                    words.add(v)
                walk(v)
        elif isinstance(node, list):
            for x in node:
                walk(x)

    for path in glob.glob(os.path.join(ROOT, "schemas", "*.json")):
        walk(json.load(open(path)))
    units = re.findall(r'\{"([^"]+)", Dim::', open(os.path.join(ROOT, "src", "core", "units.cpp")).read())
    words.update(" " + u for u in units)
    words.update(["==", "!=", "<=", ">=", "&&", "||", "?", ":", "^", "min(", "max(", "abs(", "sqrt(", "sin(",
                  "cos(", "tan(", "atan2(", "floor(", "ceil(", "deg(", "rad(", "pi", "count(", "sum(", "avg(",
                  "type:", "*", ".nan", ".inf", "1e308", "-0", "&a", "*a", "<<: ", "{", "}", "[", "]", "- ", ": ",
                  "sscs: 1", "package://", "<robot", "<link", "<joint", "<parent", "<child", "<origin", "<axis",
                  "<limit", "<collision", "<visual", "<geometry", "<box", "<cylinder", "<sphere", "<mesh",
                  "<inertial", "<mass", "<inertia", "<mimic", "<safety_controller", "xyz=", "rpy=", "size=",
                  "radius=", "length=", "filename=", "lower=", "upper=", "revolute", "prismatic", "continuous",
                  "fixed", "floating", "solid", "facet normal", "outer loop", "vertex", "endloop", "endfacet",
                  "element vertex", "property float", "end_header", "glTF", "OFF", "v ", "f ", "vn ", "usemtl"])
    return sorted(words)


def main():
    args = sys.argv[1:]
    if "--dict" in args:
        i = args.index("--dict")
        with open(args[i + 1], "w") as out:
            for w in dictionary():
                out.write(json.dumps(w) + "\n")
        del args[i:i + 2]
    if args:
        target, out_dir = args
        os.makedirs(out_dir, exist_ok=True)
        n = 0
        for name, data in seeds(target):
            with open(os.path.join(out_dir, name), "wb") as f:
                f.write(data)
            n += 1
        if n == 0:
            sys.exit(f"seeds.py: no seeds for '{target}'")


if __name__ == "__main__":
    main()
