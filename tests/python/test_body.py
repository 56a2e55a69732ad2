"""ringlet.Body (issue 25, item 6): signed distances, gradients and Hessians against closed forms
(a sphere's |p - c| - r, an axis-aligned cube's box distance, the quadratic smooth minimum of
two spheres written out from its formula), shapes and errors, the GIL released for large
queries, pickling (bit-exact queries after a fresh parse) and bodies wherever a body is taken."""
import copy
import gc
import pickle
import threading
import time

import numpy as np
import pytest

import ringlet
from conftest import EXAMPLES

RNG = np.random.default_rng(25)


def sphere_reference(p, centre, radius):
    v = p - centre
    r = np.linalg.norm(v, axis=-1)
    return r - radius, v / r[..., None], r


def test_one_sphere_is_its_closed_form():
    centre, radius = np.array([0.01, -0.02, 0.03]), 0.1
    body = ringlet.Body({"spheres": [{"name": "head", "center": centre.tolist(),
                                      "radius": radius}]})
    p = centre + RNG.uniform(-0.3, 0.3, size=(500, 3))
    d_ref, n_ref, r = sphere_reference(p, centre, radius)
    d, g, h = body.signed_distance_hessian(p)
    assert d.shape == (500,) and g.shape == (500, 3) and h.shape == (500, 3, 3)
    assert (d < 0).any() and (d > 0).any()  # inside and outside both tested
    np.testing.assert_allclose(d, d_ref, rtol=0, atol=1e-16)
    np.testing.assert_allclose(g, n_ref, rtol=0, atol=1e-15)
    # The Hessian of |x - c|: (I - n n^T) / |x - c|.
    h_ref = (np.eye(3) - n_ref[:, :, None] * n_ref[:, None, :]) / r[:, None, None]
    np.testing.assert_allclose(h, h_ref, rtol=1e-13, atol=1e-13 * np.abs(h_ref).max())
    assert np.array_equal(body.signed_distance(p), d)
    d2, g2 = body.signed_distance_gradient(p)
    assert np.array_equal(d2, d) and np.array_equal(g2, g)


def smin(a, b, k):
    """Quilez's quadratic smooth minimum, as docs/body.md writes it."""
    h = np.clip(0.5 + (b - a) / (2 * k), 0.0, 1.0)
    return b + h * (a - b) - k * h * (1 - h)


def test_two_spheres_with_a_blend():
    c1, r1, c2, r2, k = np.array([0.0, 0, 0]), 0.1, np.array([0.0, 0.04, -0.08]), 0.055, 0.005
    body = ringlet.Body({"spheres": [{"center": c1.tolist(), "radius": r1},
                                     {"center": c2.tolist(), "radius": r2}], "blend": k})
    assert body.blend == k
    p = RNG.uniform(-0.25, 0.25, size=(4000, 3))
    d1, n1, _ = sphere_reference(p, c1, r1)
    d2, n2, _ = sphere_reference(p, c2, r2)
    d, g = body.signed_distance_gradient(p)
    # Far from the seams (the distances differ by more than k) the union is the exact minimum
    # and its gradient the nearer sphere's normal.
    far = np.abs(d1 - d2) > k
    assert far.sum() > 3000 and (~far).sum() > 10  # both regions sampled
    np.testing.assert_allclose(d[far], np.minimum(d1, d2)[far], rtol=0, atol=1e-16)
    np.testing.assert_allclose(g[far], np.where((d1 < d2)[:, None], n1, n2)[far], atol=1e-15)
    # On the seams: the smooth minimum, at most k/4 below the exact one.
    seam = ~far
    np.testing.assert_allclose(d[seam], smin(d1, d2, k)[seam], rtol=0, atol=1e-16)
    assert (d[seam] <= np.minimum(d1, d2)[seam] + 1e-16).all()
    assert (d[seam] >= np.minimum(d1, d2)[seam] - k / 4 - 1e-16).all()
    assert (np.minimum(d1, d2)[seam] - d[seam]).max() > k / 8  # the blend does act there


CUBE_OBJ = """o cube
v -H -H -H
v H -H -H
v H H -H
v -H H -H
v -H -H H
v H -H H
v H H H
v -H H H
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
"""


def cube_reference(p, half):
    q = np.abs(p) - half
    outside = np.linalg.norm(np.maximum(q, 0), axis=-1)
    inside = np.minimum(q.max(axis=-1), 0)
    return outside + inside


@pytest.fixture
def cube(tmp_path):
    half = 0.0625  # exact in float32 (OBJ vertices are read as float)
    (tmp_path / "cube.obj").write_text(CUBE_OBJ.replace("H", repr(half)))
    return tmp_path, half


def test_a_cube_mesh_exact_and_on_its_grid(cube):
    directory, half = cube
    exact = ringlet.Body({"meshes": [{"obj": "cube.obj"}], "mesh_distance": "exact"},
                         base_directory=str(directory))
    assert exact.mesh_distance == "exact"
    (mesh,) = exact.meshes
    assert mesh["name"] == "cube" and mesh["triangles"].shape == (12, 3)
    assert mesh["vertices"].shape == (8, 3)
    assert mesh["volume"] == pytest.approx((2 * half) ** 3, rel=1e-14)
    p = RNG.uniform(-0.12, 0.12, size=(3000, 3))
    d_ref = cube_reference(p, half)
    assert (d_ref < 0).sum() > 100
    np.testing.assert_allclose(exact.signed_distance(p), d_ref, rtol=0, atol=1e-16)
    # Outside, away from edges and corners (one axis outside only): the face normal.
    q = np.abs(p) - half
    face = ((q > 0).sum(axis=1) == 1)
    _, g = exact.signed_distance_gradient(p[face])
    axis = np.argmax(q[face], axis=1)
    g_ref = np.zeros_like(g)
    g_ref[np.arange(len(axis)), axis] = np.sign(p[face][np.arange(len(axis)), axis])
    np.testing.assert_allclose(g, g_ref, rtol=0, atol=1e-12)
    # The grid of the same mesh: within its spacing of the exact distance inside the band less
    # two spacings (the B-spline's Jensen bound for a 1-Lipschitz distance, docs/body.md).
    grid = ringlet.Body({"meshes": [{"obj": "cube.obj"}], "grid_spacing": 0.005,
                         "grid_band": 0.03}, base_directory=str(directory))
    assert grid.mesh_distance == "grid" and grid.grid_spacing == 0.005
    near = np.abs(d_ref) < 0.03 - 2 * 0.005
    error = np.abs(grid.signed_distance(p[near]) - d_ref[near])
    assert error.max() <= 0.005 and error.max() > 0  # a smoothing, not the exact values


def test_shapes_and_single_points():
    body = ringlet.Body({"spheres": [{"center": [0, 0, 0], "radius": 0.1}]})
    assert isinstance(body.signed_distance([0, 0, 0.3]), float)
    assert body.signed_distance([0, 0, 0.3]) == pytest.approx(0.2, abs=1e-16)
    d, g = body.signed_distance_gradient(np.zeros((2, 4, 3)) + [0, 0.2, 0])
    assert d.shape == (2, 4) and g.shape == (2, 4, 3)
    assert body.signed_distance(np.zeros((0, 3))).shape == (0,)
    assert body.signed_distance(np.array([[0, 0, 1]], dtype=np.int32))[0] == pytest.approx(0.9)
    np.testing.assert_array_equal(body.bounds, [[-0.1] * 3, [0.1] * 3])


@pytest.mark.parametrize("points, message", [
    (np.zeros((4, 2)), "points: expected an array of shape (..., 3) (m), got shape (4, 2)"),
    ([[0, 0, np.nan]], "points: expected finite coordinates (m), got nan in point 0"),
    ([[0, 0, 0], [0, np.inf, 0]], "got inf in point 1"),
    (np.ones((2, 3), dtype=bool), "points: expected an array of shape (..., 3) (m), got an "
                                  "array of dtype bool"),
    ([["a", "b", "c"]], "got an array of dtype <U1"),
])
def test_bad_points_name_the_argument(points, message):
    body = ringlet.Body({"spheres": [{"center": [0, 0, 0], "radius": 0.1}]})
    with pytest.raises(ringlet.Error) as error:
        body.signed_distance(points)
    assert message in str(error.value)


@pytest.mark.parametrize("source, message", [
    ({"spheres": [{"center": [0, 0, 0], "radius": -0.1}]}, "body.spheres[0].radius: expected"),
    ({"spheres": []}, "body"),
    ({"cubes": []}, "body"),
    (3, "body: expected a ringlet.Body, a body file path or a body dict"),
    ("/nonexistent/body.json", "body: /nonexistent/body.json: cannot"),
])
def test_bad_bodies_name_the_field(source, message):
    with pytest.raises(ringlet.Error) as error:
        ringlet.Body(source)
    assert message in str(error.value)


def test_file_bodies_and_reprs():
    body = ringlet.Body(str(EXAMPLES / "bodies" / "mannequin.json"))
    assert [s["name"] for s in body.spheres][:2] == ["head", "jaw"]
    assert body.spheres[0]["radius"] == 0.1
    # Head and jaw turn with the head; neck, chest, shoulders, arms and back stay (body.md).
    assert [s["moves_with"] for s in body.spheres] == ["head", "head"] + ["torso"] * 7
    assert body.base_directory == str((EXAMPLES / "bodies").resolve())
    assert body.document()["spheres"][0]["name"] == "head"
    text = repr(body)
    assert text.startswith("Body(spheres=[Sphere(name='head', center=(0.0, 0.0, 0.0), "
                           "radius=0.1), Sphere(name='jaw'")
    assert "... (9 spheres)" in text and "blend=0.005" in text and "meshes=[]" in text
    assert copy.copy(body) is body and copy.deepcopy(body) is body


def test_mesh_repr(cube):
    directory, _ = cube
    body = ringlet.Body({"meshes": [{"obj": "cube.obj"}], "mesh_distance": "exact"},
                        base_directory=str(directory))
    assert repr(body) == ("Body(spheres=[], meshes=[Mesh(name='cube', vertices=8, "
                          "triangles=12, volume=0.001953125)], blend=0.005, "
                          "mesh_distance='exact')")


def test_pickles_give_the_same_queries_bit_for_bit(cube):
    directory, _ = cube
    p = RNG.uniform(-0.15, 0.15, size=(2000, 3))
    sources = [({"spheres": [{"center": [0.1 / 3, 0, 0], "radius": 0.1},
                             {"center": [0, 0.07, 0], "radius": 0.05}]}, "."),
               ({"meshes": [{"obj": "cube.obj"}], "grid_spacing": 0.004}, str(directory)),
               (str(EXAMPLES / "bodies" / "mannequin.json"), ".")]
    for source, base in sources:
        body = ringlet.Body(source, base_directory=base)
        reference = [a.copy() for a in body.signed_distance_hessian(p)]
        for protocol in range(2, pickle.HIGHEST_PROTOCOL + 1):
            data = pickle.dumps(body, protocol=protocol)
            del body
            gc.collect()  # the unpickled body is parsed again, not the one in memory
            body = pickle.loads(data)
            for a, b in zip(reference, body.signed_distance_hessian(p)):
                assert a.tobytes() == b.tobytes()


def test_large_queries_release_the_gil(cube):
    directory, _ = cube
    body = ringlet.Body({"meshes": [{"obj": "cube.obj"}], "mesh_distance": "exact"},
                        base_directory=str(directory))
    p = RNG.uniform(-0.2, 0.2, size=(400000, 3))
    window = []
    done = threading.Event()

    def query():
        start = time.perf_counter()
        body.signed_distance(p)
        window.extend([start, time.perf_counter()])
        done.set()
    worker = threading.Thread(target=query)
    stamps = []
    worker.start()
    while not done.is_set():
        stamps.append(time.perf_counter())  # only while the GIL is free during the query
        time.sleep(0.001)
    worker.join()
    start, end = window
    during = sum(start < t < end for t in stamps)
    assert end - start > 0.03, end - start  # long enough to tell
    assert during > 10, (during, end - start)


def test_bodies_are_taken_wherever_a_body_is(tmp_path):
    path = EXAMPLES / "bodies" / "mannequin.json"
    body = ringlet.Body(str(path))
    curves = ringlet.HairCurves([[0.0, 0.0, 0.12], [0.0, 0.02, 0.2]], [2], [1e-3, 1e-3])
    settings = dict(width=24, height=16, samples_per_pixel=1, threads=1)
    by_path = ringlet.render(curves, body=str(path), **settings)
    assert np.array_equal(ringlet.render(curves, body=body, **settings), by_path)
    assert np.array_equal(ringlet.render(curves, body=body.document(), **settings), by_path)
    assert not np.array_equal(ringlet.render(curves, **settings), by_path)  # the body shows
    # invert: a strand lying on a ball, with the ball as a Body and as a dict.
    ball = {"spheres": [{"center": [0.0, 0.0, 0.0], "radius": 0.05}]}
    s = np.linspace(0, 0.6, 12)
    target = [np.stack([0.0506 * np.sin(s), np.zeros_like(s), 0.0506 * np.cos(s)], axis=1)]
    a = ringlet.invert(target, body=ringlet.Body(ball), segments=3)
    b = ringlet.invert(target, body=ball, segments=3)
    for x, y in zip(a["models"], b["models"]):
        assert np.array_equal(x.rest_curvatures, y.rest_curvatures)


def test_a_hairstyles_body(small_style):
    path, style = small_style
    hairstyle = ringlet.load_hairstyle(str(path))
    body = hairstyle.body
    p = RNG.uniform(-0.3, 0.3, size=(1000, 3))
    by_file = ringlet.Body(style["body"])  # the same file: the same body, shared while alive
    assert by_file is body or np.array_equal(by_file.signed_distance(p), body.signed_distance(p))
    assert body.spheres[0]["name"] == "head" and len(body.spheres) == 9
    reference = body.signed_distance(p)
    data = pickle.dumps(body)
    del body, by_file
    gc.collect()
    assert pickle.loads(data).signed_distance(p).tobytes() == reference.tobytes()
    # An inline body.
    style["body"] = {"spheres": [{"center": [0, 0, 0], "radius": 0.1}], "blend": 0}
    inline = ringlet.parse_hairstyle(style).body
    assert inline.blend == 0 and inline.signed_distance([0, 0, 0.25]) == pytest.approx(0.15)
    assert ringlet.groom(style).hairstyle.body.document() == style["body"]
