"""ringlet.simulate against `ringlet simulate`: the same points as hair.usda's time samples and
the same per-frame summary as frames.jsonl, bit for bit; inputs, shapes, errors with the
readers' wording; a progress callback; Ctrl-C (KeyboardInterrupt) in a subprocess."""
import json
import os
import re
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import ringlet
from conftest import SMALL_STYLE

SUMMARY_FIELDS = ["kinetic", "elastic", "gravity", "contact", "max_penetration",
                  "newton_iterations", "halved_steps", "failed_steps", "residual"]


def usda_points(text):
    """The points.timeSamples of a ringlet .usda as {frame: float32 array (P, 3)}."""
    block = re.search(r"point3f\[\] points\.timeSamples = \{\n(.*?)\n    \}", text, re.S).group(1)
    samples = {}
    for line in block.split("\n"):
        m = re.match(r"\s+(\d+): \[(.*)\],$", line)
        values = re.findall(r"[-0-9.e+]+", m.group(2))
        samples[int(m.group(1))] = np.array(values, dtype=np.float32).reshape(-1, 3)
    return samples


def test_simulate_matches_the_command_bit_for_bit(cli, tmp_path, small_style):
    path, document = small_style
    out = tmp_path / "out"
    cli("simulate", path, "-o", out, "--motion", "shake", "--duration", 0.5, "--quiet",
        "--threads", 2)
    result = ringlet.simulate(str(path), motion="shake", duration=0.5, threads=1)
    frames = 13  # floor(0.5 * 24) + 1
    assert result["time"].shape == (frames,)
    np.testing.assert_array_equal(result["time"], np.arange(frames) / 24.0)
    points = result["points"]
    assert points.dtype == np.float32 and points.shape == (frames, 36 * 8, 3)
    assert result["point_counts"].dtype == np.uint32
    assert result["point_counts"].sum() == 36 * 8
    samples = usda_points((out / "hair.usda").read_text())
    assert sorted(samples) == list(range(frames))
    for k in range(frames):
        np.testing.assert_array_equal(points[k], samples[k])
    lines = [json.loads(l) for l in (out / "frames.jsonl").read_text().splitlines()]
    summary = result["summary"]
    for field in SUMMARY_FIELDS:
        assert summary[field].shape == (frames,)
        assert list(summary[field]) == [l[field] for l in lines], field
    assert summary["message"] == [l.get("message", "") for l in lines]
    # The head moved the hair: the tips are not where they started.
    assert np.abs(points[6] - points[0]).max() > 0.01
    # A Groom and the dict give the same frames.
    groom = ringlet.groom(document)
    again = ringlet.simulate(groom, motion="shake", duration=0.5)
    np.testing.assert_array_equal(again["points"], points)


def test_inexact_steps_match_the_command_and_stay_near_newtons(cli, tmp_path, small_style):
    """The fast setting of docs/benchmarks.md (inexact steps, 2 mass points): the module and the
    command write the same frames; fewer Newton updates than Newton to the tolerance (measured
    160 against 782), and every point within 2 mm of Newton's frames (measured 0.83 mm while the
    shake moves points by up to 7 cm)."""
    path, _ = small_style
    out = tmp_path / "fast"
    cli("simulate", path, "-o", out, "--motion", "shake", "--duration", 0.5, "--quiet",
        "--model-tolerance", 0.03, "--mass-points", 2)
    fast = ringlet.simulate(str(path), motion="shake", duration=0.5, model_tolerance=0.03,
                            mass_points=2)
    samples = usda_points((out / "hair.usda").read_text())
    for k in range(len(fast["time"])):
        np.testing.assert_array_equal(fast["points"][k], samples[k])
    exact = ringlet.simulate(str(path), motion="shake", duration=0.5)
    fast_updates = fast["summary"]["newton_iterations"].sum()
    exact_updates = exact["summary"]["newton_iterations"].sum()
    moved = np.abs(exact["points"][-1] - exact["points"][0]).max()
    apart = np.abs(fast["points"] - exact["points"]).max()
    print(f"updates {fast_updates} vs {exact_updates}, apart {apart:.3e} m, moved {moved:.3e} m")
    assert fast_updates < 0.5 * exact_updates
    assert apart < 2e-3


def test_single_strands_and_motion_dicts():
    scene = {"strands": [{"length": 0.1, "segments": 6,
                          "root": {"position": [0, 0, 0], "tangent": [1, 0, 0],
                                   "normal": [0, 0, 1]}}]}
    motion = {"keyframes": [{"time": 0}, {"time": 0.2, "translation": [0, 0, 0.02]}]}
    result = ringlet.simulate(scene, motion=motion, duration=0.25, pivot=[0, 0, 0])
    assert result["points"].shape == (7, 25, 3)  # 4 points per segment and the root
    # The root follows the keyframes: 2 cm up from t = 0.2 s on.
    np.testing.assert_allclose(result["points"][6, 0], [0, 0, 0.02], atol=1e-7)
    np.testing.assert_array_equal(result["points"][0, 0], [0, 0, 0])


@pytest.mark.parametrize("kwargs, message", [
    ({"motion": "wiggle"}, "motion: expected nod, shake, turn, walk, none, a motion file"),
    ({"motion": {"keyframes": [{"time": 0}, {"time": 0}]}},
     "motion: keyframes[1].time: expected a time after the previous keyframe's"),
    ({"motion": {"keyframes": [{"time": 0, "angel": 1}]}},
     'motion: keyframes[0].angel: unknown field (did you mean "angle"?)'),
    ({"fps": 0.0}, "fps: expected a finite number > 0 (frames per second), got 0.0"),
    ({"duration": float("nan")}, "duration: expected a finite number > 0 (s), got nan"),
    ({"substeps": 0}, "substeps: expected an integer between 1 and 1000, got 0"),
    ({"integrator": "rk4"}, 'integrator: expected "backward_euler" or "bdf2", got "rk4"'),
    ({"model_tolerance": 1.0}, "model_tolerance: expected a number in [0, 1) (0 = Newton to the tolerance), got 1.0"),
    ({"model_tolerance": float("nan")}, "model_tolerance: expected a number in [0, 1)"),
    ({"mass_points": 9}, "mass_points: expected an integer in 1..8, got 9"),
    ({"pivot": [0, 0]}, "pivot: expected 3 finite numbers (m)"),
    ({"threads": -1}, "threads: expected"),
])
def test_bad_arguments_name_the_field(kwargs, message):
    with pytest.raises(ringlet.Error) as error:
        ringlet.simulate(SMALL_STYLE, **{"duration": 0.1, **kwargs})
    assert message in str(error.value)
    assert "\n" not in str(error.value)


def test_progress_reports_frames_and_its_exception_stops_the_simulation():
    seen = []
    ringlet.simulate(SMALL_STYLE, motion="nod", duration=0.25, progress=lambda d, t: seen.append((d, t)))
    assert seen[-1] == (7, 7) and all(t == 7 for _, t in seen)

    class Stop(Exception):
        pass

    def stop(done, total):
        raise Stop()
    with pytest.raises(Stop):
        ringlet.simulate(SMALL_STYLE, motion="nod", duration=600.0, progress=stop)


# A simulation far longer than the 2 s before the signal.
SCRIPT = textwrap.dedent("""
    import json, sys, time
    import ringlet
    style = json.loads(sys.argv[1])
    print("start", flush=True)
    try:
        ringlet.simulate(style, motion="walk", duration=3600.0, threads=1)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted %.6f" % time.time(), flush=True)
""")


def test_ctrl_c_interrupts_a_long_simulation():
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT, json.dumps(SMALL_STYLE)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ))
    try:
        assert proc.stdout.readline().strip() == "start"
        time.sleep(2.0)
        sent = time.time()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert out.startswith("interrupted"), (out, err)
    assert float(out.split()[1]) - sent < 2.0
