"""Content checks of the studio's screenshots (tests/studio_screenshot_test.sh).

A minimal PNG reader (8-bit RGB/RGBA, non-interlaced: what ringlet's WritePng writes), then:
hair-coloured pixels where the hair is, cyan (brushed) curls after the brushed curl, fewer hair
pixels in the lower part of the hair after the cut, and the ImGui panel on the left.
"""
import struct
import sys
import zlib

import numpy as np

PANEL = 360  # the panel's width (pixels)


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, width, height, channels = 8, b"", 0, 0, 3
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and interlace == 0 and colour in (2, 6), path
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    out = np.zeros((height, stride), dtype=np.int32)
    previous = np.zeros(stride, dtype=np.int32)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = np.frombuffer(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)], np.uint8).astype(np.int32)
        cur = np.zeros(stride, dtype=np.int32)
        for x in range(stride):
            a = cur[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            if f == 0:
                p = 0
            elif f == 1:
                p = a
            elif f == 2:
                p = b
            elif f == 3:
                p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            cur[x] = (line[x] + p) & 255
        out[y] = cur
        previous = cur
    return out.reshape(height, width, channels)[:, :, :3]


def hair_mask(image):
    """Brown-orange fibres: red dominant, blue well below red (the skin is paler, b/r ~ 0.8)."""
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    mask = (r > 30) & (b < 0.62 * r) & (g < 0.85 * r)
    mask[:, :PANEL] = False
    return mask


def cyan_mask(image):
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    mask = (g > r + 60) & (b > r + 60)
    mask[:, :PANEL] = False
    return mask


def main(directory):
    images = {name: read_png(f"{directory}/{name}.png") for name in ("before", "curl", "cut", "wet_orbit")}
    before = hair_mask(images["before"])
    rows = np.nonzero(before.any(axis=1))[0]
    print(f"before: {before.sum()} hair pixels, rows {rows.min()}..{rows.max()}")
    assert before.sum() > 3000, "too few hair pixels before styling"
    # The hair is in the view, around the head, not everywhere.
    assert before.sum() < 0.5 * before[:, PANEL:].size, "hair everywhere?"
    assert cyan_mask(images["before"]).sum() == 0, "brushed colour before the brush"
    curl_cyan = cyan_mask(images["curl"]).sum()
    print(f"curl: {curl_cyan} brushed (cyan) pixels")
    assert curl_cyan > 200, "the brushed, curled masters are not highlighted"
    # The cut: hair below the lower third of the uncut hair's height mostly gone.
    low = rows.min() + 2 * (rows.max() - rows.min()) // 3
    cut = hair_mask(images["cut"]) | cyan_mask(images["cut"])
    uncut = before | cyan_mask(images["before"])
    print(f"cut: {uncut[low:].sum()} -> {cut[low:].sum()} hair pixels below row {low}")
    assert cut[low:].sum() < 0.5 * uncut[low:].sum(), "a cut should remove the low hair"
    assert cut[:low].sum() > 0.3 * uncut[:low].sum(), "a cut should keep the upper hair"
    wet = hair_mask(images["wet_orbit"]).sum()
    print(f"wet, orbited: {wet} hair pixels")
    assert wet > 1000, "no hair after wetting"
    # The panel: text (bright pixels) and widgets on the left, unlike the plain background.
    panel = images["before"][:, :PANEL]
    bright = (panel.min(axis=2) > 180).sum()
    print(f"panel: {bright} bright pixels")
    assert bright > 2000, "the panel is missing"
    print("screenshots: ok")


if __name__ == "__main__":
    main(sys.argv[1])
