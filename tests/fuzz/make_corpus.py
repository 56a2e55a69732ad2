#!/usr/bin/env python3
"""Writes a seed corpus for one fuzz harness (tests/fuzz, docs/robustness.md#fuzzing).

usage: make_corpus.py OUT_DIR SOURCE_DIR MAX_LEN [files or globs] [options]
  files/globs       relative to SOURCE_DIR; JSON files are parsed, others copied as they are
  --extract KEY     for JSON: the document's KEY member as a document of its own (when an object)
  --extract-wrapped KEY   for JSON: {KEY: document[KEY]} (when present)
  --inline-body     for hairstyles: a "body" given by file name is replaced by that body file's
                    object (so that the harness, which reads no files, gets past the body)
  --json-mutants N  for each JSON seed, up to N JSON-aware mutants: each member removed, each
                    value replaced by hostile values (0, -1, 5e-324, 1e308, 2^53 + 1, 2^63, huge
                    and negative integers, strings, null, booleans, empty and nested containers),
                    arrays emptied and repeated; chosen deterministically (seeded)
  --hair-seeds      small valid .hair files with each combination of the optional arrays
  --obj-seeds       small valid OBJ meshes (tetrahedron, cube of quads, two objects, groups)
Inputs larger than MAX_LEN bytes are left out. Standard library only (Debian's python3).
"""
import copy
import glob
import json
import os
import random
import struct
import sys

HOSTILE = [0, -1, 1, 5e-324, 1e308, -1e308, 2**53 + 1, 2**63, -(2**63), 2**64, 1e-300,
           0.5, "x", "", None, True, False, [], {}, [0, 0, 0], [1e308, 1e308, 1e308],
           "auto", "newton", [[[[[[]]]]]]]


def paths_of(value, prefix=()):
    """Every path (tuple of keys / indices) to a value of the document, root excluded."""
    out = []
    if isinstance(value, dict):
        for k, v in value.items():
            out.append(prefix + (k,))
            out.extend(paths_of(v, prefix + (k,)))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            out.append(prefix + (i,))
            out.extend(paths_of(v, prefix + (i,)))
    return out


def get_parent(doc, path):
    node = doc
    for key in path[:-1]:
        node = node[key]
    return node


def mutants(doc, count, rng):
    """JSON-aware mutants of doc (a parsed document), deterministic for a given rng."""
    candidates = []
    for path in paths_of(doc):
        candidates.append(("remove", path, None))
        for value in HOSTILE:
            candidates.append(("set", path, value))
        candidates.append(("repeat", path, None))
    rng.shuffle(candidates)
    out = []
    for kind, path, value in candidates[:count]:
        m = copy.deepcopy(doc)
        parent = get_parent(m, path)
        key = path[-1]
        if kind == "remove":
            del parent[key]
        elif kind == "set":
            parent[key] = copy.deepcopy(value)
        elif isinstance(parent[key], list) and parent[key]:
            parent[key] = parent[key] * 8
        elif isinstance(parent, list):
            parent.extend([copy.deepcopy(parent[key])] * 8)
        else:
            continue
        out.append(m)
    return out


def hair_file(strands, points_per_strand, flags):
    """A small valid .hair file (Cem Yuksel's format, hair_file.h): flags 1 segments, 2 points,
    4 thickness, 8 transparency, 16 colour."""
    n = strands * points_per_strand
    header = b"HAIR" + struct.pack("<IIII", strands, n, flags, points_per_strand - 1)
    header += struct.pack("<fffff", 1e-4, 0.0, 0.3, 0.2, 0.1)
    header += b"fuzz seed".ljust(88, b"\0")
    body = b""
    if flags & 1:
        body += struct.pack("<%dH" % strands, *([points_per_strand - 1] * strands))
    for s in range(strands):
        for p in range(points_per_strand):
            body += struct.pack("<fff", 0.01 * s, 0.0, -0.01 * p)
    if flags & 4:
        body += struct.pack("<%df" % n, *([8e-5] * n))
    if flags & 8:
        body += struct.pack("<%df" % n, *([0.0] * n))
    if flags & 16:
        body += struct.pack("<%df" % (3 * n), *([0.5] * (3 * n)))
    return header + body


OBJ_SEEDS = {
    "tetrahedron.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    "cube_quads.obj": ("o cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
                       "v 0 1 1\nvn 0 0 1\nvt 0 0\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\n"
                       "f 3 4 8 7\nf 4 1 5 8\n"),
    "two_objects.obj": ("o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1/1 3/1 2/1\nf 1//1 2//1 4//1\n"
                        "f 1/1/1 4/1/1 3/1/1\nf 2 3 4\ng b\nv 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\n"
                        "f -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\nvt 0 0\nvn 0 0 1\n"),
    "open_mesh.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "weights_colours.obj": ("v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1 0.5 0.5 0.5\nv 0 0 1 1 0 0 0\n"
                            "# comment\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"),
}


def main(argv):
    out_dir, source_dir, max_len = argv[0], argv[1], int(argv[2])
    args = argv[3:]
    files, extract, wrapped, inline_body, n_mutants, hair, obj = [], None, None, False, 0, False, False
    i = 0
    while i < len(args):
        a = args[i]
        if a == "--extract":
            extract = args[i + 1]; i += 1
        elif a == "--extract-wrapped":
            wrapped = args[i + 1]; i += 1
        elif a == "--inline-body":
            inline_body = True
        elif a == "--json-mutants":
            n_mutants = int(args[i + 1]); i += 1
        elif a == "--hair-seeds":
            hair = True
        elif a == "--obj-seeds":
            obj = True
        else:
            found = sorted(glob.glob(os.path.join(source_dir, a)))
            if not found:
                sys.exit("make_corpus.py: no file matches " + a)
            files.extend(found)
        i += 1
    os.makedirs(out_dir, exist_ok=True)
    written = 0

    def write(name, data):
        nonlocal written
        if isinstance(data, str):
            data = data.encode()
        if len(data) > max_len:
            return
        with open(os.path.join(out_dir, name), "wb") as f:
            f.write(data)
        written += 1

    rng = random.Random(16)
    for path in files:
        base = os.path.basename(path)
        with open(path, "rb") as f:
            raw = f.read()
        if not path.endswith(".json"):
            write(base, raw)
            continue
        doc = json.loads(raw)
        docs = []
        if extract is None and wrapped is None:
            docs.append(doc)
        if inline_body and isinstance(doc.get("body"), str):
            body_path = os.path.join(os.path.dirname(path), doc["body"])
            inlined = copy.deepcopy(doc)
            with open(body_path) as f:
                inlined["body"] = json.load(f)
            docs.append(inlined)
        if extract is not None:
            if isinstance(doc, dict) and isinstance(doc.get(extract), dict):
                docs.append(doc[extract])
            elif isinstance(doc, dict) and extract not in doc:
                docs.append(doc)  # a document of that kind itself (e.g. a body file)
        if wrapped is not None and isinstance(doc, dict):
            docs.append({wrapped: doc[wrapped]} if wrapped in doc else doc)
        for k, d in enumerate(docs):
            stem = "%s.%d" % (base, k)
            write(stem + ".json", json.dumps(d, indent=1))
            for m, mutant in enumerate(mutants(d, n_mutants, rng)):
                write("%s.m%03d.json" % (stem, m), json.dumps(mutant))
    if hair:
        for flags in range(2, 32, 2):  # the points array (2) is required
            for with_segments in (0, 1):
                write("seed_%02d.hair" % (flags | with_segments),
                      hair_file(3, 4, flags | with_segments))
        write("one_strand_two_points.hair", hair_file(1, 2, 2))
    if obj:
        for name, text in OBJ_SEEDS.items():
            write(name, text)
    print("make_corpus.py: %d inputs in %s" % (written, out_dir))


if __name__ == "__main__":
    main(sys.argv[1:])
