"""Content checks of the studio's screenshots (tests/studio_screenshot_test.sh).

A minimal PNG reader (8-bit RGB/RGBA, non-interlaced: what ringlet's WritePng writes), then:
hair-coloured pixels where the hair is, cyan (brushed) curls after the brushed curl, fewer cyan
pixels and as many others after the brushed wet and cut, the cut plane gizmo in the view, fewer
hair pixels in the lower part of the hair after the plane cut, the ImGui panel on the left, the
render panel's window and its PNG (hair-coloured, not uniform), and the exported files (counts
read back: 300 wisps of 10 strands of 24 points).
"""
import struct
import sys
import zlib

import numpy as np

PANEL = 450  # the panel's width (pixels: studio/main.cpp kPanelEm = 30 em of the 15 px font)


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


def read_ppm(path):
    """A binary PPM (P6, 8 bits): the studio's screenshots in the test (fast to read)."""
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval, separated by whitespace
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    assert fields[0] == b"P6" and fields[3] == b"255", path
    width, height = int(fields[1]), int(fields[2])
    pixels = np.frombuffer(data[pos + 1:pos + 1 + width * height * 3], np.uint8)
    assert pixels.size == width * height * 3, path
    return pixels.reshape(height, width, 3).astype(np.int32)


def hair_mask(image):
    """Blonde fibres (small.json's melanins, drawn in the path tracer's colour of that hair):
    green close to red (g/r > 0.81; the skin has g/r ~ 0.77), blue below red (the background
    is bluish)."""
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    mask = (r > 40) & (g > 0.81 * r) & (g <= r) & (b < 0.85 * r)
    mask[:, :PANEL] = False
    return mask


def cyan_mask(image):
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    mask = (g > r + 60) & (b > r + 60)
    mask[:, :PANEL] = False
    return mask


def orange_mask(image):
    """The cut gizmo's lines (1, 0.55, 0.2) and fill (1, 0.35, 0.2)."""
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    mask = (r > 200) & (g > 60) & (g < 190) & (b < 110)
    mask[:, :PANEL] = False
    return mask


def check_exports(directory):
    # 300 masters x 10 strands of 24 points, some clipped by the session's cut (a cut ends every
    # strand where it leaves the kept region): the same strands and points in every format.
    strands, max_points = 300 * 10, 300 * 10 * 24
    data = open(f"{directory}/styled.hair", "rb").read()
    assert data[:4] == b"HAIR", "styled.hair: no HAIR signature"
    n_strands, n_points = struct.unpack("<II", data[4:12])
    print(f"styled.hair: {n_strands} strands, {n_points} points")
    assert n_strands == strands and max_points // 2 < n_points <= max_points
    obj = open(f"{directory}/styled.obj").read().splitlines()
    v = sum(1 for line in obj if line.startswith("v "))
    lines = sum(1 for line in obj if line.startswith("l "))
    print(f"styled.obj: {v} vertices, {lines} segments")
    assert (v, lines) == (n_points, n_points - strands)  # 2-vertex segments, one per edge
    usda = open(f"{directory}/styled.usda").read()
    assert usda.startswith("#usda 1.0") and "BasisCurves" in usda, "styled.usda: not a USD curves file"
    counts = usda[usda.index("curveVertexCounts"):].split("[", 1)[1].split("]", 1)[0].split(",")
    print(f"styled.usda: {len(counts)} curves")
    assert len(counts) == strands and all(2 <= int(c) <= 24 for c in counts)
    assert sum(int(c) for c in counts) == n_points


def main(directory):
    images = {name: read_ppm(f"{directory}/{name}.ppm")
              for name in ("before", "curl", "brushed_cut", "gizmo", "cut", "wet_orbit", "render_panel")}
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
    # The brushed wet and cut: fewer brushed (cyan) pixels, the other hair kept.
    brushed_cut = images["brushed_cut"]
    cyan_after = cyan_mask(brushed_cut).sum()
    others_before, others_after = hair_mask(images["curl"]).sum(), hair_mask(brushed_cut).sum()
    print(f"brushed wet + cut: cyan {curl_cyan} -> {cyan_after}, other hair {others_before} -> {others_after}")
    assert cyan_after < 0.8 * curl_cyan, "the brushed cut should shorten the brushed masters"
    assert others_after > 0.85 * others_before, "the brushed cut should keep the other hair"
    # The cut plane gizmo: orange in the view, not before.
    gizmo = orange_mask(images["gizmo"]).sum()
    print(f"gizmo: {gizmo} plane pixels (before: {orange_mask(images['before']).sum()})")
    assert gizmo > 500 and orange_mask(images["before"]).sum() < 50, "the cut plane is not shown"
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
    # The render panel: a dark ImGui window over the view, and the rendered PNG shows hair.
    window = images["render_panel"][20:400, PANEL + 20:PANEL + 400]
    dark = (window.max(axis=2) < 30).mean()
    print(f"render panel: {dark:.2f} of its window dark")
    render = read_png(f"{directory}/render.png")
    # Something (hair, body) in front of the environment: pixels far from the top-left corner's.
    background = render[0, 0]
    subject = (np.abs(render - background).max(axis=2) > 30).mean()
    print(f"render.png: {render.shape[1]} x {render.shape[0]}, {subject:.2f} not background, "
          f"std {render.std():.1f}")
    assert render.shape[1] == 96 and render.std() > 5, "the render is empty or uniform"
    assert 0.05 < subject < 0.9, "nothing rendered in front of the environment"
    assert dark > 0.05, "the render panel's window is missing"
    check_exports(directory)
    print("screenshots: ok")


if __name__ == "__main__":
    main(sys.argv[1])
