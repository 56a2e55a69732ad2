"""Issue 25, items 1-4: ordinary Python code must not crash the interpreter or get silent wrong
answers. Each case crashed (segfault) or returned nonsense before the fix; the crashing ones
run in a subprocess so that a regression fails the test instead of killing pytest.

  1. no handle the module returns dangles: views and objects kept across every mutating call;
  2. threads are capped as the command caps them (--threads: 0 to 1024);
  3. dicts are limited to the file readers' 64 levels, and circular ones are refused;
  4. no silent conversions: the helpers and constructors check what the file readers check.
"""
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import ringlet
from conftest import EXAMPLES, SMALL_STYLE, cli_error


def module_env():
    """The environment of a child interpreter that imports this very module (the PYTHONPATH
    of the tests may be relative to another directory)."""
    env = dict(os.environ)
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(ringlet.__file__)))
    env["PYTHONPATH"] = os.pathsep.join([package_parent, env.get("PYTHONPATH", "")])
    return env


def run_isolated(code, tmp_path):
    """Runs code in a fresh interpreter (the module's environment); returns its stdout.
    Fails with the exit status (-11: segfault) and stderr when it does not exit 0."""
    script = tmp_path / "isolated.py"
    script.write_text(textwrap.dedent(code))
    (tmp_path / "small.json").write_text(json.dumps(SMALL_STYLE))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          cwd=str(tmp_path), env=module_env(), timeout=240)
    assert done.returncode == 0, "exit %d:\n%s" % (done.returncode, done.stderr[-3000:])
    return done.stdout


# ---------------------------------------------------------------------------------------------
# 1. Dangling handles.

def test_styled_handles_survive_every_operation(tmp_path):
    """Every object and view StyledHair and Groom return, kept by a researcher across every
    styling operation (each replaces the styled state), still reads what it read when taken:
    it used to read freed memory (5e-315, then a segfault)."""
    out = run_isolated("""
        import gc
        import numpy as np
        import ringlet

        groom = ringlet.groom("small.json", threads=1)
        styled = ringlet.StyledHair(groom, threads=1)

        def handles():
            # (name, a zero-argument function reading the handle) for every handle taken now.
            taken = []
            sols, models = styled.solutions, styled.models
            for i in (0, len(sols) - 1):
                s, m = sols[i], models[i]
                curv, summ = s.curvatures, s.summary
                taken += [("solutions[%d].curvatures" % i, lambda v=curv: v.copy()),
                          ("solutions[%d].summary" % i,
                           lambda v=summ: (v.iterations, v.residual, v.energy.total)),
                          ("solutions[%d] (object)" % i, lambda v=s: v.curvatures.copy())]
                views = {k: getattr(m, k) for k in ("segment_lengths", "natural_curvature",
                                                      "root_position", "root_frame", "gravity")}
                for k, v in views.items():
                    taken.append(("models[%d].%s" % (i, k), lambda v=v: v.copy()))
                sec, mat = m.section, m.material
                taken += [("models[%d].section" % i, lambda v=sec: (v.a, v.b)),
                          ("models[%d].material" % i, lambda v=mat: (v.young_modulus, v.density)),
                          ("models[%d] (object)" % i, lambda v=m: v.segment_lengths.copy())]
            strands = styled.strands()
            for k in ("points", "widths", "point_counts", "major_axes", "colors", "wetness"):
                taken.append(("strands().%s" % k, lambda v=getattr(strands, k): v.copy()))
            g_strands, g_sol, g_model = groom.strands, groom.solutions[3], groom.models[3]
            for k in ("points", "widths", "point_counts", "major_axes", "colors"):
                taken.append(("groom.strands.%s" % k, lambda v=getattr(g_strands, k): v.copy()))
            taken += [("groom.solutions[3].curvatures", lambda v=g_sol.curvatures: v.copy()),
                      ("groom.models[3].natural_curvature",
                       lambda v=g_model.natural_curvature: v.copy()),
                      ("groom.root_positions", lambda v=groom.root_positions: v.copy()),
                      ("groom.wisp_radii", lambda v=groom.wisp_radii: v.copy())]
            return [(name, read, read()) for name, read in taken]

        def same(a, b):
            if isinstance(a, np.ndarray):
                return a.shape == b.shape and np.array_equal(a, b)
            return a == b

        operations = [
            ("curl", lambda: styled.curl(0.01, 0.03, select={"indices": [0, 2, 5]})),
            ("wet", lambda: styled.wet()),
            ("cut", lambda: styled.cut(z=-0.12)),
            ("dry", lambda: styled.dry()),
            ("grow", lambda: styled.grow(step=0.01, steps=1)),
            ("apply_operation", lambda: styled.apply_operation({"cut": {"length": 0.1}})),
            ("apply_operations", lambda: styled.apply_operations()),
        ]
        kept = handles()
        checked = 0
        for op_name, op in operations:
            op()
            gc.collect()
            junk = [np.full(4096, 7.0) for _ in range(64)]  # reuse what was freed
            kept += handles()
            for name, read, value in kept:
                assert same(read(), value), "%s changed after %s" % (name, op_name)
                checked += 1
        # The owners go away; the handles keep them alive.
        del groom, styled
        gc.collect()
        junk = [np.full(4096, 7.0) for _ in range(64)]
        for name, read, value in kept:
            assert same(read(), value), "%s changed after its owner was deleted" % name
            checked += 1
        print("OK", checked)
    """, tmp_path)
    assert out.startswith("OK"), out
    assert int(out.split()[1]) > 1000


def test_styled_models_and_solutions_are_copies(small_style):
    path, _ = small_style
    styled = ringlet.StyledHair(ringlet.groom(str(path), threads=1), threads=1)
    model = styled.models[0]
    model.natural_curvature[:] = 123.0  # edits the copy only
    assert not np.any(styled.models[0].natural_curvature == 123.0)
    before = styled.solutions[0].curvatures.copy()
    styled.curl(0.01, 0.03)
    assert not np.array_equal(styled.solutions[0].curvatures, before)  # a new state


def test_result_scene_and_curve_views_outlive_their_owners(tmp_path):
    out = run_isolated("""
        import gc
        import numpy as np
        import ringlet
        results = ringlet.solve("%s", points_per_segment=3, threads=1)
        views = [results[0].points, results[0].curvatures, results[0].segment_lengths,
                 results[0].material_frames]
        copies = [v.copy() for v in views]
        scene = ringlet.load_scene("%s")
        strand = scene.strands[0]
        lengths = strand.segment_lengths
        saved = lengths.copy()
        section = strand.section
        strand.section = ringlet.CrossSection(3e-5, 2e-5)  # assigned in place: no dangling
        assert (section.a, section.b) == (3e-5, 2e-5)
        del results, scene, strand
        gc.collect()
        junk = [np.full(4096, 7.0) for _ in range(64)]
        assert all(np.array_equal(v, c) for v, c in zip(views, copies))
        assert np.array_equal(lengths, saved)
        print("OK")
    """ % (EXAMPLES / "vertical_curly.json", EXAMPLES / "vertical_curly.json"), tmp_path)
    assert out.strip() == "OK"


# ---------------------------------------------------------------------------------------------
# 2. Threads.

def test_threads_beyond_the_command_limit_are_refused(tmp_path):
    """threads=10**5 used to segfault solve (a TBB arena of 10^5 threads); now every threads
    argument takes what the command's --threads takes, 0 to 1024."""
    out = run_isolated("""
        import ringlet
        calls = {
            "solve": lambda t: ringlet.solve("%s", threads=t),
            "groom": lambda t: ringlet.groom("small.json", threads=t),
            "StyledHair": lambda t: ringlet.StyledHair(groom, threads=t),
            "render": lambda t: ringlet.render(groom, width=4, height=4, samples_per_pixel=1,
                                               threads=t),
        }
        groom = ringlet.groom("small.json", threads=1)
        for name, call in calls.items():
            for threads in (10**5, 1025, -1):
                try:
                    call(threads)
                except ringlet.Error as e:
                    assert str(e) == ("threads: expected an integer in [0, 1024] (0 = all "
                                      "cores), got %%d" %% threads), (name, str(e))
                else:
                    raise AssertionError("%%s accepted threads=%%d" %% (name, threads))
        print("OK")
    """ % (EXAMPLES / "vertical_curly.json"), tmp_path)
    assert out.strip() == "OK"


def test_threads_limit_is_the_commands(cli):
    done = cli("solve", EXAMPLES / "vertical_curly.json", "--threads", 1025, check=False)
    assert done.returncode != 0 and "1024" in done.stderr
    assert cli("solve", EXAMPLES / "vertical_curly.json", "--threads", 1024, "-o",
               os.devnull, "--quiet", check=False).returncode in (0, 1)


# ---------------------------------------------------------------------------------------------
# 3. Deep and circular dicts.

def nested(levels, leaf):
    """`levels` dicts around leaf (not a container): {"a": {"a": ... leaf}}."""
    value = leaf
    for _ in range(levels):
        value = {"a": value}
    return value


def test_deep_and_circular_dicts_are_refused(tmp_path):
    """A 200,000-deep dict and a dict holding itself used to overflow the C stack."""
    out = run_isolated("""
        import ringlet
        deep = {}
        d = deep
        for _ in range(200000):
            d["a"] = {}
            d = d["a"]
        circular = {"strands": []}
        circular["strands"].append(circular)
        loop = [1]
        loop.append(loop)
        groom = None
        calls = [
            ("parse_scene", lambda v: ringlet.parse_scene(v)),
            ("solve", lambda v: ringlet.solve(v)),
            ("parse_hairstyle", lambda v: ringlet.parse_hairstyle(v)),
            ("groom", lambda v: ringlet.groom(v)),
            ("render", lambda v: ringlet.render(settings=v)),
            ("apply_operation", lambda v: styled.apply_operation({"curl": v})),
            ("curl select", lambda v: styled.curl(0.01, 0.03, select=v)),
        ]
        styled = ringlet.StyledHair(ringlet.groom("small.json", threads=1), threads=1)
        for name, call in calls:
            for kind, value, expected in (("deep", deep, "levels of nested dicts"),
                                           ("circular", circular, "circular reference"),
                                           ("list loop", {"x": loop}, "circular reference")):
                try:
                    call(value)
                except ringlet.Error as e:
                    assert expected in str(e) and len(str(e)) < 600, (name, kind, str(e))
                else:
                    raise AssertionError("%s accepted the %s dict" % (name, kind))
        print("OK")
    """, tmp_path)
    assert out.strip() == "OK"


def test_dict_depth_limit_is_the_file_readers(cli, tmp_path):
    """64 levels pass the conversion (the scene reader then names the unknown field), 65 do
    not: the limit of JSON files (kMaxJsonDepth), which the command applies to the same text."""
    for depth, refused in ((64, False), (65, True)):
        # {"strands": [...]} is 2 levels; the rest nest in an unknown field of the strand.
        scene = {"strands": [nested(depth - 2, 1)]}
        assert json.dumps(scene).count("{") + json.dumps(scene).count("[") == depth
        with pytest.raises(ringlet.Error) as info:
            ringlet.parse_scene(scene)
        assert ("levels of nested dicts" in str(info.value)) == refused, str(info.value)
        path = tmp_path / ("depth%d.json" % depth)
        path.write_text(json.dumps(scene))
        message = cli_error(cli("solve", path, "-o", tmp_path / "r.json", check=False))
        assert ("nested deeper than 64 levels" in message) == refused, message


# ---------------------------------------------------------------------------------------------
# 4. Silent conversions.

POINTS = np.array([[0, 0, 0], [0, 0, 0.01]], np.float32)
WIDTHS = [7e-5, 7e-5]


@pytest.mark.parametrize("counts, got", [
    ([2**32 + 2], "4294967298"),   # used to wrap to 2
    ([2.5], "2.5"),                # used to round to 2
    ([-1], "-1"),                  # used to wrap to 4294967295
    ([1], "1"),
    (np.array([2**63 + 5], np.uint64), "9223372036854775813"),
    ([float("nan")], "nan"),
])
def test_point_counts_are_integers_never_wrapped_or_rounded(counts, got):
    with pytest.raises(ringlet.Error) as info:
        ringlet.HairCurves(POINTS, counts, WIDTHS)
    assert str(info.value) == ("point_counts[0]: expected an integer in [2, 4294967295], got "
                               + got)


def test_point_counts_accept_integers_of_any_dtype_and_integral_floats():
    for counts in ([2], np.array([2], np.int8), np.array([2], np.uint64), [2.0]):
        assert list(ringlet.HairCurves(POINTS, counts, WIDTHS).point_counts) == [2]
    for bad in (np.array([True]), ["2"], [2 + 0j]):
        with pytest.raises(ringlet.Error, match="point_counts: expected a 1-D array of integers"):
            ringlet.HairCurves(POINTS, bad, WIDTHS)
    with pytest.raises(ringlet.Error, match="points: expected an array of shape"):
        ringlet.HairCurves(POINTS.astype(complex), [2], WIDTHS)


@pytest.mark.parametrize("kwargs, message", [
    ({"colors": [[5.0, -1.0, 0.0]]}, "colors[0]: expected linear RGB in [0, 1], got (5.0, -1.0, 0.0)"),
    ({"colors": [[0.5, float("nan"), 0.5]]}, "curves.colors[0]: expected a finite"),
    ({"major_axes": np.zeros((2, 3))}, "major_axes[0]: expected a finite, non-zero major axis, "
                                       "got (0.0, 0.0, 0.0)"),
    ({"wetness": [1.5]}, "curves.wetness[0]: expected a value in [0, 1], got 1.5"),
])
def test_curve_attributes_are_checked(kwargs, message):
    with pytest.raises(ringlet.Error) as info:
        ringlet.HairCurves(POINTS, [2], WIDTHS, **kwargs)
    assert str(info.value).startswith(message), str(info.value)


def test_curve_attributes_in_range_are_kept_exactly():
    c = ringlet.HairCurves(POINTS, [2], WIDTHS, colors=[[0.0, 0.5, 1.0]],
                           major_axes=[[1, 0, 0], [0, 1, 0]], wetness=[0.25])
    assert c.colors.tolist() == [[0.0, 0.5, 1.0]]
    assert c.major_axes.tolist() == [[1, 0, 0], [0, 1, 0]]
    assert c.wetness.tolist() == [0.25]


def test_png_of_srgb_codes_is_refused(tmp_path):
    """write_png(render(srgb=True)) used to write an all-white PNG (the codes taken as radiance
    0..255); it now says what it expects, and writes nothing."""
    codes = np.full((2, 2, 3), 10, np.uint8)
    for call in (lambda: ringlet.write_png(str(tmp_path / "x.png"), codes),
                 lambda: ringlet.encode_srgb8(codes)):
        with pytest.raises(ringlet.Error) as info:
            call()
        assert str(info.value).startswith("image: expected linear radiance, a floating-point "
                                          "array of shape (height, width, 3), got dtype uint8")
    assert not (tmp_path / "x.png").exists()
    with pytest.raises(ringlet.Error, match="exposure: expected a finite number >= 0, got -1.0"):
        ringlet.encode_srgb8(np.zeros((1, 1, 3), np.float32), exposure=-1.0)


def scene_error(strand_fields):
    """The scene reader's message for one strand with these fields, without "strands[0]."."""
    strand = {"length": 0.3}
    strand.update(strand_fields)
    with pytest.raises(ringlet.Error) as info:
        ringlet.parse_scene({"strands": [strand]})
    message = str(info.value)
    assert message.startswith("strands[0]."), message
    return message[len("strands[0]."):]


def test_helpers_check_what_the_scene_reader_checks():
    """The same value gives the same message as the scene file's field (the file reader is the
    reference: the helpers used to return NaN sections and negative segments)."""
    nan = float("nan")
    cases = [
        (lambda: ringlet.section_from_eccentricity(5e-5, 1.0), {"eccentricity": 1.0}),
        (lambda: ringlet.section_from_eccentricity(5e-5, -0.1), {"eccentricity": -0.1}),
        (lambda: ringlet.section_from_ellipticity(5e-5, 0.5), {"ellipticity": 0.5}),
        (lambda: ringlet.Material(young_modulus=-1.0), {"young_modulus": -1.0}),
        (lambda: ringlet.Material(poisson_ratio=0.6), {"poisson_ratio": 0.6}),
        (lambda: ringlet.Material(density=-1.0), {"density": -1.0}),
        (lambda: ringlet.uniform_segments(-0.1, 3), {"length": -0.1}),
        (lambda: ringlet.graded_segments(0.3, 3, 0.5), {"grading": 0.5}),
        (lambda: ringlet.uniform_segments(0.3, 0), {"segments": 0}),
        (lambda: ringlet.uniform_segments(0.3, 100001), {"segments": 100001}),
    ]
    for call, fields in cases:
        with pytest.raises(ringlet.Error) as info:
            call()
        reference = scene_error(fields)
        mine = str(info.value)
        # Same value and expectation; the helpers' argument names (ratio) may differ from the
        # file's (grading), and the grading's "or \"auto\"" is the file's alone.
        field, expected = reference.split(": ", 1)
        expected = expected.replace(' or "auto"', "")
        assert mine.split(": ", 1)[1] == expected, (mine, reference)
    for call, field in [
        (lambda: ringlet.CrossSection(nan, 1e-5), "a"),
        (lambda: ringlet.CrossSection(1e-5, 2e-5), "b"),
        (lambda: ringlet.CrossSection(1e-5, 0.0), "b"),
        (lambda: ringlet.section_from_eccentricity(nan, 0.5), "mean_radius"),
        (lambda: ringlet.section_from_eccentricity(5e-5, nan), "eccentricity"),
        (lambda: ringlet.uniform_segments(float("inf"), 3), "length"),
        (lambda: ringlet.graded_segments(0.3, 3, nan), "ratio"),
        (lambda: ringlet.graded_segments(1e-320, 50, 1e300), "ratio"),
        (lambda: ringlet.recommended_grading_ratio(-1.0), "gravity_parameter"),
    ]:
        with pytest.raises(ringlet.Error) as info:
            call()
        assert str(info.value).startswith(field + ": "), str(info.value)


def test_section_and_material_fields_are_checked_when_set():
    section, material = ringlet.CrossSection(5e-5, 4e-5), ringlet.Material()
    for obj, field, value, message in [
        (section, "a", float("nan"), "a: expected a finite number > 0 (metres), got nan"),
        (section, "b", -1e-5, "b: expected a finite number > 0 (metres), got -1e-05"),
        (material, "young_modulus", 0.0, "young_modulus: expected a finite number > 0 "
                                          "(pascals), got 0.0"),
        (material, "poisson_ratio", 0.5000001, "poisson_ratio: expected a finite number in "
                                               "(-1, 0.5], got 0.5000001"),
        (material, "density", float("inf"), "density: expected a finite number >= 0 (kg/m^3), "
                                            "got inf"),
    ]:
        with pytest.raises(ringlet.Error) as info:
            setattr(obj, field, value)
        assert str(info.value) == message
    assert (section.a, section.b) == (5e-5, 4e-5) and material.density == 1300.0
    material.density = 0.0  # in range: set
    section.b = 4.5e-5
    assert material.density == 0.0 and section.b == 4.5e-5


def test_helpers_in_range_are_unchanged():
    s = ringlet.section_from_eccentricity(5e-5, 0.5)
    assert s.a * s.b == pytest.approx(25e-10, rel=1e-15) and s.a > s.b
    assert ringlet.uniform_segments(0.3, 3) == [0.3 / 3] * 3
    lengths = ringlet.graded_segments(0.3, 3, 4.0)
    assert lengths[2] / lengths[0] == pytest.approx(4.0, rel=1e-14)
    assert ringlet.CrossSection(2e-5, 2e-5).a == 2e-5


def test_non_finite_numbers_in_dicts_and_keywords_are_named(small_style):
    """JSON has no NaN or infinity: the readers used to quote them as "got null"."""
    path, document = small_style
    styled = ringlet.StyledHair(ringlet.groom(str(path), threads=1), threads=1)
    nan = float("nan")
    for call, message in [
        (lambda: styled.curl(nan, 0.03), "curl.radius: expected a finite number (JSON has no "
                                         "NaN or infinity), got nan"),
        (lambda: styled.curl(0.01, float("-inf")), "curl.pitch: expected a finite number "
                                                   "(JSON has no NaN or infinity), got -inf"),
        (lambda: styled.wet(stiffness_factor=nan), "wet.stiffness_factor: expected a finite "
                                                   "number (JSON has no NaN or infinity), got nan"),
        (lambda: ringlet.parse_scene({"strands": [{"length": nan}]}),
         "scene.strands[0].length: expected a finite number (JSON has no NaN or infinity), "
         "got nan"),
    ]:
        with pytest.raises(ringlet.Error) as info:
            call()
        assert str(info.value) == message
    styled.curl(float("inf"), 0.03)  # +inf radius: straighten, as "inf" in a file


def test_scene_limits_of_the_reader_hold_for_python_scenes():
    """A scene made in Python gets the scene reader's limits: dense BFGS up to 1000 segments
    (the library used to switch to L-BFGS silently), 10^7 segments in all strands."""
    model = ringlet.StrandModel(ringlet.uniform_segments(0.3, 1001),
                                ringlet.CrossSection(5e-5, 5e-5))
    with pytest.raises(ringlet.Error) as info:
        ringlet.solve(model, options=ringlet.SolveOptions(method="bfgs"))
    assert str(info.value).startswith(
        'strands[0].segment_lengths: 1001 segments exceed the limit of 1000 for the method "bfgs"')
    reference = {"strands": [{"length": 0.3, "segments": 1001}], "solver": {"method": "bfgs"}}
    with pytest.raises(ringlet.Error) as file_info:
        ringlet.parse_scene(reference)
    assert str(file_info.value).split(": ", 1)[1] == str(info.value).split(": ", 1)[1]
    big = ringlet.StrandModel(ringlet.uniform_segments(0.3, 100000),
                              ringlet.CrossSection(5e-5, 5e-5))
    with pytest.raises(ringlet.Error) as info:
        ringlet.solve([big] * 101)
    assert str(info.value) == ("strands[100].segment_lengths: 100000 more segments would take "
                               "the scene beyond its limit of 10000000 segments in all strands")


def test_render_overrides_take_what_the_command_takes(small_style, cli, tmp_path):
    path, _ = small_style
    groom = ringlet.groom(str(path), threads=1)
    for kwargs, message in [
        ({"width": 0}, "width: expected an integer between 1 and 16384, got 0"),
        ({"height": 2**40}, "height: expected an integer between 1 and 16384, got 1099511627776"),
        ({"samples_per_pixel": 2**20 + 1},
         "samples_per_pixel: expected an integer between 1 and 1048576, got 1048577"),
    ]:
        with pytest.raises(ringlet.Error) as info:
            ringlet.render(groom, **kwargs)
        assert str(info.value) == message
    with pytest.raises(ringlet.Error) as info:
        ringlet.render(groom, width=16384, height=16384, samples_per_pixel=1)
    mine = str(info.value)
    assert mine.startswith("width, height, samples_per_pixel (or the settings): ")
    done = cli("render", path, "-o", tmp_path / "x.png", "--width", 16384, "--height", 16384,
               "--spp", 1, check=False)
    assert cli_error(done).split(": ", 1)[1] == mine.split(": ", 1)[1]
    assert not (tmp_path / "x.png").exists()


def test_one_styling_operation_at_a_time(small_style):
    """Two threads styling the same head used to run both on the same old state (one result
    silently lost); the second is now refused while the first runs."""
    import threading
    path, _ = small_style
    styled = ringlet.StyledHair(ringlet.groom(str(path), threads=1), threads=1)
    busy = ("StyledHair: expected one operation at a time, got another while one is running "
            "(from another thread)")

    def grow():
        while True:  # until it is not refused itself (a dry below may be running)
            try:
                return styled.grow(step=0.005, steps=40)
            except ringlet.Error as e:
                assert str(e) == busy, str(e)

    worker = threading.Thread(target=grow)
    worker.start()
    refused = None
    attempts = 0
    while worker.is_alive() and refused is None:
        attempts += 1
        try:
            styled.dry()  # on a dry head: refused by Dry itself when nothing else runs
        except ringlet.Error as e:
            if str(e) == busy:
                refused = str(e)
            else:
                assert str(e) == "dry: the hair is not wet (wet it first)", str(e)
    worker.join()
    if refused is None and attempts < 20:
        pytest.skip("the grow finished before a second operation could start")
    assert refused is not None, "%d operations ran while the grow did" % attempts
    assert refused == busy
    assert len(styled.solutions[0].curvatures) > 8  # the grow itself went through
