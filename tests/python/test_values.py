"""Issue 25, item 7: the module's values pickle bit for bit (also through multiprocessing with
the spawn context), copy and deepcopy independently, have useful reprs, and help(ringlet)
lists the classes; the type stubs are the generator's output for the built module."""
import ast
import copy
import json
import os
import pathlib
import pickle
import pydoc
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import ringlet
from conftest import EXAMPLES, SMALL_STYLE, SOURCE_DIR

SCENE = EXAMPLES / "vertical_curly.json"


def module_env():
    """The environment of a child interpreter that imports this very module (the PYTHONPATH
    of the tests may be relative to another directory)."""
    env = dict(os.environ)
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(ringlet.__file__)))
    env["PYTHONPATH"] = os.pathsep.join([package_parent, env.get("PYTHONPATH", "")])
    return env


def bits(value):
    """Everything observable about a value, numbers as their exact bits: arrays as (dtype,
    shape, bytes), floats as their 8 bytes (so -0.0, NaN payloads and subnormals count)."""
    if isinstance(value, np.ndarray):
        return ("array", str(value.dtype), value.shape, value.tobytes())
    if isinstance(value, float):
        return ("float", np.float64(value).tobytes())
    if isinstance(value, (list, tuple)):
        return [bits(v) for v in value]
    if isinstance(value, (int, str, bool, bytes)) or value is None:
        return value
    fields = {}
    for name in dir(value):
        if name.startswith("_"):
            continue
        attr = getattr(value, name)
        if callable(attr):
            continue
        if isinstance(attr, (ringlet.Hairstyle, ringlet.StyledHair)):
            fields[name] = repr(attr)
            continue
        fields[name] = bits(attr)
    return (type(value).__name__, fields)


def round_trips(value):
    for protocol in (2, pickle.DEFAULT_PROTOCOL, pickle.HIGHEST_PROTOCOL):
        back = pickle.loads(pickle.dumps(value, protocol=protocol))
        assert type(back) is type(value)
        assert bits(back) == bits(value)
    for back in (copy.copy(value), copy.deepcopy(value)):
        assert bits(back) == bits(value)
    return pickle.loads(pickle.dumps(value))


def odd_model():
    """A model whose numbers are hard to carry as text: thirds, -0.0, a subnormal, 2^-1074."""
    return ringlet.StrandModel(
        [0.1 / 3, 0.2 / 3, 1 / 7], ringlet.CrossSection(5e-5 + 1e-21, 4e-5 / 3),
        ringlet.Material(1e10 / 3, 0.3 + 1e-17, 1300.0 / 7),
        natural_curvature=[1 / 3, -0.0, 5e-324], root_position=[np.pi, -np.e, 1e-300],
        root_frame=np.eye(3), gravity=[0.0, -0.0, -9.81 / 3])


def test_models_options_and_scenes_round_trip_bit_for_bit():
    model = round_trips(odd_model())
    assert np.float64(model.natural_curvature[1]).tobytes() == np.float64(-0.0).tobytes()
    assert model.natural_curvature[2] == 5e-324
    round_trips(ringlet.CrossSection(5e-5 + 1e-21, 4e-5 / 3))
    round_trips(ringlet.Material(1e10 / 3, 0.1, 1.0 / 3))
    round_trips(ringlet.SolveOptions(method="newton", max_iterations=17, tolerance=1e-11 / 3,
                                     check_stability=False, max_stability_restarts=2))
    scene = ringlet.load_scene(str(SCENE))
    back = round_trips(scene)
    assert len(back.strands) == len(scene.strands)
    # The unpickled scene solves to the same bits (every field the solver reads survived).
    a = ringlet.solve(scene, threads=1, points_per_segment=2)
    b = ringlet.solve(back, threads=1, points_per_segment=2)
    assert [bits(r) for r in a] == [bits(r) for r in b]


def test_results_round_trip_bit_for_bit():
    results = ringlet.solve(str(SCENE), points_per_segment=3, threads=1)
    for r in results:
        back = round_trips(r)
        assert back.points.tobytes() == r.points.tobytes()
        assert back.material_frames.tobytes() == r.material_frames.tobytes()
        assert back.succeeded() == r.succeeded()
    round_trips(results[0].summary)
    round_trips(results[0].summary.energy)
    round_trips(results[0].summary.contact)
    round_trips(results)  # a list of them


def test_curves_hairstyles_and_grooms_round_trip_bit_for_bit(small_style, tmp_path):
    path, document = small_style
    from_file = ringlet.load_hairstyle(str(path))
    from_dict = ringlet.parse_hairstyle(document)
    for hairstyle in (from_file, from_dict):
        back = pickle.loads(pickle.dumps(hairstyle))
        assert repr(back) == repr(hairstyle)
        assert (back.length, back.segments, back.seed, back.num_operations, back.eccentricity) \
            == (hairstyle.length, hairstyle.segments, hairstyle.seed, hairstyle.num_operations,
                hairstyle.eccentricity)
        assert copy.copy(hairstyle) is hairstyle and copy.deepcopy(hairstyle) is hairstyle
    groom = ringlet.groom(from_file, threads=1)
    # The unpickled hairstyle grooms to the same bytes.
    again = ringlet.groom(pickle.loads(pickle.dumps(from_dict)), threads=1)
    assert ringlet.encode_hair_file(again.strands) == ringlet.encode_hair_file(groom.strands)

    strands = round_trips(groom.strands)
    assert ringlet.encode_hair_file(strands) == ringlet.encode_hair_file(groom.strands)
    back = round_trips(groom)
    for a, b in zip(groom.models, back.models):  # rebuilt from the hairstyle, checked
        for name in ("segment_lengths", "natural_curvature", "root_position", "root_frame"):
            assert getattr(a, name).tobytes() == getattr(b, name).tobytes()
        assert repr(a) == repr(b)
    # A styled head from the unpickled groom styles to the same bits.
    styled = [ringlet.StyledHair(g, threads=1) for g in (groom, back)]
    for s in styled:
        s.curl(0.01, 0.03, select={"indices": [0, 2]})
        s.wet()
    assert bits(styled[0].strands()) == bits(styled[1].strands())
    assert bits(styled[0].solutions) == bits(styled[1].solutions)
    round_trips(styled[0].curl(0.02, 0.03))  # an OperationReport
    round_trips(groom.summary)
    image, stats = ringlet.render(groom, width=4, height=4, samples_per_pixel=1, threads=1,
                                  return_stats=True)
    assert bits(round_trips(stats)) == bits(stats) and stats.camera_rays == 16
    # Styled hair carries wetness; it survives too.
    wet = styled[0].strands()
    assert wet.wetness.size == wet.num_strands() and wet.wetness.max() == 1.0
    round_trips(wet)


def test_groom_refuses_a_changed_body(small_style):
    path, _ = small_style
    groom = ringlet.groom(str(path), threads=1)
    state = list(groom.__getstate__())
    roots = state[5].copy()
    roots[0] = np.nextafter(roots[0], 1.0)  # one bit: as if the body file had moved a root
    state[5] = roots
    fresh = ringlet.Groom.__new__(ringlet.Groom)
    with pytest.raises(ringlet.Error, match="masters built again differ from the pickled"):
        fresh.__setstate__(tuple(state))


def test_a_model_with_contact_is_not_pickled_alone(small_style):
    path, _ = small_style
    groom = ringlet.groom(str(path), threads=1)
    with pytest.raises(ringlet.Error, match="cannot be pickled alone: pickle the Groom"):
        pickle.dumps(groom.models[0])
    model = copy.deepcopy(groom.models[0])  # copying keeps the (shared) body
    assert "contact=True" in repr(model)


def test_copies_are_independent():
    model = odd_model()
    for twin in (copy.copy(model), copy.deepcopy(model)):
        twin.natural_curvature[0] = 42.0
        twin.section = ringlet.CrossSection(1e-4, 1e-4)
        assert model.natural_curvature[0] == 1 / 3 and model.section.a == 5e-5 + 1e-21
    curves = ringlet.HairCurves([[0, 0, 0], [0, 0, 0.01]], [2], [7e-5, 7e-5])
    twin = copy.deepcopy(curves)
    twin.points[0, 0] = 1.0
    assert curves.points[0, 0] == 0.0


def test_errors_cross_processes():
    with pytest.raises(ringlet.Error) as info:
        ringlet.uniform_segments(-1.0, 3)
    back = pickle.loads(pickle.dumps(info.value))
    assert type(back) is ringlet.Error and str(back) == str(info.value)
    assert repr(ringlet.load_scene(str(SCENE))).startswith("Scene(strands=1, solver=SolveOptions(")


def test_stale_or_foreign_states_are_refused():
    fresh = ringlet.StrandModel.__new__(ringlet.StrandModel)
    with pytest.raises(ringlet.Error, match="expected a state of version 1"):
        fresh.__setstate__((99, 1, 2))
    bad = list(ringlet.HairCurves([[0, 0, 0], [0, 0, 0.01]], [2], [7e-5, 7e-5]).__getstate__())
    bad[1] = np.array([3], np.uint32)  # counts that do not match the points
    fresh = ringlet.HairCurves.__new__(ringlet.HairCurves)
    with pytest.raises(ringlet.Error, match="points"):
        fresh.__setstate__(tuple(bad))


def test_inconsistent_curves_are_refused_when_pickled():
    curves = ringlet.HairCurves([[0, 0, 0], [0, 0, 0.01]], [2], [7e-5, 7e-5])
    curves.point_counts[0] = 3  # edited in place: no longer matches the points
    with pytest.raises(ringlet.Error, match="pickling HairCurves.points: expected 3 points"):
        pickle.dumps(curves)


def test_values_cross_spawned_processes(tmp_path):
    """multiprocessing with the spawn context (fresh interpreters: everything is pickled both
    ways): workers solve an unpickled scene, style an unpickled groom and return results that
    are bit-identical to the same work done here."""
    (tmp_path / "small.json").write_text(json.dumps(SMALL_STYLE))
    script = tmp_path / "sweep.py"
    script.write_text(textwrap.dedent("""
        import multiprocessing
        import pickle
        import sys
        import ringlet

        def work(job):
            kind, value, radius = job
            if kind == "scene":
                return ringlet.solve(value, threads=1, points_per_segment=2)
            styled = ringlet.StyledHair(value, threads=1)
            styled.curl(radius, 0.03)
            return styled.strands(), styled.solutions

        if __name__ == "__main__":
            scene = ringlet.load_scene(sys.argv[1])
            groom = ringlet.groom("small.json", threads=1)
            jobs = [("scene", scene, 0.0), ("groom", groom, 0.01), ("groom", groom, 0.02)]
            with multiprocessing.get_context("spawn").Pool(2) as pool:
                remote = pool.map(work, jobs)
            local = [work(job) for job in jobs]
            same = [pickle.dumps(a) == pickle.dumps(b) for a, b in zip(remote, local)]
            print("OK" if all(same) else "DIFFERENT %s" % same)
    """))
    done = subprocess.run([sys.executable, str(script), str(SCENE)], capture_output=True,
                          text=True, cwd=str(tmp_path), env=module_env(), timeout=240)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip() == "OK", done.stdout


def test_reprs_say_what_the_value_is(small_style):
    path, _ = small_style
    assert repr(ringlet.CrossSection(5e-5, 4e-5)) == "CrossSection(a=5e-05, b=4e-05)"
    assert repr(ringlet.Material()) == \
        "Material(young_modulus=10000000000.0, poisson_ratio=0.3, density=1300.0)"
    assert repr(ringlet.SolveOptions()) == (
        "SolveOptions(method='auto', max_iterations=1000, tolerance=1e-09, "
        "check_stability=True, max_stability_restarts=4)")
    r = ringlet.solve(str(SCENE), threads=1)[0]
    assert repr(r).startswith("StrandResult(points=%d, segments=%d, termination='converged'"
                              % (len(r.points), len(r.segment_lengths)))
    groom = ringlet.groom(str(path), threads=1)
    assert repr(groom) == "Groom(masters=12, strands=36, points=288)"
    assert repr(groom.strands) == \
        "HairCurves(strands=36, points=288, colors=True, major_axes=True, wetness=False)"
    assert repr(ringlet.StyledHair(groom, threads=1)) == "StyledHair(masters=12, wet=False)"
    assert repr(groom.hairstyle).startswith("Hairstyle(length=0.15, segments=8, seed=2, ")
    for value in (r.summary, r.summary.energy, r.summary.contact, groom.summary,
                  ringlet.StyledHair(groom, threads=1).curl(0.02, 0.03),
                  groom.solutions[0], groom.models[0], ringlet.load_scene(str(SCENE))):
        assert not repr(value).startswith("<"), repr(value)


def test_help_lists_the_classes_and_functions():
    text = pydoc.render_doc(ringlet, renderer=pydoc.plaintext)
    for name in ("StrandModel", "Scene", "StrandResult", "HairCurves", "Groom", "StyledHair",
                 "Hairstyle", "Error"):
        assert "class %s" % name in text, name
    for name in ("solve", "groom", "render", "read_hair_file"):
        assert "\n    %s(" % name in text, name
    assert ringlet.StrandModel.__module__ == "ringlet"


def test_type_stubs_are_the_generators_output():
    """python/ringlet/__init__.pyi is what python/generate_stubs.py writes for the built module
    (regenerate it after changing a binding), parses, and covers every public name; the build
    tree holds it with py.typed (PEP 561), as `pip install` does (setup.py package_data)."""
    committed = (SOURCE_DIR / "python" / "ringlet" / "__init__.pyi").read_text()
    generated = subprocess.run([sys.executable, str(SOURCE_DIR / "python" / "generate_stubs.py")],
                               capture_output=True, text=True, check=True).stdout
    assert generated == committed, "regenerate python/ringlet/__init__.pyi (see its generator)"
    tree = ast.parse(committed)
    names = {n.name for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    assert set(ringlet.__all__) <= names, set(ringlet.__all__) - names
    package = pathlib.Path(ringlet.__file__).parent
    assert (package / "py.typed").exists() and (package / "__init__.pyi").exists()
    setup = (SOURCE_DIR / "setup.py").read_text()
    assert '"__init__.pyi", "py.typed"' in setup
