#!/usr/bin/env bash
# The command-line contract of `ringlet simulate` (docs/dynamics.md): a small hairstyle shaken
# for 1.5 s at 24 fps writes one time-sampled hair.usda and frames.jsonl; the same bytes on 1 and
# 2 threads and on a second run; the USD stage's time codes and every sample's point count; the
# tips move with the shake and come back toward rest once it is over; a scene of single strands;
# --hair-per-frame; --render (PNG frames, hair.mp4 through ffmpeg or a clear warning without
# it); bad options and motion files give one line naming the field, exit code 1 and no output
# directory; SIGINT and SIGTERM during the run leave neither OUTDIR nor its staging directory;
# --force replaces an existing OUTDIR's files only at the end (an interrupt keeps them); a full
# disk gives one line and leaves nothing.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_simulate`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_simulate.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/styles/bodies"
cp "$EXAMPLES/bodies/mannequin.json" "$work/styles/bodies/mannequin.json"

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

# 6 masters of 8 segments, 3 strands of 8 points per wisp: 18 strands, 144 points per frame.
cat >"$work/styles/small.json" <<EOF
{
  "description": "cli_simulate_test: a small head of hair",
  "body": "bodies/mannequin.json",
  "masters": {"count": 6, "seed": 4, "segments": 8, "points_per_segment": 2},
  "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.15, "seed": 2},
  "wisps": {"strands_per_wisp": 3, "points_per_strand": 8},
  "layers": {"count": 3, "thickness": 0.003}
}
EOF
SMALL="$work/styles/small.json"

# --- a shake: outputs, determinism -------------------------------------------------------------
run simulate "$SMALL" -o "$work/a" --motion shake --duration 1.5 --fps 24 --threads 1
expect_rc "shake" 0
expect_files "shake" "$work/a" hair.usda frames.jsonl
if grep -q "^simulated 6 strands (shake motion) for 37 frames at 24 fps: [0-9]* Newton iterations, 0 halved steps in 0 frames, 0 frames with failed steps" "$work/stdout"; then ok; else
  fail "shake: summary line: $(cat "$work/stdout")"
fi
run simulate "$SMALL" -o "$work/b" --motion shake --duration 1.5 --fps 24 --threads 2
expect_rc "shake, 2 threads" 0
for f in hair.usda frames.jsonl; do
  if cmp -s "$work/a/$f" "$work/b/$f"; then ok; else fail "$f differs between 1 and 2 threads"; fi
done
run simulate "$SMALL" -o "$work/b" --motion shake --duration 1.5 --fps 24 --threads 1 --force
expect_rc "shake again (--force)" 0
for f in hair.usda frames.jsonl; do
  if cmp -s "$work/a/$f" "$work/b/$f"; then ok; else fail "$f differs between two runs"; fi
done
run simulate "$SMALL" -o "$work/b" --motion shake --duration 1.5
expect_rc "existing outputs without --force" 1
expect_one_error_line "existing outputs without --force" "already exists"

# The stage and its samples, read by an independent parser of the usda text; the tips' motion.
if "$PYTHON" - "$work/a" 37 24 144 <<'EOF' >"$work/check" 2>&1; then ok; else
import json, math, re, sys
out, frames, fps, points = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
text = open(out + "/hair.usda").read()
errors = []
def meta(name):
    m = re.search(r"^\s+%s = ([0-9.e+-]+)$" % name, text, re.M)
    return float(m.group(1)) if m else None
for name, want in [("startTimeCode", 0), ("endTimeCode", frames - 1),
                   ("timeCodesPerSecond", fps), ("framesPerSecond", fps)]:
    if meta(name) != want:
        errors.append("%s = %s, expected %s" % (name, meta(name), want))
counts = re.search(r"int\[\] curveVertexCounts = \[([^\]]*)\]", text)
counts = [int(c) for c in counts.group(1).split(",")]
if sum(counts) != points or len(counts) != 18:
    errors.append("curveVertexCounts: %d curves, %d points; expected 18, %d" % (len(counts), sum(counts), points))
block = re.search(r"point3f\[\] points\.timeSamples = \{\n(.*?)\n    \}", text, re.S).group(1)
samples = {}
for line in block.split("\n"):
    m = re.match(r"\s+(\d+): \[(.*)\],$", line)
    if not m:
        errors.append("unexpected line in points.timeSamples: " + line[:80])
        continue
    tuples = re.findall(r"\(([^)]*)\)", m.group(2))
    samples[int(m.group(1))] = [tuple(float(v) for v in t.split(",")) for t in tuples]
if sorted(samples) != list(range(frames)):
    errors.append("time samples %s, expected 0..%d" % (sorted(samples)[:5], frames - 1))
for k, pts in samples.items():
    if len(pts) != points:
        errors.append("sample %d has %d points, expected %d" % (k, len(pts), points))
tips = [sum(counts[:i + 1]) - 1 for i in range(len(counts))]
def tip_move(k):
    return max(math.dist(samples[k][i], samples[0][i]) for i in tips)
peak = max(tip_move(k) for k in samples)
last = tip_move(frames - 1)
# shake: 30 degrees about the vertical axis 10 cm below the head centre; ends at t = 1 s. The
# tips travel centimetres; half a second after the head stopped they are back within a fifth.
if not peak > 0.01:
    errors.append("the shake moved the tips by %.4g m at most, expected > 1 cm" % peak)
if not last < 0.2 * peak:
    errors.append("0.5 s after the shake the tips are %.4g m from rest (peak %.4g m)" % (last, peak))
lines = open(out + "/frames.jsonl").read().splitlines()
if len(lines) != frames:
    errors.append("frames.jsonl: %d lines, expected %d" % (len(lines), frames))
fields = ["frame", "time", "kinetic", "elastic", "gravity", "contact", "max_penetration",
          "newton_iterations", "halved_steps", "failed_steps", "residual"]
for k, line in enumerate(lines):
    d = json.loads(line)
    if list(d)[:len(fields)] != fields:
        errors.append("frames.jsonl line %d: fields %s" % (k, list(d)))
        break
    if d["frame"] != k or abs(d["time"] - k / fps) > 1e-15:
        errors.append("frames.jsonl line %d: frame %s time %s" % (k, d["frame"], d["time"]))
    if k > 0 and not (d["newton_iterations"] > 0 and d["residual"] < 1e-10):
        errors.append("frames.jsonl line %d: %s iterations, residual %s" % (k, d["newton_iterations"], d["residual"]))
    if not all(math.isfinite(d[f]) for f in fields) or d["kinetic"] < 0 or d["elastic"] < 0:
        errors.append("frames.jsonl line %d: %s" % (k, line))
kinetic = [json.loads(l)["kinetic"] for l in lines]
if not max(kinetic) > 100 * kinetic[-1]:
    errors.append("kinetic energy peak %.3g J, last %.3g J: not coming to rest" % (max(kinetic), kinetic[-1]))
print("\n".join(errors))
print("peak tip move %.4g m, last %.4g m" % (peak, last))
sys.exit(1 if errors else 0)
EOF
  fail "shake outputs: $(cat "$work/check")"
fi

# --- a scene of single strands, --hair-per-frame ------------------------------------------------
cat >"$work/scene.json" <<'EOF'
{"strands": [
  {"length": 0.1, "segments": 6, "root": {"position": [0, 0, 0], "tangent": [1, 0, 0], "normal": [0, 0, 1]}},
  {"length": 0.12, "segments": 5, "root": {"position": [0.01, 0, 0], "tangent": [0, 1, 0], "normal": [0, 0, 1]}}
]}
EOF
run simulate "$work/scene.json" -o "$work/s" --motion nod --duration 0.25 --hair-per-frame
expect_rc "scene" 0
expect_files "scene" "$work/s" hair.usda frames.jsonl frame_0000.hair frame_0001.hair \
  frame_0002.hair frame_0003.hair frame_0004.hair frame_0005.hair frame_0006.hair
# 4 points per segment and the root: 25 + 21 points per sample.
n=$(grep -c "^        [0-9]*: \[" "$work/s/hair.usda")
if [ "$n" -eq 14 ]; then ok; else fail "scene: $n time samples (points and extent), expected 2 x 7"; fi
if grep -q "int\[\] curveVertexCounts = \[25, 21\]" "$work/s/hair.usda"; then ok; else
  fail "scene: curveVertexCounts: $(grep curveVertexCounts "$work/s/hair.usda")"
fi
if [ "$(head -c 4 "$work/s/frame_0003.hair")" = "HAIR" ]; then ok; else fail "frame_0003.hair is not a .hair file"; fi

# --- a motion file ---------------------------------------------------------------------------
cat >"$work/turn.json" <<'EOF'
{"description": "look left and back", "pivot": [0, 0, -0.1],
 "keyframes": [{"time": 0}, {"time": 0.3, "axis": [0, 0, 1], "angle": 40}, {"time": 0.6}]}
EOF
run simulate "$SMALL" -o "$work/m" --motion "$work/turn.json" --duration 0.5 -q
expect_rc "motion file" 0
expect_files "motion file" "$work/m" hair.usda frames.jsonl
if [ ! -s "$work/stdout" ] && [ ! -s "$work/stderr" ]; then ok; else fail "-q printed something"; fi

# --- bad options and motion files: one line, exit 1, no output directory ----------------------
bad() {  # bad WHAT SUBSTRING ARGS...
  local what=$1 want=$2
  shift 2
  run simulate "$@"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$want"
  if [ ! -e "$work/bad" ]; then ok; else fail "$what: created $work/bad"; fi
}
motion() { printf '%s\n' "$2" >"$work/$1"; }
bad "fps" "--fps: expected a finite number > 0" "$SMALL" -o "$work/bad" --motion shake --fps 0
bad "duration" "--duration: expected a finite number > 0" "$SMALL" -o "$work/bad" --motion shake --duration -1
bad "substeps" "--substeps: expected an integer between 1 and" "$SMALL" -o "$work/bad" --motion shake --substeps 0
bad "integrator" "--integrator: expected backward_euler or bdf2" "$SMALL" -o "$work/bad" --motion shake --integrator rk4
bad "model tolerance" "--model-tolerance: expected a number in [0, 1)" "$SMALL" -o "$work/bad" --motion shake --model-tolerance 1
bad "mass points" "--mass-points: expected an integer in 1..8, got 0" "$SMALL" -o "$work/bad" --motion shake --mass-points 0
bad "preset" "--motion: expected nod, shake, turn, walk, none or a motion file" "$SMALL" -o "$work/bad" --motion wiggle
bad "width without render" "--width, --height, --spp: only with --render" "$SMALL" -o "$work/bad" --motion shake --width 64
bad "missing motion file" "nope.json: cannot open" "$SMALL" -o "$work/bad" --motion "$work/nope.json"
motion times.json '{"keyframes": [{"time": 0}, {"time": 0}]}'
bad "keyframe time" "times.json: keyframes[1].time: expected a time after the previous keyframe's" \
  "$SMALL" -o "$work/bad" --motion "$work/times.json"
motion field.json '{"keyframes": [{"time": 0, "angel": 3}]}'
bad "unknown field" 'keyframes[0].angel: unknown field (did you mean "angle"?)' \
  "$SMALL" -o "$work/bad" --motion "$work/field.json"
motion axis.json '{"keyframes": [{"time": 0, "axis": [0, 0, 0], "angle": 10}]}'
bad "zero axis" "keyframes[0].axis: expected a non-zero direction" \
  "$SMALL" -o "$work/bad" --motion "$work/axis.json"
motion syntax.json '{"keyframes": [{"time": 0},]}'
bad "syntax" "syntax.json: line 1, column" "$SMALL" -o "$work/bad" --motion "$work/syntax.json"
bad "input" "no_such.json: cannot open" "$work/no_such.json" -o "$work/bad" --motion shake

# --- --render: PNG frames and hair.mp4 (or a clear warning without ffmpeg) --------------------
run simulate "$SMALL" -o "$work/r" --motion turn --duration 0.125 --render --width 48 --height 40 --spp 1
expect_rc "render" 0
if command -v ffmpeg >/dev/null; then
  expect_files "render" "$work/r" hair.usda frames.jsonl frame_0000.png frame_0001.png \
    frame_0002.png frame_0003.png hair.mp4
  if "$PYTHON" - "$work/r/hair.mp4" <<'EOF'; then ok; else fail "hair.mp4 is not an MP4 file"; fi
import sys
data = open(sys.argv[1], "rb").read(64)
sys.exit(0 if data[4:8] == b"ftyp" else 1)
EOF
else
  expect_files "render" "$work/r" hair.usda frames.jsonl frame_0000.png frame_0001.png \
    frame_0002.png frame_0003.png
fi
if [ "$(head -c 4 "$work/r/frame_0002.png" | tail -c 3)" = "PNG" ]; then ok; else fail "frame_0002.png is not a PNG"; fi
# Without ffmpeg on PATH: the frames, and one warning that says so.
(cd / && PATH=/nonexistent "$RINGLET" simulate "$SMALL" -o "$work/r2" --motion turn \
  --duration 0.125 --render --width 48 --height 40 --spp 1) >"$work/stdout" 2>"$work/stderr"
rc=$?
expect_rc "render without ffmpeg" 0
if grep -q "^ringlet: warning: ffmpeg is not on PATH: no hair.mp4" "$work/stderr"; then ok; else
  fail "render without ffmpeg: stderr $(cat "$work/stderr")"
fi
expect_files "render without ffmpeg" "$work/r2" hair.usda frames.jsonl frame_0000.png \
  frame_0001.png frame_0002.png frame_0003.png
# --force over a run that made a video, now without ffmpeg: no stale hair.mp4 stays.
if command -v ffmpeg >/dev/null; then
  (cd / && PATH=/nonexistent "$RINGLET" simulate "$SMALL" -o "$work/r" --motion turn \
    --duration 0.125 --render --width 48 --height 40 --spp 1 --force) >"$work/stdout" 2>"$work/stderr"
  rc=$?
  expect_rc "render again without ffmpeg" 0
  expect_files "render again without ffmpeg" "$work/r" hair.usda frames.jsonl frame_0000.png \
    frame_0001.png frame_0002.png frame_0003.png
fi

# --- SIGINT / SIGTERM during the simulation: no output directory, no staging directory -------
# The outputs are streamed into a staging directory beside OUTDIR (".t_INT.tmp-*"); the signal
# is sent once hair.usda has frames in it.
shopt -s nullglob dotglob
wait_for_frames() {  # wait_for_frames GLOB: until a staged hair.usda holds a time sample
  for _ in $(seq 1 600); do
    for f in $1; do
      grep -q "^        1: " "$f" 2>/dev/null && return 0
    done
    sleep 0.05
  done
  return 1
}
for signal in INT TERM; do
  # A background job of a script ignores SIGINT and ringlet keeps an ignored signal ignored (as
  # nohup wants): env restores the default first.
  (cd / && exec env --default-signal=INT,TERM "$RINGLET" simulate "$SMALL" -o "$work/t_$signal" \
    --motion walk --duration 600 -q) &
  pid=$!
  if wait_for_frames "$work/.t_$signal.tmp-*/hair.usda"; then ok; else fail "$signal: no staged hair.usda with frames"; fi
  kill -s "$signal" "$pid" 2>/dev/null
  wait "$pid"
  status=$?
  want=$((128 + $(kill -l "$signal")))
  if [ "$status" -eq "$want" ]; then ok; else fail "SIG$signal: exit status $status, expected $want"; fi
  if [ ! -e "$work/t_$signal" ]; then ok; else fail "SIG$signal left $work/t_$signal"; fi
  left=("$work"/.t_"$signal".tmp-*)
  if [ ${#left[@]} -eq 0 ]; then ok; else fail "SIG$signal left the staging directory ${left[*]}"; fi
done

# --- --force over an existing OUTDIR: replaced only at the end; an interrupt keeps it -----------
mkdir -p "$work/f"
echo "old usda" >"$work/f/hair.usda"
echo "mine" >"$work/f/notes.txt"
(cd / && exec env --default-signal=INT "$RINGLET" simulate "$SMALL" -o "$work/f" --force \
  --motion walk --duration 600 -q) &
pid=$!
if wait_for_frames "$work/f/.staging.tmp-*/hair.usda"; then ok; else fail "--force: no staged hair.usda inside OUTDIR"; fi
if [ "$(cat "$work/f/hair.usda")" = "old usda" ]; then ok; else fail "--force: hair.usda replaced before the end"; fi
kill -INT "$pid" 2>/dev/null
wait "$pid"
expect_files "--force, interrupted" "$work/f" hair.usda notes.txt
if [ "$(cat "$work/f/hair.usda")" = "old usda" ]; then ok; else fail "--force, interrupted: hair.usda changed"; fi
run simulate "$SMALL" -o "$work/f" --force --motion shake --duration 1.5 --threads 1 -q
expect_rc "--force to the end" 0
expect_files "--force to the end" "$work/f" hair.usda frames.jsonl notes.txt
for f in hair.usda frames.jsonl; do
  if cmp -s "$work/a/$f" "$work/f/$f"; then ok; else fail "--force: $f differs from the first run's"; fi
done

# --- a full disk (a file-size limit; SIGXFSZ ignored so that write() fails with EFBIG): one
# line, exit 1, nothing left ---------------------------------------------------------------------
(
  trap '' XFSZ
  ulimit -f 64
  cd / && exec "$RINGLET" simulate "$SMALL" -o "$work/full" --motion shake --duration 1.5 -q
) >"$work/stdout" 2>"$work/stderr"
rc=$?
expect_rc "full disk" 1
expect_one_error_line "full disk" "full/hair.usda: cannot write: File too large (nothing was written)"
left=("$work"/.full.tmp-*)
if [ ! -e "$work/full" ] && [ ${#left[@]} -eq 0 ]; then ok; else fail "full disk left $(ls -d "$work"/full "$work"/.full.tmp-* 2>/dev/null)"; fi
shopt -u nullglob dotglob

echo "cli_simulate: $checks checks, $failures failures"
[ "$failures" -eq 0 ]
