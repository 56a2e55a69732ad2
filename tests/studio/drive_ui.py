"""Drives ringlet-studio through the X server's input (xdotool: XTEST mouse and key events), the
way a user does, and checks what the document, the view and the files became (issue 26).

Run under xvfb-run by tests/studio_input_test.sh. The studio runs with --report FILE (the
widgets' rectangles, the camera and the document after each frame: read only, never written by
the test) and --min-frame-seconds (slow frames: a click, a key tap or a whole drag then falls
inside one frame, as on a slow machine). Every value is set by mouse or keyboard events.

usage: drive_ui.py STUDIO RINGLET HAIRSTYLE WORKDIR SECTION
SECTION: sliders (defects 1 and 6), keys (3, 4, 6, 7), export (2), sculpt (the comb and puff
brushes), brushes (length, clump, frizz), session (a whole styling session, by hand on the
50,000-strand example: docs/studio.md) or view (the view that keeps up: the opening view, view keys, orbit with a tool on, headlight, preview density, the resizable
panel). With STUDIO_SHOTS=DIR set, the view section copies its screenshots (F12) there.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import time

STUDIO, RINGLET, HAIRSTYLE, WORK, SECTION = sys.argv[1:6]
REPORT = os.path.join(WORK, "report.json")
FRAME = 0.1           # --min-frame-seconds: slow frames
PANEL = 0             # the panel's width (px): from the report (30 em of the UI font)
FIELD = 0             # the width of a slider's frame (px): from the report (13 em)
failures = []


T0 = time.time()


def check(condition, what):
    print(f"{time.time() - T0:5.1f} s " + ("ok    " if condition else "FAIL  ") + what, flush=True)
    if not condition:
        failures.append(what)


def xdo(*args):
    subprocess.run(["xdotool", *[str(a) for a in args]], check=True)


def report():
    while True:
        try:
            with open(REPORT) as f:
                return json.load(f)
        except (FileNotFoundError, json.JSONDecodeError):
            time.sleep(0.02)


def quiet(timeout=30.0):
    """Waits until the studio draws no more frames (it redraws only when something changed):
    every event sent so far has been handled. Returns the report."""
    end = time.time() + timeout
    last, since = report()["frame"], time.time()
    while time.time() < end:
        time.sleep(0.05)
        frame = report()["frame"]
        if frame != last:
            last, since = frame, time.time()
        elif time.time() - since > 3 * FRAME + 0.3:
            return report()
    check(False, "the studio never stops drawing")
    raise SystemExit(finish())


def wait(condition, what, timeout=30.0):
    """Waits until condition(report) holds and the studio is quiet."""
    end = time.time() + timeout
    while time.time() < end:
        if condition(report()):
            print(f"{time.time() - T0:5.1f} s       ({what})", flush=True)
            return quiet()
        time.sleep(0.05)
    r = report()
    check(False, f"timed out waiting for {what} (message: {r['message']!r}, "
                 f"history: {r['history'][-3:]})")
    raise SystemExit(finish())


def settle(timeout=30.0):
    """Waits for the studio to be idle: no solve, the document's hair shown."""
    return wait(lambda r: not r["busy"] and r["up_to_date"] and r["strands"] > 0, "the solve",
                timeout)


def widget(name):
    return report()["widgets"][name]


def slider_x(rect, value, lo, hi):
    """The cursor x that sets a float slider (ImGui 1.86 SliderBehavior: 2 px grab padding,
    10 px grab) of [lo, hi] to value; its frame starts at the rectangle's left."""
    t = (value - lo) / (hi - lo)
    return rect[0] + 2 + 5 + t * (FIELD - 4 - 10)


def centre_y(rect):
    return (rect[1] + rect[3]) / 2


def click(x, y, button=1):
    if not 0 <= y < 800:
        check(False, f"a click at y = {y:.0f}: outside the window")
        raise SystemExit(finish())
    xdo("mousemove", int(round(x)), int(round(y)))
    time.sleep(2 * FRAME)  # the move is seen before the press (hover)
    xdo("click", button)


def field(r, name):
    """A field of the document by its dotted name (None when absent)."""
    value = r["document"]
    for key in name.split("."):
        if not isinstance(value, dict) or key not in value:
            return None
        value = value[key]
    return value


def reveal(name):
    """Scrolls the panel with the mouse wheel (over the panel) until the widget is in the window
    (the panel is taller than the window with the UI font)."""
    for _ in range(40):
        rect = widget(name)
        if rect[1] >= 30 and rect[3] <= 790:  # below the title bar, above the bottom
            return rect
        xdo("mousemove", 60, 400)
        time.sleep(2 * FRAME)
        xdo("click", 5 if rect[3] > 790 else 4)  # wheel down / up
        quiet()
    check(False, f"{name} never scrolled into the window: {widget(name)}")
    raise SystemExit(finish())


def centre(name):
    rect = reveal(name)
    return (rect[0] + rect[2]) / 2, (rect[1] + rect[3]) / 2


def drag_slider(name, start_x, end_x):
    """Presses on a slider at start_x, drags it to end_x in two moves a frame apart, releases."""
    y = int(centre_y(reveal(name)))
    xdo("mousemove", int(round(start_x)), y)
    time.sleep(2 * FRAME)
    xdo("mousedown", 1)
    time.sleep(FRAME)
    xdo("mousemove", int(round((start_x + end_x) / 2)), y)
    time.sleep(FRAME)
    xdo("mousemove", int(round(end_x)), y)
    time.sleep(2 * FRAME)
    xdo("mouseup", 1)


def type_into(name, text):
    """Clicks a text field, replaces its text and presses Enter."""
    rect = reveal(name)
    click(rect[0] + 20, centre_y(rect))
    quiet()  # the field is active before Ctrl+A selects its text
    xdo("key", "ctrl+a")
    xdo("type", text)
    xdo("key", "Return")
    quiet()


def outside_panel():
    """Controls (labels included) reaching under the panel's scrollbar (14 px) and padding (8 px),
    or beyond it; the collapsing headers span the whole width by design."""
    r = report()
    return [n for n, w in r["widgets"].items()
            if not n.startswith("header.") and (w[2] > r["panel_width"] - 16 or w[0] < 0)]


def finish():
    if studio.poll() is None:
        studio.terminate()
        try:
            studio.wait(10)
        except subprocess.TimeoutExpired:
            studio.kill()
    if failures:
        print(f"{len(failures)} failures:\n  " + "\n  ".join(failures))
        return 1
    print("studio input test: ok")
    return 0



def sliders():
    # Defect 1: a dragged document slider applies the value where it is released.
    before = field(report(), "hair.length.front")
    rect = widget("hair.length.front")
    drag_slider("hair.length.front", slider_x(rect, 0.20, 0.05, 0.8),
                slider_x(rect, 0.238, 0.05, 0.8))
    r = wait(lambda r: field(r, "hair.length.front") != before, "the dragged length")
    value = field(r, "hair.length.front")
    # One pixel of the slider is 0.75 / 166 = 0.0045 m.
    check(abs(value - 0.238) <= 0.005,
          f"length, front dragged from {before} to 0.238: {value}")
    check(abs(value * 1000 - round(value * 1000)) < 1e-9,
          f"the dragged value is stored with the slider's 3 decimals: {value!r}")
    check(r["history"][-1] == f"set hair.length.front = {json.dumps(value)}",
          f"History records the dragged value: {r['history'][-1]!r}")
    settle()
    # Typed: Ctrl+click turns the slider into a text field; "0.2" Enter stores 0.2 as typed.
    xdo("mousemove", int(rect[0] + 60), int(centre_y(rect)))
    time.sleep(2 * FRAME)
    xdo("keydown", "ctrl")
    xdo("click", 1)
    xdo("keyup", "ctrl")
    time.sleep(3 * FRAME)
    xdo("key", "ctrl+a")
    xdo("type", "0.2")
    xdo("key", "Return")
    r = wait(lambda r: field(r, "hair.length.front") == 0.2, "the typed length", timeout=15)
    check('"front": 0.2,' in json.dumps(r["document"]), "typed 0.2 is stored as 0.2")
    settle()
    # Save (the button, to the default name in the work directory) writes what was set; its
    # message line does not move the controls below.
    y_length = widget("hair.length.front")[1]
    click(*centre("Save"))
    r = wait(lambda r: not r["modified"], "the save")
    text = open(os.path.join(WORK, "styled.json")).read()
    check(json.loads(text)["hair"]["length"]["front"] == 0.2 and '"front": 0.2,' in text,
          "Save writes the typed value 0.2")
    check(r["message"].startswith("saved") and widget("hair.length.front")[1] == y_length,
          f"a message does not move the panel: y {widget('hair.length.front')[1]} vs {y_length}")
    # An integer slider (hair seed), and sliders under the collapsed headers (wisps, comb).
    rect = widget("hair.seed")
    before = field(report(), "hair.seed")
    drag_slider("hair.seed", rect[0] + 10, rect[0] + FIELD - 10)
    r = wait(lambda r: field(r, "hair.seed") != before, "the dragged hair seed")
    check(field(r, "hair.seed") >= 90, f"hair seed dragged to the right end: {field(r, 'hair.seed')}")
    settle()
    for header, name, lo, hi, target in (("header.masters", "wisps.tip_scale", 0.0, 2.0, 1.5),
                                         ("header.comb", "comb.tilt", 0.0, 1.5707, 0.6)):
        click(reveal(header)[0] + 40, centre_y(widget(header)))
        wait(lambda r: name in r["widgets"], f"the {name} slider")
        before = field(report(), name)
        rect = widget(name)
        drag_slider(name, slider_x(rect, (lo + hi) / 2, lo, hi), slider_x(rect, target, lo, hi))
        r = wait(lambda r: field(r, name) != before, f"the dragged {name}")
        step = (hi - lo) / (FIELD - 14)
        check(abs(field(r, name) - target) <= 1.5 * step,
              f"{name} dragged from {before} to {target}: {field(r, name)}")
        settle()
        # Defect 6: every control inside the panel, the wisp radius' auto button too.
        outside = outside_panel()
        check(not outside and (header != "header.masters" or "wisps.radius.auto" in
                               report()["widgets"]), f"controls outside the panel: {outside}")
        click(reveal(header)[0] + 40, centre_y(widget(header)))  # closed again
        wait(lambda r: name not in r["widgets"], f"{header} closed")


def keys():
    # Three edits to undo (hair seed dragged three times): a repeated undo would show.
    for end in (FIELD - 10, 60, 120):
        rect = widget("hair.seed")
        before = field(report(), "hair.seed")
        drag_slider("hair.seed", rect[0] + 30, rect[0] + end)
        wait(lambda r: field(r, "hair.seed") != before, "the dragged hair seed")
        settle()
    # Defect 4: taps shorter than a frame act once; holds do not repeat.
    cursor = report()["history_cursor"]
    xdo("mousemove", 900, 400)
    time.sleep(2 * FRAME)
    xdo("key", "ctrl+z")  # press and release within ~12 ms; a frame lasts >= 100 ms
    r = wait(lambda r: r["history_cursor"] != cursor, "Ctrl+Z", timeout=10)
    check(r["history_cursor"] == cursor - 1,
          f"a Ctrl+Z tap undoes one edit: {cursor} -> {r['history_cursor']}")
    settle()
    xdo("keydown", "ctrl+z")  # held for 1.2 s (key repeat after ~0.3 s)
    time.sleep(1.2)
    xdo("keyup", "ctrl+z")
    r = settle()
    check(r["history_cursor"] == cursor - 2, f"a held Ctrl+Z undoes one edit: {r['history_cursor']}")
    xdo("key", "ctrl+y")
    r = wait(lambda r: r["history_cursor"] != cursor - 2, "Ctrl+Y", timeout=10)
    check(r["history_cursor"] == cursor - 1, "a Ctrl+Y tap redoes one edit")
    settle()
    masters_only = report()["masters_only"]
    xdo("key", "m")
    wait(lambda r: r["masters_only"] != masters_only, "M", timeout=10)
    xdo("keydown", "m")
    time.sleep(0.3)
    samples = []
    for _ in range(10):  # 0.3 s to 1.3 s into the hold: key repeat would toggle it again
        time.sleep(0.1)
        samples.append(report()["masters_only"])
    xdo("keyup", "m")
    check(quiet()["masters_only"] == masters_only and samples == [masters_only] * 10,
          f"M tapped, then held: toggled once each (during the hold: {samples})")

    # Defect 3: drags measured from the press. The cursor comes from far away, presses and
    # moves 50 px inside one frame; frames later it moves 50 px more and releases.
    xdo("key", "f")  # frame all: the camera looks at the hair's centre
    c0 = quiet()["centre_on_screen"]
    xdo("mousemove", 700, 250)
    time.sleep(2 * FRAME)
    xdo("mousemove", 900, 500, "mousedown", 3, "mousemove", 950, 500)
    time.sleep(3 * FRAME)
    xdo("mousemove", 1000, 500, "mouseup", 3)
    r = quiet()
    c1 = r["centre_on_screen"]
    shift = (c1[0] - c0[0], c1[1] - c0[1])
    check(abs(shift[0] - 100) <= 2 and abs(shift[1]) <= 2,
          f"a 100 px pan moves the head 100 px: ({shift[0]:.1f}, {shift[1]:.1f}) px")
    pitch, yaw = r["camera"]["pitch"], r["camera"]["yaw"]
    xdo("mousemove", 800, 300)
    time.sleep(2 * FRAME)
    xdo("mousemove", 900, 450, "mousedown", 1, "mousemove", 960, 450)
    time.sleep(3 * FRAME)
    xdo("mousemove", 1000, 450, "mouseup", 1)
    r = quiet()
    check(r["camera"]["pitch"] == pitch,
          f"a horizontal orbit keeps the pitch: {pitch} -> {r['camera']['pitch']}")
    check(abs((r["camera"]["yaw"] - yaw) - (-100 * 0.008)) < 1e-4,
          f"a 100 px orbit turns by 0.8 rad: {r['camera']['yaw'] - yaw:.4f}")

    # Defect 6: the cut tool's rows do not move the controls below them.
    reveal("Grow")
    reveal("cut_tool.plane")
    y_cut, y_grow = widget("Cut below")[1], widget("Grow")[1]
    for tool in ("cut_tool.plane", "cut_tool.sphere", "cut_tool.plane"):
        click(*centre(tool))
        r = quiet()
        check(widget("Cut below")[1] == y_cut and widget("Grow")[1] == y_grow,
              f"with {tool}, the controls below stay: y {widget('Cut below')[1]} vs {y_cut}")
    # Defect 4: an Enter tap applies the cut tool's cut once; Ctrl+Z undoes it.
    xdo("mousemove", 900, 400)
    time.sleep(2 * FRAME)
    operations = report()["operations"]
    xdo("key", "Return")
    r = wait(lambda r: r["operations"] != operations, "Enter", timeout=10)
    check(r["operations"] == operations + 1, "an Enter tap applies one cut")
    xdo("key", "ctrl+z")
    r = wait(lambda r: r["operations"] == operations, "Ctrl+Z of the cut", timeout=10)
    click(*centre("cut_tool.off"))
    settle()

    # Defect 7: idle, no frame is drawn and no CPU is used.
    xdo("mousemove", 1270, 790)
    frame = quiet()["frame"]
    with open(f"/proc/{studio.pid}/stat") as f:
        ticks0 = sum(int(v) for v in f.read().rsplit(")", 1)[1].split()[11:13])
    time.sleep(2.0)
    with open(f"/proc/{studio.pid}/stat") as f:
        ticks1 = sum(int(v) for v in f.read().rsplit(")", 1)[1].split()[11:13])
    cpu = (ticks1 - ticks0) / os.sysconf("SC_CLK_TCK") / 2.0
    frames = report()["frame"] - frame
    check(frames == 0 and cpu < 0.03, f"idle: {frames} frames and {cpu * 100:.1f} % CPU in 2 s")


def export():
    # Defect 2: Export writes the bytes `ringlet style` writes for the saved document.
    history = len(report()["history"])
    click(*centre("Wet"))
    wait(lambda r: len(r["history"]) > history, "Wet")
    settle()
    for ext in ("hair", "usda", "obj"):
        path = os.path.join(WORK, f"export.{ext}")
        type_into("export_path", f"export.{ext}")  # the studio runs in WORK
        check(report()["export_path"] == f"export.{ext}",
              f"export file name typed: {report()['export_path']!r}")
        click(*centre("Export"))
        wait(lambda r: os.path.exists(path), f"export.{ext}")
    saved = os.path.join(WORK, "session.json")
    type_into("save_path", "session.json")
    check(report()["save_path"] == "session.json", f"save name typed: {report()['save_path']!r}")
    click(*centre("Save"))
    wait(lambda r: os.path.exists(saved) and not r["modified"], "the save")
    out = os.path.join(WORK, "styled")
    subprocess.run([RINGLET, "style", saved, "-o", out, "--formats", "hair,usda,obj", "-q"],
                   check=True)
    for ext in ("hair", "usda", "obj"):
        same = subprocess.run(["cmp", os.path.join(WORK, f"export.{ext}"),
                               os.path.join(out, f"strands.{ext}")]).returncode == 0
        check(same, f"Export .{ext} is `ringlet style`'s strands.{ext} byte for byte (cmp)")


def back_vector(camera):
    """From the target toward the camera (viewer.h OrbitCamera::Position)."""
    y, p = camera["yaw"], camera["pitch"]
    return (math.sin(y) * math.cos(p), -math.cos(y) * math.cos(p), math.sin(p))


def until(condition, what, timeout=10.0):
    """Waits until condition(report) holds (without waiting for the studio to be quiet)."""
    end = time.time() + timeout
    while time.time() < end:
        r = report()
        if condition(r):
            return r
        time.sleep(0.03)
    check(False, f"timed out waiting for {what}")
    raise SystemExit(finish())


def shot(name, always=False):
    """F12 saves the window as the next studio-NNN.png; kept under STUDIO_SHOTS as NAME.png.
    Only with STUDIO_SHOTS set, unless always."""
    if not always and not os.environ.get("STUDIO_SHOTS"):
        return None
    before = set(f for f in os.listdir(WORK) if f.startswith("studio-"))
    xdo("key", "F12")
    r = wait(lambda r: set(f for f in os.listdir(WORK) if f.startswith("studio-")) != before,
             f"the screenshot {name}", timeout=15)
    new = sorted(set(f for f in os.listdir(WORK) if f.startswith("studio-")) - before)
    check(len(new) == 1 and r["message"] == f"wrote {new[0]}", f"F12 wrote {new}")
    if os.environ.get("STUDIO_SHOTS") and new:
        shutil.copy(os.path.join(WORK, new[0]),
                    os.path.join(os.environ["STUDIO_SHOTS"], name + ".png"))
    return os.path.join(WORK, new[0]) if new else None


def view_light(path):
    """The light in the view of a screenshot: the mean over the view (right of the panel) of
    how much brighter than the background (viewer.cpp's clear colour) each pixel is."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from check_screenshots import read_png
    image = read_png(path).astype(float)
    view = image[:, int(report()["panel_width"]) + 10:, :]
    background = view[5:20, -20:-5, :].reshape(-1, 3).mean(axis=0)
    return float((view - background).clip(min=0).mean())


def drag(button, x0, y0, x1, y1, modifier=None):
    """A drag with this button from (x0, y0) to (x1, y1) in two moves, with a key held."""
    xdo("mousemove", x0, y0)
    time.sleep(2 * FRAME)
    if modifier:
        xdo("keydown", modifier)
        time.sleep(FRAME)
    xdo("mousedown", button)
    time.sleep(FRAME)
    xdo("mousemove", (x0 + x1) // 2, (y0 + y1) // 2)
    time.sleep(FRAME)
    xdo("mousemove", x1, y1)
    time.sleep(2 * FRAME)
    xdo("mouseup", button)
    if modifier:
        time.sleep(FRAME)
        xdo("keyup", modifier)
    return quiet()


def view():
    # The file opens facing the face: input.json places no render camera, so the view is the
    # render's framed one, along CameraSettings::view_direction = (-0.5, -1, -0.25) (from the
    # camera, render_json.h): the camera sits at +x, +y (the face's side), +z of the target.
    r = report()
    b = back_vector(r["camera"])
    n = math.sqrt(0.5 ** 2 + 1 + 0.25 ** 2)
    expected = (0.5 / n, 1 / n, 0.25 / n)
    check(sum(u * v for u, v in zip(b, expected)) > 1 - 1e-6 and b[1] > 0.8,
          f"opens facing the face, along the render's default view: {b} vs {expected}")
    shot("studio_open", always=True)
    # The view keys: 1 front, 3 right side, 7 top, with Ctrl the opposite (numpad-like).
    pi = math.pi
    for key, yaw, pitch in (("1", pi, 0.0), ("ctrl+1", 0.0, 0.0), ("3", pi / 2, 0.0),
                            ("ctrl+3", -pi / 2, 0.0), ("7", pi, 1.5), ("ctrl+7", pi, -1.5),
                            ("1", pi, 0.0)):
        xdo("key", key)
        r = until(lambda r: abs(r["camera"]["yaw"] - yaw) < 1e-5 and
                  abs(r["camera"]["pitch"] - pitch) < 1e-5, f"the view of key {key}", timeout=5)
        c = r["camera"]
        check(abs(c["yaw"] - yaw) < 1e-5 and abs(c["pitch"] - pitch) < 1e-5,
              f"key {key}: yaw {c['yaw']:.4f} (expected {yaw:.4f}), pitch {c['pitch']:.4f} "
              f"(expected {pitch})")
        if key in ("3", "7"):
            shot({"3": "studio_view_side", "7": "studio_view_top"}[key])
    # Alt+left drag orbits while the cut tool is on (the plane does not move); 0.008 rad per
    # pixel from the press (100 px: 0.8 rad), whatever the frame rate (slow frames here).
    click(*centre("cut_tool.plane"))
    r = quiet()
    yaw, pitch, height = r["camera"]["yaw"], r["camera"]["pitch"], r["plane_height"]
    r = drag(1, 900, 450, 1000, 450, "alt")
    check(abs(r["camera"]["yaw"] - yaw + 0.8) < 1e-4 and r["camera"]["pitch"] == pitch,
          f"Alt+left drag of 100 px with the cut tool on orbits by 0.8 rad: "
          f"{r['camera']['yaw'] - yaw:.4f}, pitch {pitch} -> {r['camera']['pitch']}")
    check(r["plane_height"] == height, f"... and leaves the cut plane: {height} -> "
          f"{r['plane_height']}")
    # A plain left drag with the cut tool on moves the plane, not the camera.
    yaw = r["camera"]["yaw"]
    r = drag(1, 900, 450, 900, 500)
    check(r["camera"]["yaw"] == yaw and r["plane_height"] < height,
          f"a left drag with the cut tool moves the plane: {height} -> {r['plane_height']}")
    click(*centre("cut_tool.off"))
    # Middle drag orbits while the brush is on (nothing is brushed); vertically: the pitch.
    click(*centre("brush"))
    r = wait(lambda r: True, "brush on")
    yaw, pitch = r["camera"]["yaw"], r["camera"]["pitch"]
    r = drag(2, 900, 400, 900, 350)
    check(abs(r["camera"]["pitch"] - pitch + 0.4) < 1e-4 and r["camera"]["yaw"] == yaw and
          r["brush"] == 0, f"a middle drag of 50 px up with the brush on pitches by -0.4 rad: "
          f"{r['camera']['pitch'] - pitch:.4f}, {r['brush']} masters brushed")
    click(*centre("brush"))
    xdo("key", "1")
    quiet()
    # The headlight (the light follows the camera): seen from the back (Ctrl+1), the key light
    # (the render's default, from the front and above) leaves the back in shade; the headlight
    # lights it.
    xdo("key", "ctrl+1")
    until(lambda r: abs(r["camera"]["yaw"]) < 1e-6, "the back view", timeout=5)
    quiet()
    off = view_light(shot("studio_back_key_light", always=True))
    click(*centre("headlight"))
    r = wait(lambda r: r["headlight"], "the headlight")
    on = view_light(shot("studio_headlight", always=True))
    check(on > 1.5 * off, f"from the back, the headlight lights the view: {off:.1f} -> {on:.1f} "
                          f"(mean brightening over the background)")
    click(*centre("headlight"))
    wait(lambda r: not r["headlight"], "the headlight off")
    xdo("key", "1")
    quiet()
    # The preview density (--preview-segments 1000; the 60 masters are 900 segments): while
    # the mouse orbits, the masters and 100 segments of children; full density once still.
    r = report()
    total, masters = r["segments_total"], r["master_segments"]
    check(masters < 1000 < total and r["segments_drawn"] == total and not r["preview"],
          f"still: every segment drawn ({r['segments_drawn']} of {total}, masters {masters})")
    xdo("mousemove", 900, 450)
    time.sleep(2 * FRAME)
    xdo("mousedown", 1)
    samples = []
    for k in range(6):
        xdo("mousemove", 900 + 10 * (k + 1), 450)
        time.sleep(FRAME)
        samples.append((report()["segments_drawn"], report()["preview"]))
    xdo("mouseup", 1)
    check(samples[-3:] == [(1000, True)] * 3,
          f"orbiting: the preview's 1000 segments drawn (samples {samples})")
    r = quiet()
    check(r["segments_drawn"] == total and not r["preview"],
          f"still again: every segment drawn ({r['segments_drawn']} of {total})")
    # The panel is resized by dragging its right edge (ImGui's window border): 100 px wider,
    # the view's centre 50 px to the right, every control still inside.
    r = report()
    width, cx = r["panel_width"], r["centre_on_screen"][0]
    x = int(round(width)) + 2
    r = drag(1, x, 400, x + 100, 400)
    check(abs(r["panel_width"] - (width + 100)) <= 2,
          f"the panel's edge dragged 100 px: {width} -> {r['panel_width']}")
    check(abs(r["centre_on_screen"][0] - (cx + (r["panel_width"] - width) / 2)) <= 1,
          f"the view follows the panel: centre x {cx} -> {r['centre_on_screen'][0]}")
    check(not outside_panel() and r["panel_content_width"] <= r["panel_inner_width"] + 0.5,
          f"every control inside the wider panel: {outside_panel()}, content "
          f"{r['panel_content_width']} of {r['panel_inner_width']} px")
    shot("studio_wide_panel")


def sculpt():
    # The sculpting brushes (issue 26's tools): a comb stroke dragged on the hair and a puff
    # clicked on the head, with mirror symmetry, each one operation of the document; the saved
    # file replayed by `ringlet style` gives Export's bytes.
    xdo("key", "3")  # the right side of the head: the hair hangs in view
    quiet()
    click(*centre("sculpt.comb"))
    r = quiet()
    check(r["sculpt_tool"] == 1, f"comb chosen by its radio button: tool {r['sculpt_tool']}")
    # A tip in the view, away from the panel and the window's edges, the lowest on screen.
    tips = [t for t in r["master_tips_on_screen"]
            if t and PANEL + 80 < t[0] < 1200 and 80 < t[1] < 720]
    check(len(tips) > 0, f"hair tips in the view: {len(tips)}")
    if not tips:
        return
    tip = max(tips, key=lambda t: t[1])
    history = len(r["history"])
    x0, y0 = int(round(tip[0])), int(round(tip[1]))
    r = drag(1, x0, y0, x0 + 60, y0 - 30)
    r = wait(lambda r: len(r["history"]) > history, "the comb stroke")
    settle()
    r = report()
    ops = r["document_operations"]
    check(len(ops) == 1 and "sculpt" in ops[0], f"one sculpt operation recorded: {ops}")
    if ops and "sculpt" in ops[0]:
        op = ops[0]["sculpt"]
        moved = math.dist(op["from"], op["to"])
        near = math.dist(op["from"], tip[2:5])
        check(op.get("mirror") is True and abs(op["radius"] - 0.03) < 1e-7,
              f"the panel's brush: mirror {op.get('mirror')}, radius {op['radius']}")
        check(near <= 0.03 + 1e-9, f"the stroke starts on the hair under the cursor: "
              f"{near * 1000:.1f} mm from the tip it was pressed on")
        check(0.005 < moved < 0.2, f"the stroke's length follows the drag: {moved * 1000:.1f} mm")
    shot("studio_comb")
    # Puff: a click on the head (its centre on screen) adds a puff of +15 degrees; Shift-click
    # flattens (-15).
    click(*centre("sculpt.puff"))
    r = quiet()
    hx, hy = r["head_on_screen"]
    for modifier, sign in ((None, 1), ("shift", -1)):
        history = len(report()["history"])
        xdo("mousemove", int(hx), int(hy))
        time.sleep(2 * FRAME)
        if modifier:
            xdo("keydown", modifier)
            time.sleep(FRAME)
        xdo("click", 1)
        if modifier:
            time.sleep(FRAME)
            xdo("keyup", modifier)
        wait(lambda r: len(r["history"]) > history, "the puff")
        settle()
        op = report()["document_operations"][-1]
        check("puff" in op and abs(op["puff"]["angle"] - sign * math.radians(15)) < 1e-6,
              f"a {'Shift-' if modifier else ''}click on the head: puff {op}")
    # A parting line drawn front to back on the side of the head facing the camera becomes
    # the comb's parting plane, vertical and across the drawn line: one edit of the document.
    click(*centre("sculpt.parting"))
    r = quiet()
    hx, hy = r["head_on_screen"]
    history = len(r["history"])
    drag(1, int(hx) - 25, int(hy) - 40, int(hx) + 25, int(hy) - 40)
    r = wait(lambda r: len(r["history"]) > history, "the parting")
    settle()
    parting = field(report(), "comb.parting")
    check(parting is not None and abs(parting["normal"][2]) < 1e-9 and
          abs(math.hypot(*parting["normal"]) - 1) < 1e-9,
          f"the drawn parting: a vertical plane through the line: {parting}")
    check(report()["history"][-1].startswith("set comb.parting"),
          f"one history entry: {report()['history'][-1]!r}")
    shot("studio_parting")
    # The file replays: `ringlet style` of the saved document writes Export's bytes.
    path = os.path.join(WORK, "export.hair")
    type_into("export_path", "export.hair")
    click(*centre("Export"))
    wait(lambda r: os.path.exists(path), "export.hair")
    saved = os.path.join(WORK, "sculpted.json")
    type_into("save_path", "sculpted.json")
    click(*centre("Save"))
    wait(lambda r: os.path.exists(saved) and not r["modified"], "the save")
    out = os.path.join(WORK, "styled")
    subprocess.run([RINGLET, "style", saved, "-o", out, "--formats", "hair", "-q"], check=True)
    same = subprocess.run(["cmp", path, os.path.join(out, "strands.hair")]).returncode == 0
    check(same, "the combed and puffed hair: Export is `ringlet style`'s strands.hair (cmp)")


def brushes():
    # The length, clump, frizz and curl brushes (issue 26): a click on the hair with each tool is one
    # operation of the document at the hair under the cursor, with the panel's brush and mirror;
    # Shift inverts (lengthen, unclump, smooth). `ringlet style` of the saved file reports that
    # each changed masters and writes Export's bytes.
    xdo("key", "3")  # the right side of the head: the hair hangs in view
    r = quiet()
    tips = [t for t in r["master_tips_on_screen"]
            if t and PANEL + 80 < t[0] < 1200 and 80 < t[1] < 720]
    check(len(tips) > 0, f"hair tips in the view: {len(tips)}")
    if not tips:
        return
    tip = max(tips, key=lambda t: t[1])
    hx, hy = r["head_on_screen"]
    clicks = (("sculpt.length", None, tip, "length", "factor", 0.8),
              ("sculpt.length", "shift", None, "length", "factor", 1 / 0.8),
              ("sculpt.clump", None, None, "clump", "factor", 0.6),
              ("sculpt.clump", "shift", None, "clump", "factor", 1 / 0.6),
              ("sculpt.frizz", None, None, "frizz", "amplitude", 0.003),
              ("sculpt.curl", None, None, "curl", "radius", 0.008))
    tool = None
    for count, (name, modifier, at, kind, key, value) in enumerate(clicks, 1):
        if name != tool:
            click(*centre(name))
            r = quiet()
            tool = name
            check(r["sculpt_tool"] == {"sculpt.length": 4, "sculpt.clump": 5,
                                       "sculpt.frizz": 6, "sculpt.curl": 7}[name],
                  f"{kind} chosen by its radio button: tool {r['sculpt_tool']}")
        history = len(report()["history"])
        x, y = (at[0], at[1]) if at else (hx, hy - 40)
        xdo("mousemove", int(round(x)), int(round(y)))
        time.sleep(2 * FRAME)
        if modifier:
            xdo("keydown", modifier)
            time.sleep(FRAME)
        xdo("click", 1)
        if modifier:
            time.sleep(FRAME)
            xdo("keyup", modifier)
        wait(lambda r: len(r["history"]) > history, f"the {kind} click")
        settle()
        ops = report()["document_operations"]
        op = ops[-1].get(kind) if ops else None
        # The curl brush's own fields are in "brush" (its "radius" is the helix's).
        brush = (op.get("brush") if kind == "curl" else op) if op else None
        check(op is not None and brush is not None and abs(op[key] - value) < 1e-9 and
              brush.get("mirror") is True and abs(brush["radius"] - 0.03) < 1e-7 and
              len(ops) == count,
              f"a {'Shift-' if modifier else ''}click: one {kind} operation, {key} {value:.4g}: "
              f"{ops[-1] if ops else None}")
        if op and at:
            near = math.dist(op["centre"], at[2:5])
            check(near <= 0.03 + 1e-9, f"the {kind} brush on the hair under the cursor: "
                  f"{near * 1000:.1f} mm from the tip clicked")
    shot("studio_brushes")
    # The file replays: `ringlet style` of the saved document writes Export's bytes, and each
    # brush changed some masters.
    path = os.path.join(WORK, "export.hair")
    type_into("export_path", "export.hair")
    click(*centre("Export"))
    wait(lambda r: os.path.exists(path), "export.hair")
    saved = os.path.join(WORK, "brushed.json")
    type_into("save_path", "brushed.json")
    click(*centre("Save"))
    wait(lambda r: os.path.exists(saved) and not r["modified"], "the save")
    out = os.path.join(WORK, "styled")
    run = subprocess.run([RINGLET, "style", saved, "-o", out, "--formats", "hair,json"],
                         check=True, capture_output=True, text=True)
    with open(os.path.join(out, "masters.json")) as f:
        done = json.load(f)["style"]["operations"]
    check([o["name"] for o in done] == ["length", "length", "clump", "clump", "frizz", "curl"] and
          all(o["strands"] > 0 for o in done),
          "the replay: each brush changed masters: " +
          ", ".join(f"{o['name']} {o['strands']}" for o in done))
    same = subprocess.run(["cmp", path, os.path.join(out, "strands.hair")]).returncode == 0
    check(same, "the brushed hair: Export is `ringlet style`'s strands.hair (cmp)")


def session():
    # A whole styling session with the mouse (issue 26's "done when"), meant for the 50,000-strand
    # example by hand (docs/studio.md; too slow for CI, whose sections test each step on a small
    # head): drag a slider, comb, cut, curl, wet, dry, save; `ringlet style` of the saved file
    # gives Export's bytes. Prints how long each step took from the input to the solved hair.
    long = 600.0
    times = []

    def step(what, action):
        history = len(report()["history"])
        start = time.time()
        action()
        wait(lambda r: len(r["history"]) > history, what, timeout=long)
        r = wait(lambda r: not r["busy"] and r["up_to_date"] and r["strands"] > 0,
                 f"{what}: the hair", timeout=long)
        times.append((what, time.time() - start))
        print(f"step {what}: {times[-1][1]:.1f} s to the solved hair; {r['strands']} strands, "
              f"history {r['history'][-1]!r}", flush=True)
        return r

    def drag_length():
        rect = reveal("hair.length.front")
        value = field(report(), "hair.length.front")
        drag_slider("hair.length.front", slider_x(rect, value, 0.05, 0.8),
                    slider_x(rect, value + 0.03, 0.05, 0.8))
    before = field(report(), "hair.length.front")
    r = step("drag length, front +0.03 m", drag_length)
    check(abs(field(r, "hair.length.front") - (before + 0.03)) <= 0.005,
          f"length, front dragged from {before}: {field(r, 'hair.length.front')}")
    xdo("key", "3")  # the right side of the head: the hair hangs in view
    quiet()
    click(*centre("sculpt.comb"))
    r = quiet()
    tips = [t for t in r["master_tips_on_screen"]
            if t and PANEL + 80 < t[0] < 1200 and 80 < t[1] < 720]
    check(len(tips) > 0, f"hair tips in the view: {len(tips)}")
    if tips:
        tip = max(tips, key=lambda t: t[1])
        x0, y0 = int(round(tip[0])), int(round(tip[1]))
        step("comb stroke", lambda: drag(1, x0, y0, x0 + 60, y0 - 30))
    click(*centre("sculpt.off"))
    quiet()
    for name in ("Cut below", "Curl", "Wet", "Dry"):
        step(name, lambda name=name: click(*centre(name)))
    shot("studio_session")
    kinds = [next(iter(op)) for op in report()["document_operations"]]
    check(kinds == (["sculpt"] if tips else []) + ["cut", "curl", "wet", "dry"],
          f"the document's operations: {kinds}")
    path = os.path.join(WORK, "export.hair")
    type_into("export_path", "export.hair")
    click(*centre("Export"))
    wait(lambda r: os.path.exists(path), "export.hair", timeout=long)
    saved = os.path.join(WORK, "session.json")
    type_into("save_path", "session.json")
    click(*centre("Save"))
    wait(lambda r: os.path.exists(saved) and not r["modified"], "the save", timeout=long)
    out = os.path.join(WORK, "styled")
    start = time.time()
    subprocess.run([RINGLET, "style", saved, "-o", out, "--formats", "hair", "-q"], check=True)
    print(f"ringlet style of the saved session: {time.time() - start:.1f} s", flush=True)
    same = subprocess.run(["cmp", path, os.path.join(out, "strands.hair")]).returncode == 0
    check(same, "the session's hair: Export is `ringlet style`'s strands.hair (cmp)")
    print("session steps: " + "; ".join(f"{w} {t:.1f} s" for w, t in times))


os.chdir(WORK)
extra = ["--preview-segments", "1000"] if SECTION == "view" else []
studio = subprocess.Popen([STUDIO, HAIRSTYLE, "--report", REPORT, "--size", "1280x800",
                           "--min-frame-seconds", str(FRAME), *extra])
r = settle(600.0 if SECTION == "session" else 30.0)
PANEL, FIELD = r["panel_width"], r["field_width"]
print(f"opened and solved in {time.time() - T0:.1f} s: {r['strands']} strands; "
      f"font {r['font_size']} px, panel {PANEL} px")
xdo("mousemove", 900, 400)  # the pointer over the window: it has the keyboard focus
time.sleep(2 * FRAME)
{"sliders": sliders, "keys": keys, "export": export, "view": view,
 "sculpt": sculpt, "brushes": brushes, "session": session}[SECTION]()
sys.exit(finish())
