#!/usr/bin/python3
"""Puts rendered PNG images side by side, each with a caption, into one PNG.

    combine_images.py -o OUT.png IMAGE1.png "caption 1" IMAGE2.png "caption 2" ...

Used by scripts/make_render_gallery.sh. Needs Debian's /usr/bin/python3 with matplotlib.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", required=True, help="output PNG")
    parser.add_argument("pairs", nargs="+", help="IMAGE CAPTION IMAGE CAPTION ...")
    args = parser.parse_args()
    if len(args.pairs) % 2 != 0:
        sys.exit("combine_images.py: expected IMAGE CAPTION pairs")
    pairs = list(zip(args.pairs[0::2], args.pairs[1::2]))
    images = [mpimg.imread(path) for path, _ in pairs]
    height, width = images[0].shape[:2]
    dpi = 100
    fig, axes = plt.subplots(1, len(pairs), figsize=(len(pairs) * width / dpi,
                                                      height / dpi + 0.35), dpi=dpi)
    if len(pairs) == 1:
        axes = [axes]
    for ax, image, (_, caption) in zip(axes, images, pairs):
        ax.imshow(image, interpolation="nearest")
        ax.set_title(caption, fontsize=9)
        ax.axis("off")
    fig.subplots_adjust(left=0, right=1, bottom=0, top=1 - 0.35 / (height / dpi + 0.35),
                        wspace=0.01)
    fig.savefig(args.output, dpi=dpi)


if __name__ == "__main__":
    main()
