"""ringlet.invert and StrandModel.rest_curvatures (issue 25, item 6) against `ringlet invert`
(same target file, same bits) and against the forward solve (an independent check: the
inverted rest shapes, solved by ringlet.solve, must come back to the targets); errors, progress
reports and scene bodies."""
import json

import numpy as np
import pytest

import ringlet
from conftest import EXAMPLES


@pytest.fixture(scope="module")
def dense_target(cli, tmp_path_factory):
    """The equilibria of the 5 example strands written with 25 points per helical segment (376
    to 1,001 points per strand, float32 .hair), as tests/cli_invert_formats_test.sh makes them."""
    work = tmp_path_factory.mktemp("invert")
    cli("solve", EXAMPLES / "strands.json", "-o", work / "targets.json", "--quiet")
    cli("invert", work / "targets.json", "-o", work / "dense", "--points-per-segment", 25, "-q")
    return work / "dense" / "equilibrium.hair"


def test_invert_matches_the_command_bit_for_bit(cli, tmp_path, dense_target):
    cli("invert", dense_target, "-o", tmp_path / "out", "--segments", 15, "-q", "--threads", 2)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    rest = json.loads((tmp_path / "out" / "rest_shapes.json").read_text())["strands"]
    curves = ringlet.read_hair_file(str(dense_target))
    result = ringlet.invert(curves, segments=15, threads=1)
    s = result["summary"]
    for key in ("strands", "unstable", "unconverged", "fit_max_distance", "max_deviation",
                "naive_max_deviation", "supported_samples"):
        assert s[key] == summary[key], key
    assert len(result["models"]) == 5
    for model, ref, mine_row, ref_row in zip(result["models"], rest, s["strand_results"],
                                             summary["strand_results"]):
        # rest_shapes.json holds the shortest round-trip decimals: exact doubles.
        assert np.array_equal(model.rest_curvatures, np.array(ref["rest_curvatures"]))
        assert mine_row["deviation"] == ref_row["deviation"]
        assert mine_row["fit_max_distance"] == ref_row["fit_max_distance"]
    # equilibrium.hair is written at the target's points: the same points, rounded to float32.
    written = ringlet.read_hair_file(str(tmp_path / "out" / "equilibrium.hair"))
    mine = np.concatenate(result["equilibria"]).astype(np.float32)
    assert np.array_equal(np.asarray(written.points), mine)


def test_inverted_rest_shapes_hold_the_targets_in_the_forward_solve(dense_target):
    curves = ringlet.read_hair_file(str(dense_target))
    counts = np.asarray(curves.point_counts)
    points = np.asarray(curves.points, dtype=np.float64)
    targets = np.split(points, np.cumsum(counts)[:-1])
    result = ringlet.invert(targets, segments=15)
    assert result["summary"]["unstable"] == 0 and result["summary"]["unconverged"] == 0
    # The forward solve of the inverted models from their natural (= rest) shape: an
    # independent path (the minimizer, not the inversion's closed form) back to the targets.
    # Strands 0, 1 and 3 are fitted exactly by 15 segments (their breaks fall on target
    # points): within 1e-6 L of every target point; the others within their fit error + 1e-6 L.
    solved = ringlet.solve(result["models"])
    for k, (target, model, solution) in enumerate(zip(targets, result["models"], solved)):
        length = model.length()
        row = result["summary"]["strand_results"][k]
        equilibrium = result["equilibria"][k]
        assert equilibrium.shape == target.shape
        assert solution.curvatures.shape == (15, 3)
        bound = 1e-6 * length if k in (0, 1, 3) else row["fit_max_distance"] + 1e-6 * length
        assert np.linalg.norm(equilibrium - target, axis=1).max() <= bound, k
        # The naive rest shape (q0 = target) sags: the reason for the inversion.
        assert np.linalg.norm(result["naive_equilibria"][k] - target, axis=1).max() > 1e-3 * length
    # The solve from the rest shapes finds the inverted equilibria (same curvatures to 1e-6 of
    # their scale).
    for model, solution, q in zip(result["models"], solved, result["target_curvatures"]):
        scale = max(1.0, np.abs(q).max())
        assert np.abs(solution.curvatures - q).max() <= 1e-6 * scale


def test_rest_curvatures_are_readable_and_writable():
    model = ringlet.StrandModel(ringlet.uniform_segments(0.1, 4),
                                ringlet.section_from_eccentricity(50e-6, 0.0))
    assert model.rest_curvatures is None
    q = np.arange(12, dtype=np.float64).reshape(4, 3)
    model.rest_curvatures = q
    assert np.array_equal(model.rest_curvatures, q)
    returned = model.rest_curvatures
    returned[0, 0] = 99.0  # a copy: the model does not change behind the user's back
    assert model.rest_curvatures[0, 0] == 0.0
    for bad in (np.zeros((3, 3)), np.zeros(5), [[np.nan, 0, 0]] * 4, "x"):
        with pytest.raises(ringlet.Error, match="rest_curvatures"):
            model.rest_curvatures = bad
    assert np.array_equal(model.rest_curvatures, q)  # a refused value changes nothing
    model.rest_curvatures = None
    assert model.rest_curvatures is None


def test_progress_reports_each_stage(dense_target):
    calls = []
    ringlet.invert(ringlet.read_hair_file(str(dense_target)), segments=15,
                   progress=lambda stage, done, total: calls.append((stage, done, total)))
    assert calls, "progress was never called"
    assert all(stage in ("fit", "invert") and 0 <= done <= total == 5
               for stage, done, total in calls), calls
    assert calls[-1] == ("invert", 5, 5)

    def fails(stage, done, total):
        raise ZeroDivisionError("from the callback")
    with pytest.raises(ZeroDivisionError, match="from the callback"):
        ringlet.invert(ringlet.read_hair_file(str(dense_target)), segments=15, progress=fails)


@pytest.mark.parametrize("kwargs, message", [
    (dict(targets=[np.zeros((1, 3))]), "targets[0]: expected at least 2 points, got 1"),
    (dict(targets=[np.zeros((4, 2))]), "targets[0]: expected a (k, 3) array"),
    (dict(targets=[]), "targets: expected at least one strand"),
    (dict(targets=[[[0, 0, 0], [0, 0, np.nan]]]), "targets[0]: point 1 is not finite"),
    (dict(hair_type="martian"), "hair_type: "),
    (dict(threads=10**5), "threads: expected an integer in [0, 1024]"),
    (dict(clearance=-1.0), "clearance: expected a finite number in [0, 0.1)"),
    (dict(body="/nonexistent/body.json"), "body: /nonexistent/body.json"),
    (dict(progress=3), "progress: expected None or a callable"),
])
def test_bad_arguments_name_the_field(kwargs, message):
    args = dict(targets=[np.array([[0, 0, 0], [0.05, 0, 0], [0.1, 0, 0]], dtype=float)])
    args.update(kwargs)
    with pytest.raises(ringlet.Error) as error:
        ringlet.invert(**args)
    assert message in str(error.value)


def test_scene_dicts_take_a_body():
    # A horizontal 10-cm strand above a 5-cm ball where its free end sags to
    # (tests/scene_json_test.cpp, InlineBodyHoldsTheStrand): the body keeps it outside the ball.
    centre = np.array([0.095, 0.0, -0.015])
    scene = {"strands": [{"length": 0.1, "root": {"position": [0, 0, 0.03],
                                                 "tangent": [1, 0, 0], "normal": [0, 0, 1]}}]}
    bare = ringlet.solve(scene, points_per_segment=8)[0].points
    scene["body"] = {"spheres": [{"center": centre.tolist(), "radius": 0.05}]}
    held = ringlet.solve(scene, points_per_segment=8)[0].points
    assert np.linalg.norm(bare - centre, axis=1).min() < 0.045
    assert np.linalg.norm(held - centre, axis=1).min() > 0.05 - 0.5e-3
