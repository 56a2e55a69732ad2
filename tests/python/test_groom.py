"""ringlet.groom, StyledHair and the writers against `ringlet groom` / `ringlet style`: the same
hairstyle gives the same .hair, .usda and .obj bytes; shapes, dtypes, views and errors."""
import json

import numpy as np
import pytest

import ringlet
from conftest import cli_error

# A styling list covering every operation (docs/hairstyle-format.md, "operations").
OPERATIONS = [
    {"curl": {"radius": 0.01, "pitch": 0.03, "select": {"indices": [0, 2, 5]}}},
    {"wet": {}},
    {"cut": {"z": -0.12}},
    {"dry": {}},
    {"grow": {"step": 0.01, "steps": 1}},
]


def test_groom_matches_the_command_bit_for_bit(cli, tmp_path, small_style):
    path, document = small_style
    out = tmp_path / "out"
    cli("groom", path, "-o", out, "--quiet", "--threads", 2)
    groom = ringlet.groom(str(path), threads=1)
    cli_bytes = (out / "strands.hair").read_bytes()
    assert ringlet.encode_hair_file(groom.strands) == cli_bytes
    ringlet.write_hair_file(str(tmp_path / "mine.hair"), groom.strands)
    assert (tmp_path / "mine.hair").read_bytes() == cli_bytes
    ringlet.write_usda(str(tmp_path / "mine.usda"), groom.strands)
    assert (tmp_path / "mine.usda").read_bytes() == (out / "strands.usda").read_bytes()
    ringlet.write_obj(str(tmp_path / "mine.obj"), groom.strands)
    assert (tmp_path / "mine.obj").read_bytes() == (out / "strands.obj").read_bytes()
    # The dict gives the same groom as the file.
    from_dict = ringlet.groom(document)
    assert ringlet.encode_hair_file(from_dict.strands) == cli_bytes
    # The summary agrees with masters.json's "groom" counts.
    counts = json.loads((out / "masters.json").read_text())["groom"]
    s = groom.summary
    for key in ("masters", "strands", "points", "converged", "unconverged", "unstable",
                "iterations"):
        assert getattr(s, key) == counts[key], key
    assert np.array_equal(groom.layers, counts["layers"])
    assert np.array_equal(groom.wisp_radii, counts["wisp_radii"])
    # Reading the command's file gives the module's arrays back exactly.
    read = ringlet.read_hair_file(str(out / "strands.hair"))
    assert np.array_equal(read.points, groom.strands.points)
    assert np.array_equal(read.widths, groom.strands.widths)
    assert np.array_equal(read.point_counts, groom.strands.point_counts)


def test_groom_arrays_shapes_dtypes_and_views(small_style):
    path, _ = small_style
    g = ringlet.groom(str(path))
    c = g.strands
    n, k = c.num_strands(), c.num_points()
    assert (n, k) == (36, 288)  # 12 masters x 3 strands x 8 points (SMALL_STYLE)
    expected = {"points": ((k, 3), np.float32), "point_counts": ((n,), np.uint32),
                "widths": ((k,), np.float32), "major_axes": ((k, 3), np.float32)}
    for name, (shape, dtype) in expected.items():
        a, b = getattr(c, name), getattr(c, name)
        assert a.shape == shape and a.dtype == dtype, name
        assert not a.flags.owndata and np.shares_memory(a, b), name
    offsets = c.offsets()
    assert offsets.dtype == np.int64 and offsets.shape == (n + 1,) and offsets[-1] == k
    assert np.array_equal(np.diff(offsets), c.point_counts)
    assert np.abs(np.linalg.norm(c.major_axes, axis=1) - 1).max() < 1e-5
    # In-place edits go to the curves themselves (views, not copies).
    c.points[0, 0] += 1.0
    assert g.strands.points[0, 0] == c.points[0, 0]
    roots = g.root_positions
    assert roots.shape == (12, 3) and not roots.flags.writeable
    assert np.allclose(np.linalg.norm(roots, axis=1), 0.1)  # on the 10-cm head sphere
    assert len(g.solutions) == len(g.models) == 12
    assert g.solutions[0].curvatures.shape == (g.models[0].num_segments(), 3)


def test_hair_curves_from_arrays_round_trip_through_the_file(tmp_path):
    points = np.array([[0, 0, 0], [0, 0, -0.1], [0.01, 0, 0], [0.01, 0, -0.05],
                       [0.01, 0, -0.1]], dtype=np.float64)
    curves = ringlet.HairCurves(points, [2, 3], np.full(5, 1e-4),
                                colors=[[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]])
    path = str(tmp_path / "two.hair")
    ringlet.write_hair_file(path, curves)
    back = ringlet.read_hair_file(path)
    assert np.array_equal(back.points, points.astype(np.float32))
    assert np.array_equal(back.colors, curves.colors)
    with pytest.raises(ringlet.Error) as info:
        ringlet.write_hair_file(path, curves)  # exists, no overwrite
    assert path in str(info.value)
    with pytest.raises(ringlet.Error) as info:
        ringlet.HairCurves(points, [2, 2], np.full(5, 1e-4))
    assert "point_counts" in str(info.value) or "points" in str(info.value)


def test_styling_matches_ringlet_style_bit_for_bit(cli, tmp_path, small_style):
    path, document = small_style
    document["operations"] = OPERATIONS
    styled_path = tmp_path / "styled.json"
    styled_path.write_text(json.dumps(document))
    out = tmp_path / "styled"
    cli("style", styled_path, "-o", out, "--quiet")
    cli_bytes = (out / "strands.hair").read_bytes()

    groom = ringlet.groom(str(styled_path))
    by_list = ringlet.StyledHair(groom)
    reports = by_list.apply_operations()
    assert [r.name for r in reports] == ["curl", "wet", "cut", "dry", "grow"]
    assert ringlet.encode_hair_file(by_list.strands()) == cli_bytes

    # The methods, one by one, take the same path.
    by_methods = ringlet.StyledHair(groom, threads=1)
    by_methods.curl(0.01, 0.03, select={"indices": [0, 2, 5]})
    by_methods.wet()
    assert by_methods.wet_state
    by_methods.cut(z=-0.12)
    by_methods.dry()
    by_methods.grow(step=0.01, steps=1)
    assert ringlet.encode_hair_file(by_methods.strands()) == cli_bytes
    # Anti-vacuity: styling changed the hair.
    assert ringlet.encode_hair_file(groom.strands) != cli_bytes


def test_bad_operation_raises_and_leaves_the_hair_unchanged(small_style):
    path, _ = small_style
    styled = ringlet.StyledHair(ringlet.groom(str(path)))
    before = ringlet.encode_hair_file(styled.strands())
    with pytest.raises(ringlet.Error) as info:
        styled.curl(-0.01, 0.03)
    assert str(info.value).startswith("curl.radius")
    with pytest.raises(ringlet.Error):
        styled.dry()  # not wet
    with pytest.raises(ringlet.Error) as info:
        styled.apply_operation({"perm": {}})
    assert "perm" in str(info.value)
    assert ringlet.encode_hair_file(styled.strands()) == before


def test_bad_hairstyle_raises_the_commands_message(cli, tmp_path, small_style):
    _, document = small_style
    document["hair"]["origin"] = "martian"
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(document))
    expected = cli_error(cli("groom", bad, "-o", tmp_path / "out", check=False))
    with pytest.raises(ringlet.Error) as info:
        ringlet.groom(document)
    assert expected == "%s: %s" % (bad, info.value)
    with pytest.raises(ringlet.Error) as from_file:
        ringlet.load_hairstyle(str(bad))
    assert str(from_file.value) == expected
