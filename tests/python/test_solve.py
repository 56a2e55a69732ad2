"""ringlet.solve and the strand types against `ringlet solve` (same input, same output bits),
plus shapes, dtypes, views, errors and an independent check of the material frames."""
import json

import numpy as np
import pytest

import ringlet
from conftest import EXAMPLES, cli_error

SCENES = [EXAMPLES / "strands.json", EXAMPLES / "vertical_curly.json"]


def reference(cli, scene, tmp_path, k):
    """The CLI's result document: numbers written as the shortest round-trip decimals, so
    json.load gives back the exact doubles (result_json.h)."""
    out = tmp_path / ("result_%d.json" % k)
    cli("solve", scene, "-o", out, "--points-per-segment", k, "--quiet", "--threads", 2,
        check=False)
    return json.loads(out.read_text())


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.name)
def test_solve_matches_the_command_bit_for_bit(cli, tmp_path, scene):
    k = 3
    document = reference(cli, scene, tmp_path, k)
    from_path = ringlet.solve(str(scene), points_per_segment=k)
    from_dict = ringlet.solve(json.loads(scene.read_text()), points_per_segment=k, threads=1)
    assert len(from_path) == len(document["strands"]) >= 1
    for results in (from_path, from_dict):
        for mine, ref in zip(results, document["strands"]):
            # Every number of the result, compared exactly (== on float64, no tolerance).
            assert np.array_equal(mine.points, np.array(ref["points"], dtype=np.float64))
            assert np.array_equal(mine.curvatures, np.array(ref["curvatures"], dtype=np.float64))
            assert np.array_equal(mine.segment_lengths, np.array(ref["segment_lengths"]))
            s = mine.summary
            assert s.termination == ref["termination"]
            assert s.message == ref["message"]
            assert s.iterations == ref["iterations"]
            assert s.residual == ref["residual"]
            assert s.gradient_norm == ref["gradient_norm"]
            assert s.stable == ref["stable"]
            assert s.min_eigenvalue == ref["min_hessian_eigenvalue"]
            assert s.evaluations == ref["evaluations"]
            assert s.hessian_evaluations == ref["hessian_evaluations"]
            assert s.stability_checked == ref["stability_checked"]
            assert s.stability_restarts == ref["stability_restarts"]
            assert s.contact.max_penetration == ref["max_penetration"]
            assert s.contact.samples_in_contact == ref["contact_samples"]
            energy = ref["energy"]
            assert (s.energy.elastic, s.energy.gravity, s.energy.contact, s.energy.total) == (
                energy["elastic"], energy["gravity"], energy["contact"], energy["total"])
            assert mine.kirchhoff_residual == ref["kirchhoff_residual"]
            assert s.converged() and mine.succeeded()


def test_result_arrays_are_read_only_views_with_documented_shapes():
    scene = ringlet.load_scene(str(EXAMPLES / "vertical_curly.json"))
    n = scene.strands[0].num_segments()
    k = 4
    (result,) = ringlet.solve(scene, points_per_segment=k)
    shapes = {"points": (n * k + 1, 3), "curvatures": (n, 3), "segment_lengths": (n,),
              "material_frames": (n * k + 1, 3, 3)}
    for name, shape in shapes.items():
        a, b = getattr(result, name), getattr(result, name)
        assert a.shape == shape and a.dtype == np.float64, name
        assert not a.flags.owndata and a.base is not None, name  # a view ...
        assert np.shares_memory(a, b), name                      # ... of the same storage
        assert not a.flags.writeable, name
        with pytest.raises(ValueError):
            a[0] = 0.0


def test_material_frames_are_rotations_tangent_to_the_centreline():
    """Independent check of the frames: orthonormal with det +1, the first is the scene's root
    frame, and the tangent column agrees with the centred difference of the points (error
    (kappa h)^2 / 6 ~ 5e-5 here: kappa < 100 1/m, h = l/64 = 0.2 m / 15 / 64)."""
    scene = ringlet.load_scene(str(EXAMPLES / "vertical_curly.json"))
    (r,) = ringlet.solve(scene, points_per_segment=64)
    q = r.material_frames
    eye = np.einsum("kji,kjl->kil", q, q)
    assert np.abs(eye - np.eye(3)).max() < 1e-12
    assert np.abs(np.linalg.det(q) - 1.0).max() < 1e-12
    assert np.array_equal(q[0], scene.strands[0].root_frame)
    p = r.points
    chord = p[2:] - p[:-2]
    chord /= np.linalg.norm(chord, axis=1)[:, None]
    # Inside segments only: at a segment end the difference straddles two helices of different
    # curvature and its error is first order (|delta kappa| h), not (kappa h)^2 / 6.
    inside = np.arange(1, len(p) - 1) % 64 != 0
    assert np.abs(chord - q[1:-1, :, 2])[inside].max() < 1e-4
    # Anti-vacuity: the curl turns the tangent a lot along the strand.
    assert np.abs(q[:, :, 2] - q[0, :, 2]).max() > 0.5


def test_strand_model_from_python_solves_like_the_scene_model(cli, tmp_path):
    scene = ringlet.load_scene(str(EXAMPLES / "vertical_curly.json"))
    m = scene.strands[0]
    mine = ringlet.StrandModel(m.segment_lengths, m.section, m.material,
                               natural_curvature=m.natural_curvature,
                               root_position=m.root_position, root_frame=m.root_frame,
                               gravity=m.gravity)
    (a,) = ringlet.solve(mine, options=scene.solver)
    (b,) = ringlet.solve(scene)
    assert np.array_equal(a.points, b.points) and np.array_equal(a.curvatures, b.curvatures)


def test_zero_gravity_gives_the_natural_helix():
    """Rest shape: without gravity the equilibrium is the natural curvature, elastic energy 0."""
    model = ringlet.StrandModel(ringlet.uniform_segments(0.2, 10),
                                ringlet.section_from_eccentricity(50e-6, 0.3),
                                natural_curvature=(50.0, 0.0, 10.0), gravity=(0, 0, 0))
    (r,) = ringlet.solve(model)
    assert np.abs(r.curvatures - np.array([50.0, 0.0, 10.0])).max() < 1e-9
    assert abs(r.summary.energy.total) < 1e-20


def test_model_vectors_are_writable_views_of_the_model():
    model = ringlet.StrandModel([0.1, 0.1], ringlet.CrossSection(6e-5, 4e-5))
    g = model.gravity
    g[2] = -1.0
    assert model.gravity[2] == -1.0 and np.shares_memory(g, model.gravity)
    assert model.root_frame.shape == (3, 3) and model.segment_lengths.shape == (2,)
    assert model.length() == pytest.approx(0.2, abs=0)


def test_bad_scene_dict_raises_the_commands_message(cli, tmp_path):
    document = json.loads((EXAMPLES / "vertical_curly.json").read_text())
    document["strands"][0]["length"] = -1
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(document))
    expected = cli_error(cli("solve", bad, "-o", tmp_path / "r.json", check=False))
    with pytest.raises(ringlet.Error) as info:
        ringlet.solve(document)
    # The command names the file first ("bad.json: strands[0].length: ..."); the dict has none.
    assert expected == "%s: %s" % (bad, info.value)
    assert str(info.value).startswith("strands[0].length")
    assert isinstance(info.value, ValueError) and isinstance(info.value, RuntimeError)
    with pytest.raises(ringlet.Error) as from_file:
        ringlet.load_scene(str(bad))
    assert str(from_file.value) == expected


@pytest.mark.parametrize("call, needle", [
    (lambda: ringlet.StrandModel([0.1, -0.1], ringlet.CrossSection(5e-5, 5e-5)), "segment"),
    (lambda: ringlet.SolveOptions(method="newtonian"), "method"),
    (lambda: ringlet.solve(EXAMPLES / "strands.json", points_per_segment=0), "points_per_segment"),
    (lambda: ringlet.parse_scene({"strands": [{"length": 0.1, "colour": 1}]}), "colour"),
    (lambda: ringlet.load_scene("/nonexistent/scene.json"), "/nonexistent/scene.json"),
])
def test_errors_name_the_field(call, needle):
    with pytest.raises(ringlet.Error) as info:
        call()
    assert needle in str(info.value) and "\n" not in str(info.value)
