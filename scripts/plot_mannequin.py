#!/usr/bin/env python3
"""Draws examples/bodies/mannequin.obj and the spheres of mannequin.json, front and side views,
into docs/images/mannequin.png (docs/body.md). Needs matplotlib: run with /usr/bin/python3.

    /usr/bin/python3 scripts/plot_mannequin.py [examples/bodies] [docs/images/mannequin.png]
"""

import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if parts and parts[0] == "v":
                vertices.append(tuple(float(x) for x in parts[1:4]))
            elif parts and parts[0] == "f":
                faces.append([int(p.split("/")[0]) - 1 for p in parts[1:]])
    return vertices, faces


def main():
    directory = sys.argv[1] if len(sys.argv) > 1 else "examples/bodies"
    output = sys.argv[2] if len(sys.argv) > 2 else "docs/images/mannequin.png"
    vertices, faces = read_obj(directory + "/mannequin.obj")
    with open(directory + "/mannequin.json") as f:
        spheres = json.load(f)["spheres"]

    figure = plt.figure(figsize=(10, 3.3))
    views = [("mesh, front (from +y)", 90, True), ("mesh, side (from +x)", 0, True),
             ("spheres, front", 90, False), ("spheres, side", 0, False)]
    for k, (title, azimuth, mesh) in enumerate(views):
        axes = figure.add_subplot(1, 4, k + 1, projection="3d")
        if mesh:
            polygons = [[vertices[i] for i in face] for face in faces]
            axes.add_collection3d(Poly3DCollection(polygons, facecolor="#d9b99b",
                                                   edgecolor="#8a6d55", linewidth=0.05))
        else:
            for s in spheres:
                c, r = s["center"], s["radius"]
                n = 16
                for i in range(n):
                    for j in range(2 * n):
                        th0, th1 = math.pi * i / n, math.pi * (i + 1) / n
                        ph0, ph1 = math.pi * j / n, math.pi * (j + 1) / n
                        quad = [(c[0] + r * math.sin(t) * math.cos(p),
                                 c[1] + r * math.sin(t) * math.sin(p), c[2] + r * math.cos(t))
                                for t, p in ((th0, ph0), (th1, ph0), (th1, ph1), (th0, ph1))]
                        axes.add_collection3d(Poly3DCollection([quad], facecolor="#a7c4d9",
                                                               edgecolor="none"))
        axes.set_xlim(-0.3, 0.3)
        axes.set_ylim(-0.3, 0.3)
        axes.set_zlim(-0.5, 0.1)
        axes.set_box_aspect((1, 1, 1))
        axes.view_init(elev=10, azim=azimuth)
        axes.set_title(title, fontsize=9)
        axes.set_xlabel("x (m)", fontsize=7)
        axes.set_ylabel("y (m)", fontsize=7)
        axes.set_zlabel("z (m)", fontsize=7)
        axes.tick_params(labelsize=6)
    figure.tight_layout()
    figure.savefig(output, dpi=110, bbox_inches="tight")
    print(output)


if __name__ == "__main__":
    main()
