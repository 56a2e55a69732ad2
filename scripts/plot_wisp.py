#!/usr/bin/python3
"""Draws the wisps of tools/wisp_example's CSV (wisp, strand, point, x, y, z in m) to a PNG:
one 3D panel per wisp, the master (strand 0) thick and dark, the children thin.

usage: /usr/bin/python3 scripts/plot_wisp.py WISP.csv OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_wisp.py WISP.csv OUT.png")
    wisps = {}
    with open(sys.argv[1]) as f:
        for row in csv.DictReader(f):
            strands = wisps.setdefault(int(row["wisp"]), {})
            strands.setdefault(int(row["strand"]), []).append(
                [float(row[c]) * 100 for c in ("x", "y", "z")])  # cm
    titles = {0: "straight master", 1: "curly master (κ⁰ = 60 m⁻¹, τ⁰ = 12 m⁻¹)"}
    fig = plt.figure(figsize=(11, 5.5), dpi=110)
    for w, strands in sorted(wisps.items()):
        ax = fig.add_subplot(1, len(wisps), w + 1, projection="3d")
        pts = [p for s in strands.values() for p in s]
        lo = [min(p[k] for p in pts) for k in range(3)]
        hi = [max(p[k] for p in pts) for k in range(3)]
        for k, s in sorted(strands.items()):
            xs, ys, zs = zip(*s)
            if k == 0:
                ax.plot(xs, ys, zs, color="k", lw=1.8, zorder=3)
            else:
                ax.plot(xs, ys, zs, color="tab:brown", lw=0.4, alpha=0.5)
        # Equal scales on the three axes so that curls look like curls.
        span = max(h - l for l, h in zip(lo, hi)) / 2
        for k, setter in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
            mid = (lo[k] + hi[k]) / 2
            setter(mid - span, mid + span)
        ax.set_xlabel("x (cm)")
        ax.set_ylabel("y (cm)")
        ax.set_zlabel("z (cm)")
        ax.set_title(f"{titles.get(w, w)}: {len(strands)} strands, r_w = 5 mm", fontsize=10)
        ax.view_init(elev=12, azim=-70)
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    fig.savefig(sys.argv[2])


if __name__ == "__main__":
    main()
