"""The example scripts of examples/python/ run (headless matplotlib) and write what they say."""
import os
import subprocess
import sys

import numpy as np

import ringlet
from conftest import EXAMPLES


def run(script, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, str(EXAMPLES / "python" / script), *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_solve_and_plot(tmp_path):
    out = tmp_path / "strand.png"
    run("solve_and_plot.py", EXAMPLES / "vertical_curly.json", out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 5000


def test_groom_cut_export(tmp_path, small_style):
    path, _ = small_style
    stdout = run("groom_cut_export.py", path, tmp_path / "out", "--cut-z", "-0.1")
    hair = ringlet.read_hair_file(str(tmp_path / "out" / "cut.hair"))
    # Cut below z = -0.1 m: the tips may rise after the cut, never hang below it (a settled
    # cut leaves them within the 0.5-mm tolerance of the plane; the wisps follow their masters
    # within their radius, a few mm).
    assert hair.points[:, 2].min() > -0.1 - 0.01
    assert (tmp_path / "out" / "cut.usda").read_text().startswith("#usda 1.0")
    assert "strands" in stdout


def test_invert_sweep(cli, tmp_path):
    # Targets: the 5 example strands' equilibria (ringlet solve, then invert's equilibrium.hair).
    cli("solve", EXAMPLES / "strands.json", "-o", tmp_path / "targets.json", "--quiet")
    cli("invert", tmp_path / "targets.json", "-o", tmp_path / "inv", "-q")
    stdout = run("invert_sweep.py", tmp_path / "inv" / "equilibrium.hair", "--strands", 5,
                 "--workers", 2)
    assert "inverted 5 strands" in stdout and "0 unstable" in stdout, stdout
    rows = [line.split() for line in stdout.splitlines() if line.strip()[:1].isdigit()]
    factors = [float(r[0]) for r in rows]
    sags = [float(r[1]) for r in rows]
    assert factors == [1.0, 0.8, 0.6, 0.4], stdout
    # Full stiffness is the reference itself (0); softer fibres sag more and more (the load
    # parameter rho S g L^3 / (E I) grows as E falls).
    assert sags[0] == 0.0 and 0.0 < sags[1] < sags[2] < sags[3], stdout
