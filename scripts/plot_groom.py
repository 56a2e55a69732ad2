#!/usr/bin/env python3
"""Draws a groom written by `ringlet groom` (strands.hair + masters.json) on its body of spheres,
front and side views, into a PNG (docs/hairstyles.md). Needs numpy and matplotlib: run with
/usr/bin/python3.

    /usr/bin/python3 scripts/plot_groom.py OUTDIR -o groom.png
        [--body examples/bodies/mannequin.json] [--title TEXT] [--strands 8000]
        [--palette wavy] [--views front,side]
    /usr/bin/python3 scripts/plot_groom.py OUTDIR_A OUTDIR_B -o compare.png --labels A B
        --views side,slice
    /usr/bin/python3 scripts/plot_groom.py --stats OUTDIR...      (numbers only, JSON lines)

How it draws. The views are orthographic projections done here (front: looking along -y at the
face, which looks toward +y; side: looking along -x at the mannequin's right side), not
matplotlib's mplot3d: mplot3d sorts whole collections, so hair behind the head would be drawn
over it. Here each sphere is a shaded disc and every hair segment is drawn in the depth interval
between two sphere centres it belongs to (painter's algorithm, back to front). For a segment
outside a sphere whose projection falls on the sphere's disc, "behind the sphere's centre" is the
same as "behind its visible surface", so this ordering is exact for one sphere and very close for
the mannequin's union. Segments are coloured by strand (a random shade of the style's palette) and
darkened with depth.

--stats prints the volume numbers of docs/hairstyles.md for each groom directory (see
volume_stats below). With several directories and --labels, each view shows every groom side by
side (view by view), for the hull-layer comparison; the "slice" view is described at VIEWS.
"""

import argparse
import io
import json
import math
import struct
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

# Base hair colours (sRGB, 0-1) per style: dark brown-black for Asian straight, light brown for
# wavy, auburn for curly, near black for African; each strand picks a random shade between the two.
PALETTES = {
    "straight": ((0.10, 0.07, 0.05), (0.28, 0.20, 0.14)),
    "wavy": ((0.45, 0.30, 0.16), (0.80, 0.62, 0.38)),
    "curly": ((0.42, 0.16, 0.07), (0.72, 0.36, 0.16)),
    "african": ((0.08, 0.05, 0.04), (0.26, 0.17, 0.12)),
    "default": ((0.30, 0.20, 0.12), (0.60, 0.42, 0.26)),
}
SKIN = np.array([0.87, 0.74, 0.62])
# View name -> (right axis, up axis, toward-viewer axis), unit vectors in world coordinates.
VIEWS = {
    "front": (np.array([-1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([0, 1.0, 0])),
    "side": (np.array([0, 1.0, 0]), np.array([0, 0, 1.0]), np.array([1.0, 0, 0])),
    "back": (np.array([1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([0, -1.0, 0])),
    "slice": (np.array([0, 1.0, 0]), np.array([0, 0, 1.0]), np.array([1.0, 0, 0])),
}
# The "slice" view is the side view of the hair within SLICE_HALF_WIDTH of the head's mid-plane
# x = head centre (the sagittal plane), over the spheres cut by that plane, coloured by the hull
# layer of each strand's master (masters.json "groom"."layers"): it shows how the layers stack.
SLICE_HALF_WIDTH = 0.01  # m
LAYER_COLOURS = np.array([(0.27, 0.45, 0.75), (0.35, 0.68, 0.40), (0.93, 0.67, 0.20),
                          (0.85, 0.25, 0.22), (0.55, 0.35, 0.70), (0.40, 0.40, 0.40)])
# "front" looks at the face (from +y): the mannequin's right (+x) is on the image's left, as in
# a photograph of a person. "side" looks from +x: the face (+y) is on the image's right.


def read_hair(path, units_per_metre=1.0):
    """Reads a Cem Yuksel .hair file (include/ringlet/hair_file.h): returns (points (P, 3) in
    metres, counts (S,) points per strand)."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise SystemExit(f"{path}: cannot open: {e.strerror}")
    if len(data) < 128 or data[:4] != b"HAIR":
        raise SystemExit(f"{path}: not a .hair file (expected the signature HAIR)")
    strands, points, flags, default_segments = struct.unpack_from("<4I", data, 4)
    if not flags & 2:
        raise SystemExit(f"{path}: header.flags: no points array")
    offset = 128
    if flags & 1:
        segments = np.frombuffer(data, dtype="<u2", count=strands, offset=offset)
        counts = segments.astype(np.int64) + 1
        offset += 2 * strands
    else:
        counts = np.full(strands, default_segments + 1, dtype=np.int64)
    if counts.sum() != points:
        raise SystemExit(f"{path}: header.point_count: {points}, segments add up to {counts.sum()}")
    if len(data) < offset + 12 * points:
        raise SystemExit(f"{path}: truncated: {len(data)} bytes, the points array needs "
                         f"{offset + 12 * points}")
    xyz = np.frombuffer(data, dtype="<f4", count=3 * points, offset=offset)
    return xyz.reshape(points, 3).astype(np.float64) / units_per_metre, counts


def read_masters(path):
    """masters.json: list of (n, 3) point arrays and the "groom" summary object."""
    try:
        with open(path) as f:
            document = json.load(f)
    except (OSError, ValueError) as e:
        raise SystemExit(f"{path}: cannot read: {e}")
    masters = [np.asarray(s["points"], dtype=np.float64) for s in document["strands"]]
    return masters, document.get("groom", {})


def read_spheres(path):
    try:
        with open(path) as f:
            body = json.load(f)
    except (OSError, ValueError) as e:
        raise SystemExit(f"{path}: cannot read: {e}")
    return [(np.asarray(s["center"], dtype=np.float64), float(s["radius"]))
            for s in body.get("spheres", [])]


def volume_stats(masters, points, centre=np.zeros(3), radius=0.1):
    """The hair's volume over the top half of the head (z above the head centre), from the master
    points and from all strand points: mean and 95th percentile of the distance from the head
    centre (m), and the mean thickness over the scalp (mean distance - head radius)."""
    out = {}
    for name, p in (("masters", np.concatenate(masters)), ("strands", points)):
        top = p[p[:, 2] > centre[2]]
        d = np.linalg.norm(top - centre, axis=1)
        out[name] = {"points": int(len(top)), "mean": float(d.mean()),
                     "p95": float(np.percentile(d, 95)), "thickness": float(d.mean() - radius)}
    return out


def sphere_image(resolution=160):
    """RGBA image of a unit sphere lit from the upper left front (Lambert + ambient)."""
    u = np.linspace(-1, 1, resolution)
    x, y = np.meshgrid(u, -u)
    r2 = x * x + y * y
    z = np.sqrt(np.clip(1.0 - r2, 0.0, 1.0))
    light = np.array([-0.45, 0.55, 0.70])
    light /= np.linalg.norm(light)
    shade = 0.35 + 0.65 * np.clip(x * light[0] + y * light[1] + z * light[2], 0.0, 1.0)
    rgba = np.zeros((resolution, resolution, 4))
    rgba[..., :3] = shade[..., None] * SKIN
    # Antialiased rim: the alpha falls from 1 to 0 over about one pixel.
    rgba[..., 3] = np.clip((1.0 - np.sqrt(r2)) * resolution / 2 + 0.5, 0.0, 1.0)
    return rgba


def strand_segments(points, counts, choice):
    """Segments (K, 2, 3) of the chosen strands and the strand index of each segment."""
    owner_of_point = np.repeat(np.arange(len(counts)), counts)
    keep = np.zeros(len(counts), dtype=bool)
    keep[choice] = True
    # A segment joins point i to i + 1 of the same strand.
    first = np.nonzero((owner_of_point[:-1] == owner_of_point[1:]) & keep[owner_of_point[:-1]])[0]
    return np.stack([points[first], points[first + 1]], axis=1), owner_of_point[first]


def draw_slice(axes, segments, colours, spheres, limits, linewidth, alpha):
    """The hair near the sagittal plane over the spheres' cross-sections (flat discs)."""
    right, up, toward = VIEWS["slice"]
    plane = spheres[0][0] @ toward if spheres else 0.0
    for c, r in spheres:
        h = abs(c @ toward - plane)
        if h < r:
            axes.add_patch(plt.Circle((c @ right, c @ up), math.sqrt(r * r - h * h), zorder=0,
                                      facecolor=SKIN * 0.9, edgecolor=SKIN * 0.6, linewidth=0.8))
    near = np.abs(segments.mean(axis=1) @ toward - plane) < SLICE_HALF_WIDTH
    xy = np.stack([segments[near] @ right, segments[near] @ up], axis=-1)
    rgba = np.concatenate([colours[near], np.full((near.sum(), 1), min(1.0, 2 * alpha))], axis=1)
    axes.add_collection(LineCollection(xy, colors=rgba, linewidths=linewidth, zorder=1))
    finish_axes(axes, limits)


def finish_axes(axes, limits):
    axes.set_xlim(*limits[0])
    axes.set_ylim(*limits[1])
    axes.set_aspect("equal")
    axes.set_xticks([])
    axes.set_yticks([])
    for side in axes.spines.values():
        side.set_visible(False)


def draw_view(axes, view, segments, colours, spheres, limits, linewidth, alpha):
    right, up, toward = VIEWS[view]
    image = sphere_image()
    # Sphere centres sorted back to front split the depth axis into intervals.
    sphere_depth = np.array([c @ toward for c, _ in spheres])
    order = np.argsort(sphere_depth)
    edges = sphere_depth[order]
    depth = segments.mean(axis=1) @ toward
    interval = np.searchsorted(edges, depth)  # 0: behind every centre
    xy = np.stack([segments @ right, segments @ up], axis=-1)
    # Back-to-front inside the drawing; darker behind: depth shading over the hair's own depth.
    lo, hi = np.percentile(depth, [2, 98])
    t = np.clip((depth - lo) / max(hi - lo, 1e-9), 0.0, 1.0)
    shaded = colours * (0.45 + 0.55 * t)[:, None]
    rgba = np.concatenate([shaded, np.full((len(shaded), 1), alpha)], axis=1)
    z = 0
    for k in range(len(edges) + 1):
        chosen = np.nonzero(interval == k)[0]
        if len(chosen):
            chosen = chosen[np.argsort(depth[chosen], kind="stable")]
            axes.add_collection(LineCollection(xy[chosen], colors=rgba[chosen],
                                               linewidths=linewidth, zorder=z,
                                               capstyle="round"))
        z += 1
        if k < len(edges):
            c, r = spheres[order[k]]
            u, v = c @ right, c @ up
            axes.imshow(image, extent=(u - r, u + r, v - r, v + r), zorder=z,
                        interpolation="bilinear")
            z += 1
    finish_axes(axes, limits)


def save_png(figure, path, dpi, colours):
    """Saves the figure; with colours > 0 as a palette PNG of that many colours (Pillow, which
    matplotlib depends on), about 3 times smaller than RGB for these images of thin lines."""
    if colours <= 0:
        figure.savefig(path, dpi=dpi)
        return
    from PIL import Image  # matplotlib's own dependency

    buffer = io.BytesIO()
    figure.savefig(buffer, dpi=dpi, format="png")
    buffer.seek(0)
    image = Image.open(buffer).convert("RGB")
    image.quantize(colors=colours, method=Image.Quantize.MEDIANCUT).save(path, optimize=True)


def choose_strands(count, wanted, seed):
    if wanted <= 0 or wanted >= count:
        return np.arange(count)
    return np.sort(np.random.default_rng(seed).choice(count, size=wanted, replace=False))


def strand_colours(owner, palette, seed):
    dark, light = (np.asarray(c) for c in PALETTES[palette])
    mix = np.random.default_rng(seed + 1).uniform(0.0, 1.0, size=owner.max() + 1)
    return dark + (light - dark) * mix[owner][:, None]


def view_limits(points, spheres, views):
    """Common axis limits of all panels (m): the hair's extent, the head and some shoulders."""
    limits = []
    for view in views:
        right, up, _ = VIEWS[view]
        u, v = points @ right, points @ up
        u_lo, u_hi = np.percentile(u, [0.05, 99.95])
        v_lo, v_hi = np.percentile(v, [0.05, 99.95])
        head_c, head_r = spheres[0] if spheres else (np.zeros(3), 0.1)
        u_lo = min(u_lo, head_c @ right - 1.6 * head_r)
        u_hi = max(u_hi, head_c @ right + 1.6 * head_r)
        v_lo = min(v_lo, head_c @ up - 1.8 * head_r)
        v_hi = max(v_hi, head_c @ up + 1.2 * head_r)
        limits.append(((u_lo - 0.01, u_hi + 0.01), (v_lo - 0.01, v_hi + 0.01)))
    # Same scale in every panel: widen every panel to the largest width and height.
    width = max(l[0][1] - l[0][0] for l in limits)
    height = max(l[1][1] - l[1][0] for l in limits)
    out = []
    for (u0, u1), (v0, v1) in limits:
        cu = (u0 + u1) / 2
        out.append(((cu - width / 2, cu + width / 2), (v1 - height, v1)))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("groom", nargs="+", help="groom output directory (1, or 2 with --labels)")
    parser.add_argument("-o", "--output", help="PNG to write (without it: only --stats)")
    parser.add_argument("--body", default="examples/bodies/mannequin.json",
                        help="body JSON with the spheres (default: the sphere mannequin)")
    parser.add_argument("--title", default="", help="figure title")
    parser.add_argument("--strands", type=int, default=8000,
                        help="strands drawn, chosen at random (0 = all; default 8000)")
    parser.add_argument("--palette", default="default", choices=sorted(PALETTES))
    parser.add_argument("--labels", nargs="*", default=None, help="one panel label per groom")
    parser.add_argument("--views", default="front,side",
                        help="comma list of front, side, back, slice (default front,side)")
    parser.add_argument("--linewidth", type=float, default=0.35, help="line width (points)")
    parser.add_argument("--alpha", type=float, default=0.45, help="line opacity")
    parser.add_argument("--units-per-metre", type=float, default=1.0,
                        help="length unit of strands.hair per metre (ringlet groom's default 1)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the strand subsample")
    parser.add_argument("--dpi", type=int, default=130)
    parser.add_argument("--colours", type=int, default=256,
                        help="palette PNG with this many colours (0 = full RGB; default 256)")
    parser.add_argument("--stats", action="store_true", help="print the volume numbers")
    args = parser.parse_args()

    views = [v for v in args.views.split(",") if v]
    for v in views:
        if v not in VIEWS:
            raise SystemExit(f"--views: unknown view {v!r} (expected front, side, back or slice)")
    spheres = read_spheres(args.body)
    labels = args.labels if args.labels else [""] * len(args.groom)
    if args.output and len(labels) != len(args.groom):
        raise SystemExit("--labels: expected one label per groom directory")

    grooms = []
    for directory in args.groom:
        points, counts = read_hair(directory + "/strands.hair", args.units_per_metre)
        masters, summary = read_masters(directory + "/masters.json")
        head_c, head_r = spheres[0] if spheres else (np.zeros(3), 0.1)
        stats = volume_stats(masters, points, head_c, head_r)
        if args.stats:
            print(json.dumps({"groom": directory, "volume_top_half": stats}))
        layers = np.asarray(summary.get("layers", [0] * len(masters)), dtype=np.int64)
        if len(counts) % max(len(layers), 1):
            raise SystemExit(f"{directory}: {len(counts)} strands are not whole wisps of "
                             f"{len(layers)} masters")
        grooms.append((points, counts, stats, layers))
    if not args.output:
        if not args.stats:
            raise SystemExit("-o/--output: expected a PNG name (or --stats alone)")
        return 0

    all_points = np.concatenate([g[0] for g in grooms])
    limits = view_limits(all_points, spheres, views)
    panels = [(g, v, label) for v, lim in zip(views, limits)
              for g, label in zip(grooms, labels)]
    width = (limits[0][0][1] - limits[0][0][0]) / (limits[0][1][1] - limits[0][1][0])
    # At least 3.3 inches per panel, so that the two title lines of a narrow view stay apart.
    figure = plt.figure(figsize=(len(panels) * max(3.4 * width, 3.3) + 0.2, 3.4 + 0.5))
    names = {"front": "front (from +y)", "side": "side (from +x)", "back": "back (from -y)",
             "slice": "mid-plane slice"}
    for k, ((points, counts, stats, layers), view, label) in enumerate(panels):
        axes = figure.add_subplot(1, len(panels), k + 1)
        lim = limits[views.index(view)]
        if view == "slice":
            # Every strand: only those near the mid-plane are drawn.
            segments, owner = strand_segments(points, counts, np.arange(len(counts)))
            per_wisp = len(counts) // len(layers)
            colours = LAYER_COLOURS[np.minimum(layers[owner // per_wisp], len(LAYER_COLOURS) - 1)]
            draw_slice(axes, segments, colours, spheres, lim, args.linewidth, args.alpha)
            for layer in range(layers.max() + 1):
                axes.plot([], [], color=LAYER_COLOURS[min(layer, len(LAYER_COLOURS) - 1)],
                          label=f"layer {layer}")
            axes.legend(loc="lower right", fontsize=6, frameon=False)
        else:
            choice = choose_strands(len(counts), args.strands, args.seed)
            segments, owner = strand_segments(points, counts, choice)
            colours = strand_colours(owner, args.palette, args.seed)
            draw_view(axes, view, segments, colours, spheres, lim, args.linewidth, args.alpha)
        text = (label + ", " if label else "") + names[view]
        if label:
            text += (f"\ntop half: {1e3 * stats['strands']['thickness']:.1f} mm over the scalp,"
                     f" r95 {1e3 * stats['strands']['p95']:.0f} mm")
        axes.set_title(text, fontsize=8)
    drawn = min(args.strands, len(grooms[0][1])) if args.strands > 0 else len(grooms[0][1])
    caption = f"{drawn:,} of {len(grooms[0][1]):,} strands drawn"
    if "slice" in views:
        caption += (f"; slice: every strand segment within {1e3 * SLICE_HALF_WIDTH:.0f} mm of "
                    "the head's mid-plane")
    figure.suptitle((args.title + "\n" if args.title else "") + caption, fontsize=9)
    figure.subplots_adjust(left=0.01, right=0.99, bottom=0.01, top=0.84 if any(labels) else 0.87,
                           wspace=0.02)
    save_png(figure, args.output, args.dpi, args.colours)
    return 0


if __name__ == "__main__":
    sys.exit(main())
