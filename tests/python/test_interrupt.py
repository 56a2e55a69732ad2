"""Ctrl-C: a long groom in a subprocess gets SIGINT and raises KeyboardInterrupt promptly (the
GIL is released, the worker's solve is cancelled between strands)."""
import os
import signal
import subprocess
import sys
import textwrap
import time

from conftest import EXAMPLES

# Grooms wavy.json with 20,000 masters on one thread: about a minute of solving, far longer
# than the wait below, so an interrupt that is not honoured shows as a timeout.
SCRIPT = textwrap.dedent("""
    import json, sys, time
    import ringlet
    style = json.load(open(sys.argv[1]))
    style["masters"]["count"] = 20000
    style["wisps"]["strands_per_wisp"] = 2
    print("start", flush=True)
    t = time.monotonic()
    try:
        ringlet.groom(style, threads=1, base_directory=sys.argv[2])
        print("finished %.2f" % (time.monotonic() - t), flush=True)
    except KeyboardInterrupt:
        print("interrupted %.2f" % (time.monotonic() - t), flush=True)
""")


def test_ctrl_c_interrupts_a_long_groom(tmp_path):
    wavy = EXAMPLES / "hairstyles" / "wavy.json"
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT, str(wavy), str(wavy.parent)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ))
    try:
        assert proc.stdout.readline().strip() == "start"
        time.sleep(1.5)  # into the master solve (root sampling takes a fraction of this)
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=20)
        waited = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert out.startswith("interrupted"), (out, err)
    # Promptly: strands are short solves; the 20-ms signal poll and the strands in flight.
    assert waited < 3.0, waited
