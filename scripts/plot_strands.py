#!/usr/bin/python3
"""Draws the strands of a `ringlet solve` result JSON in 3D (matplotlib, Agg) to a PNG.

usage: /usr/bin/python3 scripts/plot_strands.py RESULT.json OUT.png [TITLE]
(Debian's /usr/bin/python3 with python3-matplotlib; installed by scripts/setup.sh)
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: plot_strands.py RESULT.json OUT.png [TITLE]")
    with open(sys.argv[1]) as f:
        result = json.load(f)
    fig = plt.figure(figsize=(7, 6), dpi=110)
    ax = fig.add_subplot(projection="3d")
    lo, hi = [1e9] * 3, [-1e9] * 3
    for i, strand in enumerate(result["strands"]):
        pts = strand["points"]
        xs, ys, zs = ([p[k] * 100 for p in pts] for k in range(3))  # cm
        label = f"{i}: {strand['termination']}, {'stable' if strand['stable'] else 'NOT stable'}"
        ax.plot(xs, ys, zs, lw=1.6, label=label)
        ax.scatter([xs[0]], [ys[0]], [zs[0]], color="k", s=12)
        for k, c in enumerate((xs, ys, zs)):
            lo[k], hi[k] = min(lo[k], min(c)), max(hi[k], max(c))
    # Equal scales on the three axes so that curls look like curls.
    span = max(h - l for l, h in zip(lo, hi)) / 2
    for k, setter in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
        mid = (lo[k] + hi[k]) / 2
        setter(mid - span, mid + span)
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    ax.set_zlabel("z (cm)")
    ax.set_title(sys.argv[3] if len(sys.argv) > 3 else sys.argv[1], fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(sys.argv[2])


if __name__ == "__main__":
    main()
