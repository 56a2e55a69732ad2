#!/usr/bin/python3
"""Draws scalp roots and their tangents (docs/images/scalp_roots.png).

Usage:
  RINGLET_SCALP_CSV=/tmp/roots.csv build/tests/ringlet_tests --gtest_filter='ScalpPicture.*'
  /usr/bin/python3 scripts/plot_scalp_roots.py /tmp/roots.csv docs/images/scalp_roots.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main(csv_path, png_path):
    d = np.genfromtxt(csv_path, delimiter=",", names=True)
    p = np.stack([d["x"], d["y"], d["z"]], axis=1)
    t = np.stack([d["tx"], d["ty"], d["tz"]], axis=1)
    side = d["side"]
    colors = np.where(side > 0, "tab:red", "tab:blue")
    tip = p + 0.012 * t  # 12 mm tangent segments

    fig = plt.figure(figsize=(10, 5))
    views = [("side view (face to the left)", 10, 180), ("from above and behind", 55, -90)]
    for k, (title, elev, azim) in enumerate(views):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        u, v = np.mgrid[0:2 * np.pi:40j, 0:np.pi:20j]
        r = 0.098
        ax.plot_surface(r * np.cos(u) * np.sin(v), r * np.sin(u) * np.sin(v), r * np.cos(v),
                        color="0.85", alpha=0.3, linewidth=0)
        for a, b, c in zip(p, tip, colors):
            ax.plot([a[0], b[0]], [a[1], b[1]], [a[2], b[2]], color=c, linewidth=0.7)
        ax.scatter(p[:, 0], p[:, 1], p[:, 2], s=2, c="k")
        ax.quiver(0, 0.1, 0, 0, 0.04, 0, color="g")  # the face looks +y
        ax.set_title(title, fontsize=9)
        ax.view_init(elev=elev, azim=azim)
        ax.set_box_aspect((1, 1, 1))
        for setter in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
            setter(-0.12, 0.12)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_zticks([])
    fig.suptitle(f"{len(p)} Poisson-disk roots combed down/back away from a centre part\n"
                 "(red: +x side, blue: -x side; green arrow: face direction)", fontsize=9)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
