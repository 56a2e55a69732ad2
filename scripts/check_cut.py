#!/usr/bin/python3
"""Counts, in a .hair file, the points of strands rooted at or above a height z that lie below
it, and the lowest such point: the check of issue 15 ("a cut cuts every strand"), made from the
written curves alone (docs/file-formats.md: 128-byte header, optional uint16 segment counts,
float32 points).

    /usr/bin/python3 scripts/check_cut.py strands.hair [Z]

Without Z, prints the median tip height (the cut height of the issue's test)."""
import struct
import sys

import numpy as np


def read_hair(path):
    data = open(path, "rb").read()
    strands, count, bits, default_segments = struct.unpack("<IIII", data[4:20])
    at = 128
    if bits & 1:
        segments = np.frombuffer(data, "<u2", strands, at).astype(np.int64)
        at += 2 * strands
    else:
        segments = np.full(strands, default_segments, np.int64)
    points = np.frombuffer(data, "<f4", 3 * count, at).reshape(count, 3).astype(np.float64)
    counts = segments + 1
    if counts.sum() != count:
        raise SystemExit(f"{path}: segment counts add up to {counts.sum()} points, not {count}")
    return counts, points


def main():
    counts, points = read_hair(sys.argv[1])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    tips = points[starts + counts - 1, 2]
    if len(sys.argv) < 3:
        print("median tip height %.6f m" % np.median(tips))
        return
    z = float(sys.argv[2])
    rooted_above = points[starts, 2] >= z
    strand_of = np.repeat(np.arange(len(counts)), counts)
    below = (points[:, 2] < z) & rooted_above[strand_of]
    lowest = points[below, 2].min() if below.any() else z
    print("%d strands rooted above z = %.6f m; %d of their points below it, the lowest %.3g mm "
          "below" % (rooted_above.sum(), z, below.sum(), (z - lowest) * 1e3))


if __name__ == "__main__":
    main()
