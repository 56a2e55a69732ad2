#!/usr/bin/env python3
"""Draws the CSV of tools/drape_example (a curly strand growing on a sphere, the paper's Figure 2
right) into docs/images/drape_sphere.png: one panel per length, seen from -x (-y to the right,
z up), the sphere as a shaded disc, the strand tube in front of or behind it by depth, darker
farther away. Needs numpy and matplotlib: run with /usr/bin/python3.

    ./build/tools/drape_example drape.csv
    /usr/bin/python3 scripts/plot_drape.py drape.csv docs/images/drape_sphere.png
"""

import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_groom import save_png, sphere_image  # noqa: E402

HAIR = np.array([0.55, 0.24, 0.10])  # auburn


def main():
    source = sys.argv[1] if len(sys.argv) > 1 else "drape.csv"
    output = sys.argv[2] if len(sys.argv) > 2 else "docs/images/drape_sphere.png"
    with open(source) as f:
        words = f.readline().split()
    if words[:2] != ["#", "sphere"]:
        raise SystemExit(f"{source}: expected a first line '# sphere cx cy cz radius'")
    centre, radius = np.array([float(w) for w in words[2:5]]), float(words[5])
    data = np.loadtxt(source, delimiter=",", comments="#", skiprows=2)
    index, length, xyz = data[:, 0].astype(int), data[:, 1], data[:, 3:6]

    # Seen from -x: the strand falls toward -y (its curl axis, the root's n1 = +y, and the
    # torsion carry it there), which is then on the right.
    right, up, toward = np.array([0, -1.0, 0]), np.array([0, 0, 1.0]), np.array([-1.0, 0, 0])
    u_all, v_all = xyz @ right, xyz @ up
    count = index.max() + 1
    figure, axes_row = plt.subplots(1, count, figsize=(2.3 * count, 3.0))
    image = sphere_image(240)
    for k, axes in enumerate(np.atleast_1d(axes_row)):
        p = xyz[index == k]
        segments = np.stack([p[:-1], p[1:]], axis=1)
        depth = segments.mean(axis=1) @ toward - centre @ toward
        xy = np.stack([segments @ right, segments @ up], axis=-1)
        shade = 0.5 + 0.5 * np.clip((depth + radius) / (2 * radius), 0, 1)
        colours = HAIR[None, :] * shade[:, None]
        behind = depth < 0
        u, v = centre @ right, centre @ up
        axes.add_collection(LineCollection(xy[behind], colors=colours[behind], linewidths=1.4,
                                           zorder=1, capstyle="round"))
        axes.imshow(image, extent=(u - radius, u + radius, v - radius, v + radius), zorder=2,
                    interpolation="bilinear")
        axes.add_collection(LineCollection(xy[~behind], colors=colours[~behind], linewidths=1.4,
                                           zorder=3, capstyle="round"))
        axes.plot(*(p[0] @ np.stack([right, up], axis=1)), "o", color="k", markersize=2.5,
                  zorder=4)
        axes.set_xlim(min(u - 1.1 * radius, u_all.min() - 0.01),
                      max(u + 1.1 * radius, u_all.max() + 0.01))
        axes.set_ylim(min(v - 1.1 * radius, v_all.min() - 0.01),
                      max(v + 1.1 * radius, v_all.max() + 0.01))
        axes.set_aspect("equal")
        axes.set_xticks([])
        axes.set_yticks([])
        for side in axes.spines.values():
            side.set_visible(False)
        axes.set_title(f"L = {100 * length[index == k][0]:.0f} cm", fontsize=9)
    figure.suptitle(f"a curly strand growing on a sphere (R = {100 * radius:.0f} cm; "
                    "caucasian curly: curl radius 1.2 cm, pitch 0.6 cm), seen from -x", fontsize=9)
    figure.subplots_adjust(left=0.01, right=0.99, bottom=0.01, top=0.86, wspace=0.03)
    save_png(figure, output, 130, 256)
    return 0


if __name__ == "__main__":
    sys.exit(main())
