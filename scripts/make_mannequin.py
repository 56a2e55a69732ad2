#!/usr/bin/env python3
"""Writes examples/bodies/mannequin.obj: the default mannequin's head, neck and torso as three
closed triangle meshes (docs/body.md). Plain Python 3, no dependencies:

    python3 scripts/make_mannequin.py [output.obj]

Conventions: metres, z up, the face looks toward +y (the mannequin's right is +x), the head's
centre at the origin. Each component is a superquadric

    (|x/a|^e + |y/b|^e)^(q/e) + |z/c|^q = 1     (x, y, z relative to the component's centre)

sampled by a subdivided icosahedron (each triangle split in four at its edge midpoints, the new
vertices pushed to the unit sphere) mapped radially onto the surface: the surface is star-shaped about its centre and the
implicit function is homogeneous of degree q, so the point in direction u is u * F(u)^(-1/q).
The radial map keeps the icosphere's outward orientation and cannot fold triangles.
Coordinates are written with 6 significant digits.
"""

import math
import sys

# name, centre (m), semi-axes (a, b, c) (m), horizontal exponent e, vertical exponent q,
# icosphere subdivision level (20 * 4^level triangles).
COMPONENTS = [
    # An ellipsoid: 16 cm wide (x), 20 cm deep (y), 20 cm high (z); top of the head at z = 0.1.
    ("head", (0.0, 0.0, 0.0), (0.08, 0.1, 0.1), 2.0, 2.0, 4),
    # A rounded cylinder of radius 5.5 cm from z = -0.22 (inside the torso) to z = -0.05
    # (inside the head).
    ("neck", (0.0, -0.01, -0.135), (0.055, 0.055, 0.085), 2.0, 8.0, 3),
    # A boxy superellipsoid 42 cm wide, 24 cm deep, top at z = -0.21 and shoulders (x = 0.15)
    # at z = -0.224, bottom at z = -0.59.
    ("torso", (0.0, -0.01, -0.40), (0.21, 0.12, 0.19), 2.5, 4.0, 4),
]


def icosphere(level):
    """Unit icosphere: vertices and counter-clockwise (outward) triangles."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
                (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
                (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    vertices = [normalize(v) for v in vertices]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
             (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
             (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
             (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        midpoint = {}

        def middle(i, j):
            key = (min(i, j), max(i, j))
            if key not in midpoint:
                a, b = vertices[i], vertices[j]
                vertices.append(normalize(((a[0] + b[0]) / 2, (a[1] + b[1]) / 2,
                                           (a[2] + b[2]) / 2)))
                midpoint[key] = len(vertices) - 1
            return midpoint[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return vertices, faces


def normalize(v):
    n = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    return (v[0] / n, v[1] / n, v[2] / n)


def superquadric_radius(u, axes, e, q):
    """Distance from the centre to the surface along the unit direction u."""
    a, b, c = axes
    horizontal = abs(u[0] / a) ** e + abs(u[1] / b) ** e
    value = horizontal ** (q / e) + abs(u[2] / c) ** q
    return value ** (-1.0 / q)


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "examples/bodies/mannequin.obj"
    lines = ["# ringlet default mannequin: head, neck, torso (scripts/make_mannequin.py).",
             "# Metres, z up, face toward +y, head centre at the origin."]
    offset = 0
    triangles = 0
    for name, centre, axes, e, q, level in COMPONENTS:
        directions, faces = icosphere(level)
        lines.append("o " + name)
        for u in directions:
            r = superquadric_radius(u, axes, e, q)
            lines.append("v %.6g %.6g %.6g" % tuple(centre[k] + r * u[k] for k in range(3)))
        for f in faces:
            lines.append("f %d %d %d" % tuple(offset + i + 1 for i in f))
        offset += len(directions)
        triangles += len(faces)
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")
    print("%s: %d vertices, %d triangles" % (path, offset, triangles))


if __name__ == "__main__":
    main()
