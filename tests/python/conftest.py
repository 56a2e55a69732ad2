"""Fixtures of the Python module's tests (docs/python.md): the module, the `ringlet` command
(the C++ reference every number is compared with), the source tree and a small hairstyle.

Run by ctest (`ctest -R python`) with PYTHONPATH=build/python, RINGLET=build/ringlet and
RINGLET_SOURCE_DIR set; by hand:
  PYTHONPATH=build/python RINGLET=build/ringlet /usr/bin/python3 -m pytest tests/python
"""
import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("RINGLET_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE_DIR / "examples"


@pytest.fixture(scope="session")
def cli():
    """Runs the `ringlet` command: cli("solve", ...) -> CompletedProcess (text)."""
    path = os.environ.get("RINGLET", str(SOURCE_DIR / "build" / "ringlet"))
    if not os.path.exists(path):
        pytest.fail("the ringlet command is needed as the reference: set RINGLET (%s)" % path)

    def run(*args, check=True):
        done = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        if check and done.returncode != 0:
            raise AssertionError("ringlet %s: exit %d: %s" % (" ".join(map(str, args)),
                                                              done.returncode, done.stderr))
        return done
    return run


def cli_error(done):
    """The message of the command's one error line ("ringlet: error: MESSAGE")."""
    lines = [l for l in done.stderr.splitlines() if l.startswith("ringlet: error: ")]
    assert done.returncode == 1 and len(lines) == 1, (done.returncode, done.stderr)
    return lines[0][len("ringlet: error: "):]


# The small hairstyle of tests/cli_groom_test.sh: 12 masters of 8 segments, 3 strands of 8 points
# per wisp (36 strands, 288 points), with an absolute body path so it can live anywhere.
SMALL_STYLE = {
    "description": "python tests: a small head of hair",
    "body": str(EXAMPLES / "bodies" / "mannequin.json"),
    "masters": {"count": 12, "seed": 4, "segments": 8, "points_per_segment": 2},
    "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.15, "seed": 2},
    "wisps": {"strands_per_wisp": 3, "points_per_strand": 8},
    "layers": {"count": 3, "thickness": 0.003},
}


@pytest.fixture
def small_style(tmp_path):
    """(path, dict) of the small hairstyle written to a temporary file."""
    path = tmp_path / "small.json"
    path.write_text(json.dumps(SMALL_STYLE, indent=1))
    return path, json.loads(json.dumps(SMALL_STYLE))
