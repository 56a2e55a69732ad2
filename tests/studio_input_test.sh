#!/usr/bin/env bash
# The studio driven through the X server's input (issue 26): xdotool moves the mouse, presses
# buttons and taps keys in an Xvfb display while the studio draws slow frames
# (--min-frame-seconds), and tests/studio/drive_ui.py checks the document, the view and the
# files (the studio's --report only reports). SECTION: sliders, keys, export, or screenshot
# (HAIRSTYLE --screenshot without --script). Skipped (exit 77) without xvfb-run or xdotool.
set -euo pipefail
: "${STUDIO:?}" "${RINGLET:?}" "${DIR:?}"
SECTION=${1:?section}
for tool in xvfb-run xdotool; do
  if ! command -v "$tool" >/dev/null; then
    echo "$tool not found: skipped"
    exit 77
  fi
done
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
# Mesa's llvmpipe leaks small JIT modules (see studio_screenshot_test.sh).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" LIBGL_ALWAYS_SOFTWARE=1
if [ "$SECTION" = screenshot ]; then
  # Without --script, --screenshot saves the first solved frame and exits.
  timeout 60 xvfb-run -a -s "-screen 0 1280x800x24" \
    "$STUDIO" "$DIR/input.json" --screenshot "$WORK/first.png" --size 640x400
  /usr/bin/python3 - "$WORK/first.png" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
width, height = struct.unpack(">II", data[16:24])
assert (width, height) == (640, 400), (width, height)
print(f"first solved frame: {width} x {height}, {len(data)} bytes")
PY
  # Without a hairstyle it is refused with one line.
  if "$STUDIO" --screenshot "$WORK/none.png" 2> "$WORK/err.txt"; then
    echo "--screenshot without a hairstyle was accepted"; exit 1
  fi
  test "$(wc -l < "$WORK/err.txt")" -eq 1 && grep -q -- "--screenshot" "$WORK/err.txt"
  echo "studio screenshot mode: ok"
  exit 0
fi
xvfb-run -a -s "-screen 0 1280x800x24" /usr/bin/python3 "$DIR/drive_ui.py" \
  "$STUDIO" "$RINGLET" "$DIR/input.json" "$WORK" "$SECTION"
