"""The studio's view under load (issue 26, "a view that keeps up"; numbers in docs/benchmarks.md):
time to the first picture, frames per second while orbiting, idle CPU. Drives the real window
with xdotool (like tests/studio/drive_ui.py) and reads the studio's --report after each frame.

usage (from the repository root, under xvfb-run):
  xvfb-run -a -s "-screen 0 1280x800x24" python3 bench/studio_view_bench.py \
      build/studio/ringlet-studio examples/hairstyles/wavy.json [SHOTS_DIR]
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

STUDIO, HAIRSTYLE = os.path.abspath(sys.argv[1]), sys.argv[2]
SHOTS = sys.argv[3] if len(sys.argv) > 3 else None
WORK = tempfile.mkdtemp()
REPORT = os.path.join(WORK, "report.json")
TICK = os.sysconf("SC_CLK_TCK")


def xdo(*args):
    subprocess.run(["xdotool", *[str(a) for a in args]], check=True)


def report():
    while True:
        try:
            with open(REPORT) as f:
                return json.load(f)
        except (FileNotFoundError, json.JSONDecodeError):
            time.sleep(0.01)


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICK


def until(condition, timeout=300.0):
    end = time.time() + timeout
    while time.time() < end:
        if os.path.exists(REPORT):
            r = report()
            if condition(r):
                return r
        time.sleep(0.01)
    raise SystemExit("timed out")


def quiet(seconds=1.5):
    last, since = report()["frame"], time.time()
    while time.time() - since < seconds:
        time.sleep(0.05)
        frame = report()["frame"]
        if frame != last:
            last, since = frame, time.time()
    return report()


def main():
    env = dict(os.environ, LIBGL_ALWAYS_SOFTWARE="1")
    t0 = time.time()
    studio = subprocess.Popen([STUDIO, os.path.abspath(HAIRSTYLE), "--report", REPORT,
                               "--size", "1280x800"], cwd=WORK, env=env,
                              stderr=subprocess.DEVNULL)
    until(lambda r: r["frame"] >= 1)
    t_window = time.time() - t0
    r = until(lambda r: (r["strands"] > 0 or r.get("masters_preview")) and
              r["segments_drawn"] > 0)
    t_first = time.time() - t0
    masters_first = bool(r.get("masters_preview"))
    r = until(lambda r: r["strands"] > 0 and r["segments_drawn"] > 0)
    t_hair = time.time() - t0
    first = (r["segments_drawn"], r["segments_total"], r["preview"])
    r = until(lambda r: r["strands"] > 0 and not r["busy"] and not r["preview"] and
              r["segments_drawn"] == r["segments_total"])
    t_full = time.time() - t0
    cpu_open = cpu_seconds(studio.pid)
    print(f"first frame (panel, no hair) {t_window:.2f} s; first picture of hair {t_first:.2f} s "
          f"({'the masters being solved' if masters_first else 'the hair'}); "
          f"first picture of the solved hair {t_hair:.2f} s "
          f"({first[0]} of {first[1]} segments, preview {first[2]}); full density {t_full:.2f} s "
          f"(draw {r['draw_seconds']:.2f} s); CPU time of the studio so far {cpu_open:.2f} s",
          flush=True)
    r = quiet()
    if SHOTS:
        xdo("mousemove", 900, 400)
        time.sleep(0.3)
        xdo("key", "F12")
        time.sleep(0.5)
        quiet()
    # Orbit: the left button held in the view, the mouse moved 4 px every 25 ms for 5 s.
    xdo("mousemove", 700, 400)
    time.sleep(0.3)
    xdo("mousedown", 1)
    frame0, cpu0, t = report()["frame"], cpu_seconds(studio.pid), time.time()
    samples = []
    k = 0
    while time.time() - t < 5.0:
        k += 1
        xdo("mousemove", 700 + 4 * (k % 100), 400)
        time.sleep(0.025)
        r = report()
        samples.append((r["segments_drawn"], r["draw_seconds"], r["preview_budget"]))
        if SHOTS and k == 60:
            xdo("key", "F12")
    elapsed = time.time() - t
    frames = report()["frame"] - frame0
    cpu = cpu_seconds(studio.pid) - cpu0
    xdo("mouseup", 1)
    drawn = sorted(s[0] for s in samples)
    draws = sorted(s[1] for s in samples)
    print(f"orbit: {frames} frames in {elapsed:.2f} s = {frames / elapsed:.1f} fps; segments "
          f"drawn (median) {drawn[len(drawn) // 2]} of {r['segments_total']}; hair draw "
          f"(median) {draws[len(draws) // 2] * 1e3:.0f} ms; budget {samples[-1][2]}; studio CPU "
          f"{cpu:.2f} s in {elapsed:.2f} s", flush=True)
    r = quiet()
    print(f"after the orbit: full density {r['segments_drawn']} segments, draw "
          f"{r['draw_seconds']:.2f} s", flush=True)
    # Idle: nothing touched for 10 s.
    xdo("mousemove", 1270, 790)
    quiet()
    frame0, cpu0 = report()["frame"], cpu_seconds(studio.pid)
    time.sleep(10.0)
    cpu = cpu_seconds(studio.pid) - cpu0
    print(f"idle: {report()['frame'] - frame0} frames, {cpu:.2f} s CPU in 10 s "
          f"({cpu * 10:.1f} % of a core)", flush=True)
    with open("/proc/loadavg") as f:
        print("load average:", f.read().strip())
    studio.terminate()
    studio.wait(10)
    if SHOTS:
        os.makedirs(SHOTS, exist_ok=True)
        for name in sorted(os.listdir(WORK)):
            if name.startswith("studio-"):
                shutil.copy(os.path.join(WORK, name), os.path.join(SHOTS, "bench-" + name))
    shutil.rmtree(WORK)


main()
