"""Progress callbacks of ringlet.solve and ringlet.groom (issue 25, item 6): progress(done,
total) in the calling thread, counts that never go back, the last call (total, total), the
solved children counted after the masters, and an exception from the callback stopping the work
and raised again."""
import json
import threading
import time

import pytest

import ringlet
from conftest import EXAMPLES, SMALL_STYLE


def long_style():
    """300 curly masters of 20 segments: about 0.5 s on one thread, some 20 reports."""
    style = json.loads(json.dumps(SMALL_STYLE))
    style["masters"].update(count=300, segments=20)
    style["hair"].update(length=0.3, curl="curly")
    return style


def recorder():
    calls = []
    main = threading.get_ident()

    def progress(done, total):
        assert threading.get_ident() == main  # never from a worker thread
        calls.append((done, total))
    return calls, progress


def check_counts(calls, total):
    assert calls, "progress was never called"
    assert all(0 < done <= t <= total for done, t in calls), calls
    assert all(a <= b for a, b in zip(calls, calls[1:])), calls  # never backwards
    assert len(set(calls)) == len(calls), calls  # called when the counts change
    assert calls[-1] == (total, total)


def test_solve_reports_strands():
    calls, progress = recorder()
    model = ringlet.StrandModel(ringlet.uniform_segments(0.4, 150),
                                ringlet.CrossSection(4e-5, 3e-5), natural_curvature=(80, 0, 20))
    results = ringlet.solve([model] * 40, threads=1, progress=progress)
    check_counts(calls, 40)
    calls, progress = recorder()
    results = ringlet.solve(str(EXAMPLES / "strands.json"), threads=2, progress=progress)
    check_counts(calls, 5)
    # The same results as without a callback.
    plain = ringlet.solve(str(EXAMPLES / "strands.json"), threads=1)
    assert all(a.curvatures.tobytes() == b.curvatures.tobytes() for a, b in zip(results, plain))


def test_groom_reports_masters_then_solved_children(small_style):
    calls, progress = recorder()
    started = time.perf_counter()
    ringlet.groom(long_style(), threads=1, progress=progress)
    seconds = time.perf_counter() - started
    check_counts(calls, 300)
    assert len(calls) >= 3 and calls[0][0] < 300, calls  # reports while it works
    _, style = small_style
    style["wisps"]["children"] = "solved"
    calls, progress = recorder()
    groom = ringlet.groom(style, threads=2, progress=progress)
    children = groom.summary.children_solved
    assert children > 0
    check_counts(calls, groom.summary.masters + children)

    # An exception from the callback at its first report stops the groom there.
    calls = []

    def fails(done, total):
        calls.append((done, total))
        raise ZeroDivisionError("from the callback")
    started = time.perf_counter()
    with pytest.raises(ZeroDivisionError, match="from the callback"):
        ringlet.groom(long_style(), threads=1, progress=fails)
    assert len(calls) == 1 and calls[0][0] < 300, calls  # raised while it worked, not again
    # Stopped, not run to its end: well under the full groom (same process, same load).
    assert time.perf_counter() - started < 0.75 * seconds
    with pytest.raises(ZeroDivisionError, match="from the callback"):
        ringlet.solve(str(EXAMPLES / "strands.json"), progress=fails)


@pytest.mark.parametrize("function, argument", [
    (ringlet.solve, str(EXAMPLES / "strands.json")),
    (ringlet.groom, json.loads((EXAMPLES / "hairstyles" / "wavy.json").read_text())),
])
def test_a_progress_must_be_callable(function, argument):
    with pytest.raises(ringlet.Error) as error:
        function(argument, progress=3)
    assert str(error.value) == ("progress: expected None or a callable progress(done, total), "
                                "got int")
