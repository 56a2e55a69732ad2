#!/usr/bin/python3
"""A contact sheet of a `ringlet batch` dataset (docs/batch.md): for some items, one view's
path-traced picture, hair mask, orientation map and depth, one column per item.

    scripts/batch_contact_sheet.py OUTDIR -o SHEET.png [--items 0,1,2,...] [--view 0]

Made docs/images/batch_contact_sheet.png from examples/batch/dataset.json. Needs python3-pil
and python3-numpy (depth: near = light, far = dark, nothing = black).
"""
import argparse
import json
import os

import numpy as np
from PIL import Image, ImageDraw


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outdir", help="the dataset's directory")
    parser.add_argument("-o", "--output", required=True, help="the sheet (PNG)")
    parser.add_argument("--items", default="0,1,2,3,4,5,6,7", help="item indices, comma-separated")
    parser.add_argument("--view", type=int, default=0, help="the view shown")
    args = parser.parse_args()
    items = [int(k) for k in args.items.split(",")]
    rows = ["rgb", "mask", "orientation", "depth"]
    tiles = []
    for k in items:
        d = os.path.join(args.outdir, "item-%09d" % k)
        meta = json.load(open(os.path.join(d, "metadata.json")))
        column = []
        for row in rows[:3]:
            png = os.path.join(d, "%s_%02d.png" % (row, args.view))
            column.append(Image.open(png).convert("RGB"))
        depth = np.load(os.path.join(d, "depth_%02d.npy" % args.view))
        hit = depth > 0
        grey = np.zeros(depth.shape, np.uint8)
        if hit.any():
            near, far = depth[hit].min(), depth[hit].max()
            grey[hit] = np.round(255 - 200 * (depth[hit] - near) / max(far - near, 1e-9))
        column.append(Image.fromarray(grey).convert("RGB"))
        label = "%d %s" % (k, os.path.basename(meta["parameters"]["base_name"]).split("_")[0])
        tiles.append((label, column))
    w, h = tiles[0][1][0].size
    top, left, gap = 16, 76, 2
    sheet = Image.new("RGB", (left + len(tiles) * (w + gap), top + len(rows) * (h + gap)),
                      (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for r, name in enumerate(rows):
        draw.text((4, top + r * (h + gap) + h // 2 - 6), name, fill=(0, 0, 0))
    for c, (label, column) in enumerate(tiles):
        x = left + c * (w + gap)
        draw.text((x + 2, 2), label, fill=(0, 0, 0))
        for r, tile in enumerate(column):
            sheet.paste(tile, (x, top + r * (h + gap)))
    sheet.save(args.output, optimize=True)


if __name__ == "__main__":
    main()
