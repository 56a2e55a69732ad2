#!/usr/bin/env python3
"""Writes a scene of N copies of a scene's first strand, for measuring `ringlet solve` per strand.

  scripts/make_many_strands.py examples/vertical_curly.json 10000 /tmp/many.json [--no-stability]

The copies differ only in their root position (a square grid, 1 cm apart), so that every strand
costs the library exactly what the original does; process start-up and the per-file work are
amortized over N (docs/benchmarks.md, "CLI overhead").
"""
import argparse
import copy
import json
import math


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", help="scene whose first strand is copied")
    parser.add_argument("count", type=int, help="number of strands")
    parser.add_argument("output", help="scene file to write")
    parser.add_argument("--no-stability", action="store_true",
                        help='write "solver": {"check_stability": false}')
    args = parser.parse_args()

    with open(args.scene) as f:
        scene = json.load(f)
    strand = scene["strands"][0]
    side = math.ceil(math.sqrt(args.count))
    strands = []
    for i in range(args.count):
        s = copy.deepcopy(strand)
        x, y = i % side, i // side
        s["root"]["position"] = [0.01 * x, 0.01 * y, strand["root"]["position"][2]]
        strands.append(s)
    scene["strands"] = strands
    if args.no_stability:
        scene.setdefault("solver", {})["check_stability"] = False
    with open(args.output, "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
