#!/usr/bin/env python3
"""Draws the pictures of docs/inverse.md from a `ringlet groom` output (masters.json, the target)
and a `ringlet invert` output (naive.hair, equilibrium.hair): three columns, the target, the naive
rest shape (rest = target) after the forward solve, and the inverted rest shape after the forward
solve, seen from the side and from the back, on the body's spheres. In the last two columns each
hair segment is coloured by its distance from the target (same scale in both: what sags is
red, what holds is blue). Needs numpy and matplotlib: run with /usr/bin/python3.

    /usr/bin/python3 scripts/plot_inverse.py GROOM_DIR INVERT_DIR -o docs/images/inverse_head.png
        [--body examples/bodies/mannequin.json] [--views side,back]

scripts/make_inverse_pictures.sh runs the whole chain (groom, invert, this script).
"""

import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_groom import (PALETTES, draw_view, read_hair, read_masters, read_spheres,  # noqa: E402
                        save_png, view_limits)


def segments_of(strands):
    """Segments (K, 2, 3) joining consecutive points of each strand, and their strand index."""
    segments, owner = [], []
    for k, p in enumerate(strands):
        segments.append(np.stack([p[:-1], p[1:]], axis=1))
        owner.append(np.full(len(p) - 1, k))
    return np.concatenate(segments), np.concatenate(owner)


def split(points, counts):
    return np.split(points, np.cumsum(counts)[:-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("groom_dir")
    parser.add_argument("invert_dir")
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--body", default="examples/bodies/mannequin.json")
    parser.add_argument("--views", default="side,back")
    parser.add_argument("--scale", type=float, default=0.05,
                        help="distance (m) at the top of the colour scale")
    parser.add_argument("--dpi", type=int, default=80)
    args = parser.parse_args()

    target, _ = read_masters(os.path.join(args.groom_dir, "masters.json"))
    with open(os.path.join(args.invert_dir, "summary.json")) as f:
        summary = json.load(f)
    panels = [("target: groomed masters", target, None)]
    for name, title in (("naive.hair", "naive rest shape (= target)\nafter the forward solve"),
                        ("equilibrium.hair", "inverted rest shape\nafter the forward solve")):
        points, counts = read_hair(os.path.join(args.invert_dir, name))
        strands = split(points, counts)
        if len(strands) != len(target) or any(
                len(a) != 4 * (len(b) - 1) + 1 for a, b in zip(strands, target)):
            raise SystemExit(f"{name}: the strands do not match the target's segments")
        # Distance from the target at the segment ends (masters.json has those points; the
        # .hair files 4 points per segment), interpolated along the segment for the colours.
        distance = []
        for a, b in zip(strands, target):
            ends = np.linalg.norm(a[::4] - b, axis=1)
            distance.append(np.interp(np.arange(len(a)) / 4.0, np.arange(len(b)), ends))
        panels.append((title, strands, distance))

    spheres = read_spheres(args.body)
    views = args.views.split(",")
    all_points = np.concatenate([np.concatenate(p[1]) for p in panels])
    limits = view_limits(all_points, spheres, views)
    figure, axes = plt.subplots(len(views), 3, figsize=(9.0, 3.9 * len(views)), squeeze=False)
    figure.subplots_adjust(left=0.01, right=0.86, top=0.90, bottom=0.01, wspace=0.02, hspace=0.02)
    colour_map = plt.get_cmap("coolwarm")
    dark, light = (np.array(c) for c in PALETTES["straight"])
    rng = np.random.default_rng(1)
    shade = rng.uniform(0.0, 1.0, len(target))
    for column, (title, strands, distance) in enumerate(panels):
        segments, owner = segments_of(strands)
        if distance is None:
            colours = dark + (light - dark) * shade[owner][:, None]
        else:
            d = np.concatenate([0.5 * (x[:-1] + x[1:]) for x in distance])
            colours = colour_map(np.clip(d / args.scale, 0.0, 1.0))[:, :3]
        for row, view in enumerate(views):
            draw_view(axes[row][column], view, segments, colours, spheres, limits[row], 0.9, 0.95)
        if distance is None:
            label = (f"{title}\n{len(strands)} strands, {summary.get('supported_samples', 0)} "
                     f"samples carry\n{1000 * summary.get('support_force', 0.0):.3g} mN of support")
        else:
            largest = max(x.max() for x in distance)
            mean = np.mean(np.concatenate([x[::4] for x in distance]))
            label = f"{title}\noff by {100 * largest:.2g} cm max, {100 * mean:.2g} cm mean"
        axes[0][column].set_title(label, fontsize=8)
    bar = figure.colorbar(plt.cm.ScalarMappable(cmap=colour_map,
                                                norm=plt.Normalize(0.0, args.scale * 100)),
                          cax=figure.add_axes([0.88, 0.25, 0.02, 0.5]))
    bar.set_label("distance from the target (cm)")
    save_png(figure, args.output, args.dpi, 256)  # 256: the colour scale stays readable
    print(f"wrote {args.output} ({os.path.getsize(args.output) // 1024} KB)")


if __name__ == "__main__":
    main()
