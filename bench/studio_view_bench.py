"""The studio's view under load (issue 26, "a view that keeps up"; numbers in docs/benchmarks.md):
time to the first picture, frames per second while orbiting, idle CPU. Drives the real window
with xdotool (like tests/studio/drive_ui.py) and reads the studio's --report after each frame.

usage (from the repository root; xvfb-run gives it an X server with Mesa's llvmpipe):
  xvfb-run -a -s "-screen 0 1280x800x24" python3 bench/studio_view_bench.py \
      build/studio/ringlet-studio examples/hairstyles/wavy.json [--shots DIR] \
      [--perf-open FILE] [--perf-orbit FILE] [--perf-call-graph fp|dwarf] [--json FILE]
      [--orbit-seconds S] [--timeout S] [--no-edit]

  --shots DIR        F12 screenshots of the opened view and of the orbit, copied to DIR
  --perf-open FILE   `perf record` the studio from launch to the first picture of hair
  --perf-orbit FILE  `perf record` the studio during the orbit
  --json FILE        the numbers as JSON (wall times, the studio's CPU times, load averages)

Phases: launch to the first frame, the first picture of hair (the masters being solved), the
solved hair, full density; an orbit (left drag) for --orbit-seconds; 10 s idle; then (unless
--no-edit) the "length, front" slider dragged +0.03 m: the re-solved masters streamed to the
view, then the hair.

Every number is printed with the studio's CPU time (user + system, /proc/PID/stat) beside the
wall time: on a shared machine the wall times measure the load, the CPU times the studio. The
load average is printed at the start and at the end. Exit status 0 when every phase was reached
(whether or not the targets were met), 1 with a message when one timed out.
"""
import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

TICK = os.sysconf("SC_CLK_TCK")


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("studio")
    p.add_argument("hairstyle")
    p.add_argument("shots_dir", nargs="?", help="(old form of --shots)")
    p.add_argument("--shots")
    p.add_argument("--perf-open")
    p.add_argument("--perf-orbit")
    p.add_argument("--perf-call-graph", default="fp",
                   help="perf's --call-graph (fp, or dwarf for the frames of Mesa and libc)")
    p.add_argument("--json")
    p.add_argument("--orbit-seconds", type=float, default=5.0)
    p.add_argument("--no-edit", action="store_true",
                   help="skip the last phase (a slider dragged: the edit's masters streamed)")
    p.add_argument("--timeout", type=float, default=600.0,
                   help="seconds allowed for each phase (default 600: a loaded machine)")
    a = p.parse_args()
    a.shots = a.shots or a.shots_dir
    return a


ARGS = parse_args()
STUDIO, HAIRSTYLE = os.path.abspath(ARGS.studio), os.path.abspath(ARGS.hairstyle)
WORK = tempfile.mkdtemp()
REPORT = os.path.join(WORK, "report.json")


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


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def until(condition, what, studio):
    end = time.time() + ARGS.timeout
    while time.time() < end:
        if studio.poll() is not None:
            raise SystemExit(f"the studio exited ({studio.returncode}) waiting for {what}")
        if os.path.exists(REPORT):
            r = report()
            if condition(r):
                return r
        time.sleep(0.01)
    raise SystemExit(f"timed out after {ARGS.timeout:.0f} s waiting for {what}")


def settled(r):
    """The solved hair at full density, nothing running, nothing left to draw."""
    return (r["strands"] > 0 and not r["busy"] and not r["preview"] and not r["refining"] and
            r["segments_drawn"] == r["segments_total"])


def quiet(studio, seconds=1.0):
    """Waits for the full-density picture, then for `seconds` without a frame."""
    until(settled, "the full-density picture", studio)
    last, since = report()["frame"], time.time()
    while time.time() - since < seconds:
        time.sleep(0.05)
        frame = report()["frame"]
        if frame != last:
            last, since = frame, time.time()
    return report()


def perf_start(path, pid):
    return subprocess.Popen(["perf", "record", "-q", "-F", "499", "--call-graph",
                             ARGS.perf_call_graph, "-o", path, "-p", str(pid)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def perf_stop(perf):
    perf.send_signal(signal.SIGINT)
    perf.wait(60)


def edit(studio, out):
    """A slider dragged through the X server (length, front: 0.05-0.8 m, from its value to
    +0.03 m): the time from the release to the edit's first masters on screen (streamed while
    they are re-solved, Session::Preview; none when the solve takes less than the preview
    period), to the hair, and to full density."""
    r = report()
    rect = r["widgets"].get("hair.length.front")
    value = r["document"].get("hair", {}).get("length", {})
    if not rect or not isinstance(value, dict) or "front" not in value:
        print("edit: skipped (no hair.length.front slider)", flush=True)
        return
    width = r["field_width"]
    x_of = lambda v: rect[0] + 7 + (v - 0.05) / 0.75 * (width - 14)
    y = int((rect[1] + rect[3]) / 2)
    cursor = r["history_cursor"]
    x0, x1 = x_of(value["front"]), x_of(value["front"] + 0.03)
    xdo("mousemove", int(round(x0)), y)
    time.sleep(0.3)
    xdo("mousedown", 1)
    time.sleep(0.2)
    xdo("mousemove", int(round((x0 + x1) / 2)), y)
    time.sleep(0.2)
    xdo("mousemove", int(round(x1)), y)
    time.sleep(0.3)
    cpu0 = cpu_seconds(studio.pid)
    xdo("mouseup", 1)
    t = time.time()
    first_masters = None
    end = time.time() + ARGS.timeout
    while time.time() < end:
        r = report()
        if r["history_cursor"] > cursor and r.get("masters_preview") and first_masters is None:
            first_masters = (time.time() - t, cpu_seconds(studio.pid) - cpu0)
        if (r["history_cursor"] > cursor and not r["busy"] and r["up_to_date"] and
                r["strands"] > 0):
            break
        time.sleep(0.01)
    else:
        raise SystemExit("timed out waiting for the edit's hair")
    hair = (time.time() - t, cpu_seconds(studio.pid) - cpu0)
    stats = r["history"][-1]
    until(settled, "the edit's full-density picture", studio)
    full = (time.time() - t, cpu_seconds(studio.pid) - cpu0)
    out["edit"] = {"what": stats, "first_masters": first_masters, "hair": hair, "full": full}
    masters = (f"{first_masters[0]:.2f} s (CPU {first_masters[1]:.2f} s)" if first_masters
               else "none (solved within the preview period)")
    print(f"edit ({stats}): the re-solved masters on screen {masters}; the hair "
          f"{hair[0]:.2f} s (CPU {hair[1]:.2f} s); full density {full[0]:.2f} s "
          f"(CPU {full[1]:.2f} s) after the release", flush=True)


def main():
    env = dict(os.environ, LIBGL_ALWAYS_SOFTWARE="1")
    out = {"load_start": loadavg(), "hairstyle": ARGS.hairstyle}
    print("load average at the start:", out["load_start"], flush=True)
    t0 = time.time()
    studio = subprocess.Popen([STUDIO, HAIRSTYLE, "--report", REPORT, "--size", "1280x800"],
                              cwd=WORK, env=env, stderr=subprocess.DEVNULL)
    perf = perf_start(ARGS.perf_open, studio.pid) if ARGS.perf_open else None
    until(lambda r: r["frame"] >= 1, "the first frame", studio)
    out["first_frame"] = [time.time() - t0, cpu_seconds(studio.pid)]
    r = until(lambda r: (r["strands"] > 0 or r.get("masters_preview")) and
              r["segments_drawn"] > 0, "the first picture of hair", studio)
    out["first_hair"] = [time.time() - t0, cpu_seconds(studio.pid)]
    masters_first = bool(r.get("masters_preview"))
    if perf:
        perf_stop(perf)
    r = until(lambda r: r["strands"] > 0 and r["segments_drawn"] > 0, "the solved hair", studio)
    out["solved_hair"] = [time.time() - t0, cpu_seconds(studio.pid)]
    first = (r["segments_drawn"], r["segments_total"], r["preview"])
    r = until(settled, "the full-density picture", studio)
    out["full_density"] = [time.time() - t0, cpu_seconds(studio.pid)]
    out["startup"] = r.get("startup")
    print(f"first frame (panel) {out['first_frame'][0]:.2f} s (studio CPU "
          f"{out['first_frame'][1]:.2f} s); first picture of hair {out['first_hair'][0]:.2f} s "
          f"(CPU {out['first_hair'][1]:.2f} s; "
          f"{'the masters being solved' if masters_first else 'the hair'}); the solved hair "
          f"{out['solved_hair'][0]:.2f} s (CPU {out['solved_hair'][1]:.2f} s; {first[0]} of "
          f"{first[1]} segments, preview {first[2]}); full density {out['full_density'][0]:.2f} s "
          f"(CPU {out['full_density'][1]:.2f} s)", flush=True)
    if r.get("startup"):
        print("studio phases (wall s, CPU s of the process):",
              json.dumps(r["startup"]), flush=True)
    r = quiet(studio)
    if ARGS.shots:
        xdo("mousemove", 900, 400)
        time.sleep(0.3)
        xdo("key", "F12")
        time.sleep(0.5)
        quiet(studio)
    # Orbit: the left button held in the view, the mouse moved 4 px every 25 ms.
    xdo("mousemove", 700, 400)
    time.sleep(0.3)
    quiet(studio)
    perf = perf_start(ARGS.perf_orbit, studio.pid) if ARGS.perf_orbit else None
    xdo("mousedown", 1)
    frame0, cpu0, t = report()["frame"], cpu_seconds(studio.pid), time.time()
    samples = []
    k = 0
    while time.time() - t < ARGS.orbit_seconds:
        k += 1
        xdo("mousemove", 700 + 4 * (k % 100), 400)
        time.sleep(0.025)
        r = report()
        samples.append((r["segments_drawn"], r["draw_seconds"], r["preview_budget"],
                        r.get("frame_cpu_seconds", 0.0)))
        if ARGS.shots and k == 20:
            xdo("key", "F12")
    elapsed = time.time() - t
    frames = report()["frame"] - frame0
    cpu = cpu_seconds(studio.pid) - cpu0
    xdo("mouseup", 1)
    if perf:
        perf_stop(perf)
    median = lambda i: sorted(s[i] for s in samples)[len(samples) // 2]
    out["orbit"] = {"frames": frames, "seconds": elapsed, "fps": frames / elapsed,
                    "cpu_seconds": cpu, "cpu_per_frame": cpu / max(1, frames),
                    "segments": median(0), "draw_seconds": median(1),
                    "frame_cpu_seconds": median(3), "budget": samples[-1][2]}
    print(f"orbit: {frames} frames in {elapsed:.2f} s = {frames / elapsed:.1f} fps; segments "
          f"drawn (median) {median(0)} of {r['segments_total']}; view draw (median) "
          f"{median(1) * 1e3:.0f} ms; UI thread CPU per frame (median) {median(3) * 1e3:.0f} ms; "
          f"budget {samples[-1][2]}; studio CPU {cpu:.2f} s in {elapsed:.2f} s "
          f"({cpu / max(1, frames) * 1e3:.0f} ms per frame)", flush=True)
    t = time.time()
    r = quiet(studio)
    print(f"after the orbit: full density ({r['segments_drawn']} segments) "
          f"{time.time() - t:.2f} s after the release (including 1 s without frames)", flush=True)
    # Idle: nothing touched for 10 s.
    xdo("mousemove", 1270, 790)
    quiet(studio)
    frame0, cpu0 = report()["frame"], cpu_seconds(studio.pid)
    time.sleep(10.0)
    cpu = cpu_seconds(studio.pid) - cpu0
    out["idle"] = {"frames": report()["frame"] - frame0, "cpu_seconds": cpu,
                   "percent": cpu * 10.0}
    print(f"idle: {out['idle']['frames']} frames, {cpu:.2f} s CPU in 10 s "
          f"({cpu * 10:.1f} % of a core)", flush=True)
    if not ARGS.no_edit:
        edit(studio, out)
    out["load_end"] = loadavg()
    print("load average at the end:", out["load_end"], flush=True)
    studio.terminate()
    studio.wait(10)
    if ARGS.shots:
        os.makedirs(ARGS.shots, exist_ok=True)
        for name in sorted(os.listdir(WORK)):
            if name.startswith("studio-"):
                shutil.copy(os.path.join(WORK, name), os.path.join(ARGS.shots, "bench-" + name))
    if ARGS.json:
        with open(ARGS.json, "w") as f:
            json.dump(out, f, indent=1)
    shutil.rmtree(WORK)


main()
