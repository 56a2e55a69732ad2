#!/usr/bin/python3
"""Writes examples/bodies/head.obj: a head and shoulders with a face, sculpted as a signed
distance model and meshed by marching cubes (docs/body.md, "The head"). Run with Debian's Python
(numpy and python3-skimage):

    /usr/bin/python3 scripts/make_head.py [output.obj]

Conventions as the mannequin's: metres, z up, the face looks toward +y (the person's right is
+x), the cranium's centre at the origin. Two closed meshes, so that the face gets a fine grid
and the torso a coarse one:

  "head"   cranium, face (brow, eye sockets with eyes, nose, cheeks, lips, jaw, chin), ears and
           the neck down into the torso; marching cubes on a 3.5 mm grid;
  "torso"  the neck's lower part, shoulders, chest, back and upper arms, cut flat at z = -0.55 m;
           on a 9 mm grid.

The model: each part is a primitive with a signed distance (sphere, capsule, round cone,
ellipsoid), combined by smooth unions and smooth subtractions with the polynomial smooth minimum
of Quilez ("Smooth minimum", 2013): smin(a, b, k) = b + h (a - b) - k h (1 - h),
h = clamp(1/2 + (b - a) / (2 k), 0, 1). The ellipsoid distance is Quilez's bound
k0 (k0 - 1) / k1 (k0 = |p / r|, k1 = |p / r^2|): exact on the surface, which is all marching
cubes needs. skimage.measure.marching_cubes (Lewiner et al. 2003, topologically consistent)
meshes the zero level set; the grid is padded so that every surface is closed. Each mesh is
checked before it is written: every edge shared by exactly two triangles, each in opposite
directions (a consistently oriented closed 2-manifold), outward orientation (positive enclosed
volume), no zero-area triangle. Coordinates are written with 7 significant digits; the output is
the same on every run (no randomness).
"""

import math
import sys

import numpy as np
from skimage import measure


# --- signed distances of primitives (p: array (..., 3), metres) ------------------------------

def sphere(p, c, r):
    return np.linalg.norm(p - np.asarray(c), axis=-1) - r


def ellipsoid(p, c, radii, rotation=None):
    q = p - np.asarray(c)
    if rotation is not None:
        q = q @ np.asarray(rotation)  # rows of q times R: R^T applied to each point
    r = np.asarray(radii)
    k0 = np.linalg.norm(q / r, axis=-1)
    k1 = np.linalg.norm(q / (r * r), axis=-1)
    return k0 * (k0 - 1.0) / np.maximum(k1, 1e-12)


def round_cone(p, a, b, ra, rb):
    """Distance to the convex hull of two spheres (a, ra) and (b, rb), approximated by the capsule
    with the radius interpolated along the axis (exact for ra = rb)."""
    a = np.asarray(a)
    b = np.asarray(b)
    ab = b - a
    t = np.clip(((p - a) @ ab) / (ab @ ab), 0.0, 1.0)
    closest = a + t[..., None] * ab
    return np.linalg.norm(p - closest, axis=-1) - (ra + (rb - ra) * t)


def capsule(p, a, b, r):
    return round_cone(p, a, b, r, r)


def smin(a, b, k):
    h = np.clip(0.5 + (b - a) / (2.0 * k), 0.0, 1.0)
    return b + h * (a - b) - k * h * (1.0 - h)


def smax(a, b, k):
    return -smin(-a, -b, k)


def rotation_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def mirror(fn, p):
    """A part given for the person's right (x > 0), mirrored to the left: min over both."""
    q = p.copy()
    q[..., 0] = np.abs(q[..., 0])
    return fn(q)


# --- the sculpture -----------------------------------------------------------------------------

def neck(p):
    return round_cone(p, (0.0, -0.012, -0.05), (0.0, -0.025, -0.24), 0.052, 0.058)


def head(p):
    # Cranium: 15 cm wide, 19.4 cm deep, crown at z = 0.097 m, the back of the skull rounder.
    d = ellipsoid(p, (0.0, -0.004, 0.0), (0.075, 0.097, 0.095))
    d = smin(d, ellipsoid(p, (0.0, -0.03, 0.01), (0.072, 0.075, 0.085)), 0.02)
    # Face: the midface and the lower face, narrower than the cranium, forward of it.
    d = smin(d, ellipsoid(p, (0.0, 0.042, -0.04), (0.058, 0.05, 0.062)), 0.03)
    # Jaw: from the angles below the ears to the chin.
    jaw = mirror(lambda q: capsule(q, (0.05, 0.0, -0.06), (0.018, 0.068, -0.104), 0.015), p)
    d = smin(d, jaw, 0.035)
    d = smin(d, ellipsoid(p, (0.0, 0.074, -0.106), (0.02, 0.014, 0.016)), 0.02)  # chin
    # Cheekbones.
    d = smin(d, mirror(lambda q: sphere(q, (0.04, 0.068, -0.022), 0.022), p), 0.02)
    # Brow ridge.
    d = smin(d, capsule(p, (-0.04, 0.082, 0.021), (0.04, 0.082, 0.021), 0.009), 0.025)
    # Eye sockets, cut below the brow, and the eyes in them.
    socket = mirror(lambda q: ellipsoid(q, (0.032, 0.103, 0.004), (0.019, 0.016, 0.014)), p)
    d = smax(d, -socket, 0.008)
    d = smin(d, mirror(lambda q: sphere(q, (0.032, 0.078, 0.004), 0.0125), p), 0.004)
    # Nose: bridge to tip, the tip and the wings.
    d = smin(d, round_cone(p, (0.0, 0.09, 0.008), (0.0, 0.112, -0.03), 0.007, 0.009), 0.012)
    d = smin(d, sphere(p, (0.0, 0.111, -0.033), 0.01), 0.006)
    d = smin(d, mirror(lambda q: sphere(q, (0.012, 0.098, -0.036), 0.007), p), 0.01)
    # Lips, and the line of the mouth between them.
    d = smin(d, ellipsoid(p, (0.0, 0.088, -0.06), (0.02, 0.008, 0.006)), 0.01)
    d = smin(d, ellipsoid(p, (0.0, 0.086, -0.072), (0.018, 0.008, 0.007)), 0.01)
    d = smax(d, -ellipsoid(p, (0.0, 0.097, -0.066), (0.017, 0.006, 0.001)), 0.002)
    # Ears: a flattened ellipsoid leaning back 10 degrees, its bowl hollowed on the outer side.
    lean = rotation_z(0.0)

    def ear(q):
        shell = ellipsoid(q, (0.074, -0.012, -0.012), (0.009, 0.019, 0.031), lean)
        bowl = ellipsoid(q, (0.083, -0.008, -0.012), (0.005, 0.012, 0.022), lean)
        return smax(shell, -bowl, 0.003)

    d = smin(d, mirror(ear, p), 0.006)
    return smin(d, neck(p), 0.02)


def torso(p):
    d = neck(p)
    # Trapezius: from the neck down to the shoulders.
    d = smin(d, mirror(lambda q: round_cone(q, (0.03, -0.03, -0.19), (0.15, -0.025, -0.245),
                                            0.04, 0.05), p), 0.04)
    # Chest and back: a broad ellipsoid, and a lower one to the waist.
    d = smin(d, ellipsoid(p, (0.0, -0.02, -0.33), (0.16, 0.1, 0.12)), 0.05)
    d = smin(d, ellipsoid(p, (0.0, -0.02, -0.48), (0.15, 0.095, 0.16)), 0.05)
    # Shoulders and upper arms.
    d = smin(d, mirror(lambda q: sphere(q, (0.165, -0.025, -0.27), 0.05), p), 0.03)
    d = smin(d, mirror(lambda q: round_cone(q, (0.175, -0.025, -0.29), (0.195, -0.02, -0.5),
                                            0.045, 0.038), p), 0.02)
    # Cut flat at the waist.
    return smax(d, -(p[..., 2] + 0.55), 0.005)


# --- meshing and checks ------------------------------------------------------------------------

def mesh(fn, lower, upper, spacing):
    """Marching cubes of fn's zero set over the box [lower, upper] (m) at the spacing (m), with
    a padding of 2 cells of 'outside' so that the surface is closed."""
    lower = np.asarray(lower, dtype=float)
    upper = np.asarray(upper, dtype=float)
    counts = np.ceil((upper - lower) / spacing).astype(int) + 1
    axes = [lower[i] + spacing * np.arange(counts[i]) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    values = fn(grid)
    # Everything outside the box is outside the body.
    values[0, :, :] = values[-1, :, :] = np.maximum(values[0, :, :], spacing)
    values[:, 0, :] = values[:, -1, :] = np.maximum(values[:, 0, :], spacing)
    values[:, :, 0] = values[:, :, -1] = np.maximum(values[:, :, 0], spacing)
    vertices, faces, _, _ = measure.marching_cubes(values, 0.0, spacing=(spacing,) * 3)
    vertices = vertices + lower
    return vertices, faces


def clean(vertices, faces):
    """Rounds to the written precision, merges equal vertices, drops zero-area triangles."""
    vertices = np.array([[float("%.7g" % x) for x in v] for v in vertices])
    unique, inverse = np.unique(vertices, axis=0, return_inverse=True)
    faces = inverse.reshape(-1)[faces]
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    faces = faces[keep]
    a, b, c = (unique[faces[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    faces = faces[area > 0.0]
    used = np.unique(faces)
    remap = -np.ones(len(unique), dtype=int)
    remap[used] = np.arange(len(used))
    return unique[used], remap[faces]


def check_closed(name, vertices, faces):
    """Every directed edge once, and its reverse once: a closed, consistently oriented
    2-manifold. Returns the enclosed volume (m^3), which must be positive (outward normals)."""
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    keys = directed[:, 0].astype(np.int64) * len(vertices) + directed[:, 1]
    reverse = directed[:, 1].astype(np.int64) * len(vertices) + directed[:, 0]
    if len(np.unique(keys)) != len(keys):
        raise SystemExit(f"{name}: an edge is used twice in the same direction")
    if not np.array_equal(np.sort(keys), np.sort(reverse)):
        raise SystemExit(f"{name}: an edge is not shared by exactly two triangles")
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    if not volume > 0.0:
        raise SystemExit(f"{name}: the enclosed volume {volume} is not positive")
    # Euler characteristic V - E + F = 2 for a sphere-like closed surface.
    euler = len(vertices) - len(keys) // 2 + len(faces)
    return volume, euler


def build():
    parts = [
        ("head", head, (-0.1, -0.125, -0.2), (0.1, 0.14, 0.115), 0.0035),
        ("torso", torso, (-0.26, -0.15, -0.56), (0.26, 0.11, -0.1), 0.009),
    ]
    out = []
    for name, fn, lower, upper, spacing in parts:
        vertices, faces = mesh(fn, lower, upper, spacing)
        vertices, faces = clean(vertices, faces)
        a, b, c = (vertices[faces[:, i]] for i in range(3))
        if np.einsum("ij,ij->i", a, np.cross(b, c)).sum() < 0.0:
            faces = faces[:, [0, 2, 1]]
        volume, euler = check_closed(name, vertices, faces)
        out.append((name, vertices, faces, volume, euler))
    return out


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "examples/bodies/head.obj"
    parts = build()
    lines = ["# ringlet head and shoulders: a sculpted signed-distance model meshed by marching",
             "# cubes (scripts/make_head.py). Metres, z up, face toward +y, cranium centre at the",
             "# origin. Two closed meshes: head (with face, ears, neck), torso (shoulders, arms)."]
    offset = 1
    for name, vertices, faces, volume, euler in parts:
        lines.append(f"o {name}")
        lines.extend("v %.7g %.7g %.7g" % tuple(v) for v in vertices)
        lines.extend("f %d %d %d" % tuple(f + offset) for f in faces)
        offset += len(vertices)
        print(f"{name}: {len(vertices)} vertices, {len(faces)} triangles, volume "
              f"{volume * 1e3:.3f} L, Euler characteristic {euler}", file=sys.stderr)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
