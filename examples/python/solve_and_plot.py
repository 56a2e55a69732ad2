#!/usr/bin/env python3
"""Solve the strands of a scene with ringlet and plot them with matplotlib.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/solve_and_plot.py \
        examples/vertical_curly.json strand.png

Each strand is drawn in two side views (x-z and y-z, metres) with its material frame's major
axis n1 every few samples; the title gives the solver's summary.
"""
import argparse

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

import ringlet


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", help="scene file (docs/scene-format.md)")
    parser.add_argument("output", help="PNG to write")
    parser.add_argument("--points-per-segment", type=int, default=16)
    args = parser.parse_args()

    results = ringlet.solve(args.scene, points_per_segment=args.points_per_segment)
    fig, axes = plt.subplots(1, 2, figsize=(8, 5), sharey=True)
    for i, r in enumerate(results):
        p = r.points                       # (N, 3) metres, a view of the result
        n1 = r.material_frames[:, :, 0]    # (N, 3) major axis of the section
        s = r.summary
        print("strand %d: %s, %s, %d iterations, residual %.2g, tip %s m" % (
            i, s.termination, "stable" if s.stable else "NOT stable", s.iterations, s.residual,
            np.array2string(p[-1], precision=4)))
        for ax, (a, b) in zip(axes, ((0, 2), (1, 2))):
            ax.plot(p[:, a], p[:, b], lw=1.5, label="strand %d" % i)
            step = max(1, len(p) // 40)
            scale = 0.05 * np.ptp(p[:, 2]) if np.ptp(p[:, 2]) > 0 else 0.005
            ax.quiver(p[::step, a], p[::step, b], n1[::step, a], n1[::step, b], angles="xy",
                      scale_units="xy", scale=1 / scale, width=0.003, color="0.6")
    for ax, name in zip(axes, ("x", "y")):
        ax.set_xlabel(name + " (m)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("z (m)")
    axes[0].legend(fontsize=8)
    fig.suptitle("%s: %d strand(s) at equilibrium (grey: major axis n1)" % (args.scene,
                                                                             len(results)))
    fig.tight_layout()
    fig.savefig(args.output, dpi=100)
    print("wrote %s (matplotlib backend %s)" % (args.output, matplotlib.get_backend()))


if __name__ == "__main__":
    main()
