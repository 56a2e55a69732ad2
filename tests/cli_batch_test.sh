#!/usr/bin/env bash
# The command-line contract of `ringlet batch` (docs/batch.md): a tiny spec of 12 items gives
# the same bytes (every file but timing.json) run as 1 x 12, as 3 shards of 4 and as 12 runs of
# 1 item, on 1 or 2 threads, and after a SIGTERM in the middle of a run and a rerun; a rerun
# skips what is done; two processes on one output directory at once give the same dataset and
# intact manifest lines; each item folder holds the documented files, and its hairstyle.json
# reproduces its strands with `ringlet groom` / `ringlet style`; --plan prints the items without
# running them; an item that fails is recorded with its error and the run goes on; unconverged
# masters flag their item; a bad spec gives exit code 1, one line naming the field, nothing
# written.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_batch`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_batch.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/specs/bodies"
cp "$EXAMPLES/bodies/mannequin.json" "$work/specs/bodies/mannequin.json"

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

# A base hairstyle next to the specs: 6 masters of 6 segments, 2 strands of 8 points per wisp.
cat >"$work/specs/base.json" <<'EOF'
{
  "body": "bodies/mannequin.json",
  "masters": {"count": 6, "seed": 1, "segments": 6, "points_per_segment": 2},
  "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.12, "seed": 1},
  "wisps": {"strands_per_wisp": 2, "points_per_strand": 8},
  "layers": {"count": 2, "thickness": 0.003}
}
EOF

# spec NAME COUNT EXTRA_MEMBERS: writes $work/specs/NAME.json over base.json.
spec() {
  cat >"$work/specs/$1.json" <<EOF
{
  "description": "cli_batch_test: $1",
  "seed": 11,
  "count": $2,
  "bases": ["base.json"]${3:+,
  $3}
}
EOF
}
spec small 12 '"parameters": {
    "masters.count": {"uniform": [4, 7]},
    "hair.length": {"normal": {"mean": 0.12, "sd": 0.02, "min": 0.08, "max": 0.16}},
    "hair.curl": {"choice": ["wavy", "curly"]},
    "render.hair.eumelanin": {"choice": [0.3, 8.0]}
  },
  "operations": [{"probability": 0.5, "cut": {"length": {"uniform": [0.05, 0.08]}}}],
  "views": {"orbit": {"count": 2, "elevation_degrees": 15}},
  "outputs": {"formats": ["hair", "data"],
              "images": {"width": 32, "height": 32, "samples_per_pixel": 1}}'
SMALL="$work/specs/small.json"

# digest DIR: one hash of every file of every item folder but timing.json (names and bytes).
digest() {
  (cd "$1" && find item-* -type f ! -name timing.json | LC_ALL=C sort | xargs sha256sum |
    sha256sum | cut -c1-16)
}
items_done() { ls -d "$1"/item-*/done 2>/dev/null | wc -l; }

# --- --plan -----------------------------------------------------------------------------------
run batch "$SMALL" --plan
expect_rc "--plan" 0
if [ "$(lines "$work/stdout")" -eq 12 ]; then ok; else fail "--plan: $(lines "$work/stdout") lines, expected 12"; fi
cp "$work/stdout" "$work/plan_all"
run batch "$SMALL" --plan --items 3:5
if [ "$(cat "$work/stdout")" = "$(sed -n 4,5p "$work/plan_all")" ]; then ok; else
  fail "--plan --items 3:5 differs from lines 4-5 of the whole plan"
fi
run batch "$EXAMPLES/batch/small.json" --plan
expect_rc "examples/batch/small.json --plan" 0
if [ -e "$work/out" ]; then fail "--plan created an output"; else ok; fi

# --- 1 x 12 on one thread: the reference -------------------------------------------------------
run batch "$SMALL" -o "$work/a" --threads 1
expect_rc "1 x 12" 0
if grep -qE '^batch: 12 items \[0, 12\) of 12: 12 done, 0 flagged, 0 failed, 0 skipped' "$work/stdout"; then ok; else
  fail "1 x 12: summary line: $(tail -1 "$work/stdout")"
fi
if grep -qE '^item-000000005 done in .* \(6/12; .* items/s, about .* left\)$' "$work/stdout"; then ok; else
  fail "1 x 12: no progress line with rate and ETA for item 5: $(head -3 "$work/stdout")"
fi
if [ "$(items_done "$work/a")" -eq 12 ]; then ok; else fail "1 x 12: $(items_done "$work/a") items done, expected 12"; fi
reference=$(digest "$work/a")

# Every item folder: the documented files, valid JSON, PNG sizes, depth arrays, manifest.
if "$PYTHON" - "$work/a" <<'EOF' >"$work/check" 2>&1; then ok; else fail "item contents: $(cat "$work/check")"; fi
import json, os, struct, sys
import numpy as np
out = sys.argv[1]
errors = []
manifest = [json.loads(l) for l in open(os.path.join(out, "manifest-all.jsonl"))]
if sorted(m["item"] for m in manifest) != list(range(12)):
    errors.append("manifest items %s" % sorted(m["item"] for m in manifest))
if any(m["status"] != "done" for m in manifest):
    errors.append("manifest statuses %s" % [m["status"] for m in manifest])
for k in range(12):
    d = os.path.join(out, "item-%09d" % k)
    names = sorted(os.listdir(d))
    want = sorted(["hairstyle.json", "strands.hair", "strands.data", "metadata.json", "timing.json",
                   "done"] + ["%s_%02d.%s" % (n, v, e) for v in range(2)
                              for n, e in [("rgb", "png"), ("mask", "png"),
                                           ("orientation", "png"), ("depth", "npy")]])
    if names != want:
        errors.append("%s holds %s" % (d, names))
        continue
    meta = json.load(open(os.path.join(d, "metadata.json")))
    style = json.load(open(os.path.join(d, "hairstyle.json")))
    if meta["item"] != k or meta["status"] != "done":
        errors.append("%s: metadata item %s status %s" % (d, meta["item"], meta["status"]))
    # The parameters drawn are the hairstyle's.
    for path, value in meta["parameters"]["values"].items():
        node = style
        for key in path.split("."):
            node = node[key]
        if node != value:
            errors.append("%s: hairstyle %s = %s, metadata says %s" % (d, path, node, value))
    if not 4 <= style["masters"]["count"] <= 7:
        errors.append("%s: masters.count %s outside [4, 7]" % (d, style["masters"]["count"]))
    if not 0.08 <= style["hair"]["length"] <= 0.16:
        errors.append("%s: hair.length %s outside [0.08, 0.16]" % (d, style["hair"]["length"]))
    # .hair header: strand and point counts as the metadata says.
    head = open(os.path.join(d, "strands.hair"), "rb").read(12)
    strands, points = struct.unpack("<II", head[4:12])
    if (strands, points) != (meta["strands"]["strands"], meta["strands"]["points"]):
        errors.append("%s: .hair has %d strands %d points, metadata %s" % (d, strands, points, meta["strands"]))
    if strands != meta["groom"]["masters"] * 2:
        errors.append("%s: %d strands for %d masters of 2 strands" % (d, strands, meta["groom"]["masters"]))
    # .data: int32 strand count, then per strand int32 n and n xyz float32 (metres, y up).
    data = open(os.path.join(d, "strands.data"), "rb").read()
    if struct.unpack("<i", data[:4])[0] != strands:
        errors.append("%s: .data strand count" % d)
    for v in range(2):
        depth = np.load(os.path.join(d, "depth_%02d.npy" % v))
        if depth.shape != (32, 32) or depth.dtype != np.float32:
            errors.append("%s: depth shape %s dtype %s" % (d, depth.shape, depth.dtype))
        for name in ["rgb", "mask", "orientation"]:
            png = open(os.path.join(d, "%s_%02d.png" % (name, v)), "rb").read(26)
            w, h = struct.unpack(">II", png[16:24])
            colour = {"rgb": 2, "mask": 0, "orientation": 2}[name]
            if (w, h, png[24], png[25]) != (32, 32, 8, colour):
                errors.append("%s: %s_%02d.png is %dx%d, depth %d, colour type %d" % (d, name, v, w, h, png[24], png[25]))
print("\n".join(errors))
sys.exit(1 if errors else 0)
EOF

# --- the same bytes from every layout and thread count -----------------------------------------
for k in 0 1 2; do run batch "$SMALL" -o "$work/b" --shard "$k/3" --threads 2 -q; done
expect_rc "3 x 4 (last shard)" 0
if [ "$(digest "$work/b")" = "$reference" ]; then ok; else fail "3 x 4 on 2 threads: bytes differ from 1 x 12"; fi
if [ "$(ls "$work/b"/manifest-shard-*-of-3.jsonl | wc -l)" -eq 3 ]; then ok; else fail "3 x 4: expected 3 manifests: $(ls "$work/b")"; fi
for k in $(seq 0 11); do run batch "$SMALL" -o "$work/c" --items "$k:$((k + 1))" --threads 2 -q; done
if [ "$(digest "$work/c")" = "$reference" ]; then ok; else fail "12 x 1: bytes differ from 1 x 12"; fi
if [ "$(cat "$work"/b/manifest-*.jsonl | LC_ALL=C sort)" = "$(LC_ALL=C sort "$work/a/manifest-all.jsonl")" ]; then ok; else
  fail "3 x 4: the manifest lines differ from 1 x 12's"
fi

# --- a rerun skips what is done ----------------------------------------------------------------
run batch "$SMALL" -o "$work/a"
expect_rc "rerun" 0
if grep -q '0 done, 0 flagged, 0 failed, 12 skipped' "$work/stdout"; then ok; else fail "rerun: $(tail -1 "$work/stdout")"; fi
if [ "$(lines "$work/a/manifest-all.jsonl")" -eq 12 ]; then ok; else fail "rerun: manifest grew to $(lines "$work/a/manifest-all.jsonl") lines"; fi

# --- SIGTERM in the middle, then a rerun: the undisturbed bytes ----------------------------------
("$RINGLET" batch "$SMALL" -o "$work/d" --threads 1 -q >/dev/null 2>&1) &
pid=$!
for _ in $(seq 1 3000); do
  [ "$(items_done "$work/d")" -ge 1 ] && break
  sleep 0.01
done
# The subshell runs ringlet as its only command (bash execs it): pid is ringlet's. It is frozen
# (SIGSTOP) the moment an item is done, so that SIGTERM lands mid-run whatever the machine's load
# (on a busy machine the 12 items of 0.1 s could otherwise all finish between two polls), then
# let go with SIGCONT: the pending SIGTERM is handled at once.
if [[ "$pid" =~ ^[1-9][0-9]*$ ]] && [ "$pid" -gt 1 ]; then
  kill -STOP "$pid" 2>/dev/null
  kill -TERM "$pid" 2>/dev/null
  kill -CONT "$pid" 2>/dev/null
fi
wait "$pid"
status=$?
if [ "$status" -eq 143 ]; then ok; else fail "SIGTERM: exit status $status, expected 143 (128 + SIGTERM)"; fi
done_after=$(items_done "$work/d")
if [ "$done_after" -lt 12 ]; then ok; else fail "SIGTERM came after the run had finished (not a test of an interrupted run)"; fi
if [ -z "$(ls -A "$work/d" | grep '^\.')" ]; then ok; else fail "SIGTERM left temporaries: $(ls -A "$work/d")"; fi
run batch "$SMALL" -o "$work/d" --threads 2
expect_rc "rerun after SIGTERM" 0
if grep -q "$((12 - done_after)) done, 0 flagged, 0 failed, $done_after skipped" "$work/stdout"; then ok; else
  fail "rerun after SIGTERM ($done_after done): $(tail -1 "$work/stdout")"
fi
if [ "$(digest "$work/d")" = "$reference" ]; then ok; else fail "SIGTERM + rerun: bytes differ from the undisturbed run"; fi

# --- two processes on one directory at once --------------------------------------------------------
"$RINGLET" batch "$SMALL" -o "$work/e" --threads 1 -q &
p1=$!
"$RINGLET" batch "$SMALL" -o "$work/e" --threads 1 -q &
p2=$!
wait "$p1"; s1=$?
wait "$p2"; s2=$?
if [ "$s1" -eq 0 ] && [ "$s2" -eq 0 ]; then ok; else fail "two processes: exit codes $s1 and $s2"; fi
if [ "$(digest "$work/e")" = "$reference" ]; then ok; else fail "two processes: bytes differ from one"; fi
if "$PYTHON" -c '
import json, sys
items = [json.loads(l)["item"] for l in open(sys.argv[1])]
assert sorted(set(items)) == list(range(12)), items
' "$work/e/manifest-all.jsonl" 2>"$work/check"; then ok; else fail "two processes: manifest: $(cat "$work/check")"; fi

# --- an item's hairstyle.json reproduces it --------------------------------------------------------
plain=$("$PYTHON" -c '
import json, sys
for k in range(12):
    m = json.load(open("%s/item-%09d/metadata.json" % (sys.argv[1], k)))
    if not m["parameters"]["operations"]:
        print("%09d" % k); break
' "$work/a")
cut=$("$PYTHON" -c '
import json, sys
for k in range(12):
    m = json.load(open("%s/item-%09d/metadata.json" % (sys.argv[1], k)))
    if m["parameters"]["operations"]:
        print("%09d" % k); break
' "$work/a")
if [ -n "$plain" ] && [ -n "$cut" ]; then ok; else fail "expected items with and without a cut ($plain, $cut)"; fi
run groom "$work/a/item-$plain/hairstyle.json" -o "$work/groom" --formats hair -q
expect_rc "groom item-$plain/hairstyle.json" 0
if cmp -s "$work/groom/strands.hair" "$work/a/item-$plain/strands.hair"; then ok; else
  fail "ringlet groom item-$plain/hairstyle.json: strands.hair differs from the item's"
fi
run style "$work/a/item-$cut/hairstyle.json" -o "$work/style" --formats hair -q
expect_rc "style item-$cut/hairstyle.json" 0
if cmp -s "$work/style/strands.hair" "$work/a/item-$cut/strands.hair"; then ok; else
  fail "ringlet style item-$cut/hairstyle.json: strands.hair differs from the item's"
fi

# --- failed and flagged items -------------------------------------------------------------------
# A curl of master 5 fails on the items with fewer than 6 masters: recorded, and the run goes on.
spec failing 6 '"parameters": {"masters.count": {"choice": [4, 6]}},
  "operations": [{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"indices": [5]}}}]'
run batch "$work/specs/failing.json" -o "$work/f" --threads 2
expect_rc "failing items" 2
if "$PYTHON" - "$work/f" <<'EOF' >"$work/check" 2>&1; then ok; else fail "failed items: $(cat "$work/check")"; fi
import json, os, sys
out = sys.argv[1]
errors = []
lines = [json.loads(l) for l in open(os.path.join(out, "manifest-all.jsonl"))]
failed = [l for l in lines if l["status"] == "failed"]
done = [l for l in lines if l["status"] == "done"]
if not failed or not done or len(lines) != 6:
    errors.append("expected failed and done items among 6: %s" % lines)
for l in failed:
    if "indices" not in l.get("error", "") or "\n" in l["error"]:
        errors.append("failed item's error: %r" % l.get("error"))
    if os.path.exists(os.path.join(out, l["name"])):
        errors.append("failed item %s has a folder" % l["name"])
for l in done:
    if not os.path.exists(os.path.join(out, l["name"], "done")):
        errors.append("done item %s has no done marker" % l["name"])
print("\n".join(errors))
sys.exit(1 if errors else 0)
EOF
if grep -qE '^ringlet: warning: item-[0-9]+: operations\[0\]: .*indices' "$work/stderr"; then ok; else
  fail "failed item: no warning line: $(head -2 "$work/stderr")"
fi
# One solver iteration: no master converges; the items are kept and flagged.
cat >"$work/specs/stiff.json" <<EOF
{"count": 2, "bases": [{"body": "bodies/mannequin.json", "masters": {"count": 3, "segments": 6},
  "wisps": {"strands_per_wisp": 1, "points_per_strand": 4}, "solver": {"max_iterations": 1}}]}
EOF
run batch "$work/specs/stiff.json" -o "$work/g"
expect_rc "flagged items" 2
if grep -q '0 done, 2 flagged, 0 failed' "$work/stdout"; then ok; else fail "flagged: $(tail -1 "$work/stdout")"; fi
if grep -q '"status": "flagged"' "$work/g/item-000000001/metadata.json" &&
   grep -q '"status":"flagged"' "$work/g/manifest-all.jsonl"; then ok; else
  fail "flagged: metadata or manifest does not say flagged"
fi

# A folder in the way without a done marker is not taken for the item: the item fails, saying so.
mkdir -p "$work/h/item-000000001" && touch "$work/h/item-000000001/junk"
run batch "$work/specs/stiff.json" -o "$work/h" --items 1:2
expect_rc "folder in the way" 2
if grep -q 'item-000000001: exists without a done marker' "$work/stderr" &&
   grep -q '"status":"failed"' "$work/h/manifest-items-1-2.jsonl"; then ok; else
  fail "folder in the way: $(cat "$work/stderr")"
fi

# --- bad specs and arguments: one line naming the field, nothing written ----------------------------
bad() {  # bad WHAT SUBSTRING SPEC_TEXT [ARGS...]
  local what=$1 substring=$2 text=$3
  shift 3
  printf '%s\n' "$text" >"$work/specs/bad.json"
  run batch "$work/specs/bad.json" -o "$work/bad_out" "$@"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$substring"
  if [ -e "$work/bad_out" ]; then fail "$what: created the output directory"; rm -rf "$work/bad_out"; else ok; fi
}
bad "missing count" 'count: missing required field' '{"bases": ["base.json"]}'
bad "unknown member" 'outptus: unknown field (did you mean "outputs"?)' '{"count": 1, "bases": ["base.json"], "outptus": {}}'
bad "unknown path" 'parameters["hair.curl_radious"]: not a hairstyle field' \
  '{"count": 1, "bases": ["base.json"], "parameters": {"hair.curl_radious": {"uniform": [0.01, 0.02]}}}'
bad "range beyond the hairstyle's" 'hair.curl_radius: expected' \
  '{"count": 1, "bases": ["base.json"], "parameters": {"hair.curl_radius": {"uniform": [0.01, 20]}}}'
bad "uniform low > high" 'parameters["masters.count"].uniform: expected [low, high]' \
  '{"count": 1, "bases": ["base.json"], "parameters": {"masters.count": {"uniform": [9, 3]}}}'
bad "normal sd" 'parameters["hair.length"].normal.sd: expected a finite number > 0' \
  '{"count": 1, "bases": ["base.json"], "parameters": {"hair.length": {"normal": {"mean": 0.1, "sd": 0, "min": 0.05, "max": 0.2}}}}'
bad "choice type" 'parameters["hair.curl"].choice[1]: expected a string, got 3' \
  '{"count": 1, "bases": ["base.json"], "parameters": {"hair.curl": {"choice": ["wavy", 3]}}}'
bad "operation" 'operations[0].perm: unknown operation' '{"count": 1, "bases": ["base.json"], "operations": [{"perm": {}}]}'
bad "operation field" 'operations[0].cut.length' \
  '{"count": 1, "bases": ["base.json"], "operations": [{"cut": {"length": {"uniform": [-1, 0.1]}}}]}'
bad "base file" 'bases[0]: ' '{"count": 1, "bases": ["no_such_base.json"]}'
bad "base field" 'hair.origin' '{"count": 1, "bases": [{"body": "bodies/mannequin.json", "hair": {"origin": "martian"}}]}'
bad "format" 'outputs.formats[0]: expected "hair", "usda" or "data", got "fbx"' \
  '{"count": 1, "bases": ["base.json"], "outputs": {"formats": ["fbx"]}}'
bad "view" 'views[0].camera.fov_degrees' '{"count": 1, "bases": ["base.json"], "views": [{"view_direction": [0, -1, 0], "fov_degrees": 200}]}'
bad "items beyond count" '--items: 0:5 goes beyond the spec' '{"count": 3, "bases": ["base.json"]}' --items 0:5
bad "shard" '--shard: expected K/N' '{"count": 3, "bases": ["base.json"]}' --shard 3/3
bad "json syntax" 'line 1, column' '{"count": 3,, }'
ok_spec='{"count": 3, "bases": ["base.json"]}'
bad "slurm tasks beyond items" '--slurm-tasks: 4 tasks for 3 items' "$ok_spec" --slurm-script --slurm-tasks 4
bad "slurm tasks and items per task" '--slurm-tasks and --slurm-items-per-task: give one' "$ok_spec" \
  --slurm-script --slurm-tasks 2 --slurm-items-per-task 2
bad "slurm time" '--slurm-time: expected a time limit' "$ok_spec" --slurm-script --slurm-time 1h
bad "slurm partition" '--slurm-partition: expected a non-empty word' "$ok_spec" --slurm-script \
  --slurm-partition 'a b'
bad "slurm own option" '--slurm-option: --array is set by the script itself' "$ok_spec" \
  --slurm-script --slurm-option=--array=0-9
bad "slurm with shard" '--shard: not with --slurm-script' "$ok_spec" --slurm-script --shard 0/2
bad "slurm option alone" '--slurm-tasks: needs --slurm-script or --slurm-unfinished' "$ok_spec" \
  --slurm-tasks 2
bad "slurm both modes" '--slurm-script and --slurm-unfinished: give one' "$ok_spec" --slurm-script \
  --slurm-unfinished
# --slurm-script without FILE: the script on stdout; OUTDIR made with its spec.json and log folder.
run batch "$SMALL" -o "$work/slurm" --items 2:12 --slurm-script --slurm-items-per-task 4
expect_rc "--slurm-script to stdout" 0
if grep -qx '#SBATCH --array=0-2' "$work/stdout" &&
  grep -qF -- "batch '$SMALL' -o '$work/slurm' --items 2:12 --shard \"\${SLURM_ARRAY_TASK_ID}/3\"" \
    "$work/stdout" && [ -d "$work/slurm/slurm-logs" ] && cmp -s "$SMALL" "$work/slurm/spec.json"; then
  ok
else
  fail "--slurm-script to stdout: $(cat "$work/stdout" "$work/stderr")"
fi
# The tasks not done: all 3; after a run of items 2 to 5 (task 0 has 2 to 4, task 1 5 to 7), 1-2.
run batch "$SMALL" -o "$work/slurm" --items 2:12 --slurm-unfinished --slurm-items-per-task 4
if [ "$rc" -eq 0 ] && [ "$(cat "$work/stdout")" = 0-2 ]; then ok; else
  fail "--slurm-unfinished before any run: rc $rc, \"$(cat "$work/stdout")\""
fi
run batch "$SMALL" -o "$work/slurm" --items 2:6 -q
run batch "$SMALL" -o "$work/slurm" --items 2:12 --slurm-unfinished --slurm-items-per-task 4
if [ "$rc" -eq 0 ] && [ "$(cat "$work/stdout")" = 1-2 ]; then ok; else
  fail "--slurm-unfinished after task 0's items: rc $rc, \"$(cat "$work/stdout")\""
fi
run batch "$work/specs/failing.json" -o "$work/slurm" --slurm-script "$work/job.sh"
expect_rc "--slurm-script on another spec's dataset" 1
expect_one_error_line "--slurm-script on another spec's dataset" "holds the dataset of another spec"
if [ ! -e "$work/job.sh" ]; then ok; else fail "--slurm-script wrote a script for another spec's dataset"; fi
# Another spec's dataset is not mixed with this one's.
run batch "$work/specs/failing.json" -o "$work/a"
expect_rc "another spec's directory" 1
expect_one_error_line "another spec's directory" "holds the dataset of another spec"

echo "cli_batch: $checks checks, $failures failures"
[ "$failures" -eq 0 ]
