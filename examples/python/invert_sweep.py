#!/usr/bin/env python3
"""Inverse statics, then a parallel sweep: how far hair held by its inverted rest shapes sags when
its fibres soften (e.g. wet hair), solved in a multiprocessing pool.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/invert_sweep.py TARGET.hair \
        [--strands 20] [--workers 2] [--segments 0]

TARGET.hair: strands to hold (metres, z up, root first; e.g. the `equilibrium.hair` of
`ringlet invert`, or any groom's strands.hair). The script fits and inverts them with
ringlet.invert (the paper's 50-um fibre, no body), then, for Young's moduli scaled by 1, 0.8,
0.6 and 0.4, solves copies of the inverted models in a spawn-context multiprocessing pool (the
models travel pickled, bit for bit) and prints the largest distance of each equilibrium from
its target, in units of the strand length L. With the full modulus the strands stay on their
targets (the inversion's point); softer fibres sag.
"""
import argparse
import copy
import multiprocessing

import numpy as np

import ringlet


def solve_points(models):
    """Worker: the equilibria of the models, 8 points per helical segment."""
    return [r.points for r in ringlet.solve(models, points_per_segment=8, threads=1)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("target", help=".hair file of target strands (metres, z up)")
    parser.add_argument("--strands", type=int, default=20, help="strands to use (first N)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes")
    parser.add_argument("--segments", type=int, default=0,
                        help="helical segments per strand (0: the fewest meeting the fit tolerance)")
    args = parser.parse_args()

    curves = ringlet.read_hair_file(args.target)
    ends = np.cumsum(np.asarray(curves.point_counts, dtype=np.int64))
    targets = np.split(np.asarray(curves.points, dtype=np.float64), ends[:-1])[:args.strands]

    def progress(stage, done, total):
        print("\r%s %d/%d" % (stage, done, total), end="", flush=True)
    result = ringlet.invert(targets, segments=args.segments, progress=progress)
    print()  # ends the progress line
    s = result["summary"]
    print("inverted %d strands: fit max %.3g L, held within %.3g L (naive rest shapes: %.3g L), "
          "%d unstable" % (s["strands"], s["fit_max_distance_per_length"],
                           s["max_deviation_per_length"], s["naive_max_deviation_per_length"],
                           s["unstable"]))

    # The reference: each inverted model's own equilibrium at full stiffness, sampled like the
    # sweep's (8 points per segment).
    models = result["models"]
    factors = [1.0, 0.8, 0.6, 0.4]
    jobs = []
    for factor in factors:
        softened = copy.deepcopy(models)
        for m in softened:
            material = m.material
            material.young_modulus *= factor
            m.material = material
        jobs.append(softened)
    with multiprocessing.get_context("spawn").Pool(args.workers) as pool:
        solved = pool.map(solve_points, jobs)
    reference = solved[0]
    lengths = [m.length() for m in models]
    print("E factor   largest sag from the held shape (L)")
    for factor, points in zip(factors, solved):
        sag = max(np.linalg.norm(p - r, axis=1).max() / length
                  for p, r, length in zip(points, reference, lengths))
        print("%8.2f   %.4g" % (factor, sag))


if __name__ == "__main__":
    main()
