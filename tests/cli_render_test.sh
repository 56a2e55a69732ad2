#!/usr/bin/env bash
# The command-line contract of `ringlet render`, `ringlet groom --render` and `ringlet style --render`
# (docs/hairstyle-format.md, "render"): a tiny hairstyle renders into a PNG of the asked size
# whose bytes do not depend on the thread count; a .hair file renders with and without a body;
# `groom --render` adds render.png to the groom's files; existing images are never overwritten
# silently; every bad input (missing file, unknown extension, bad options, bad "render" settings)
# gives exit code 1, exactly one line on stderr naming the field, and writes nothing.
#
# The first part (bad inputs) needs only the command line and the file readers; the second
# (happy paths) needs the ray tracer and the hair BSDF.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `cli_render`. Exits non-zero if any check failed, after printing what failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"

work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_cli_render.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/styles/bodies" "$work/out"
cp "$EXAMPLES/bodies/mannequin.json" "$work/styles/bodies/mannequin.json"

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

# png_size FILE: "WIDTHxHEIGHT" from the IHDR chunk (big-endian uint32 at bytes 16 and 20, PNG
# specification 11.2.2), or "not-a-png" when the 8-byte signature is wrong.
png_size() {
  local sig b
  sig=$(od -An -tu1 -N8 "$1" 2>/dev/null | tr -s ' ')
  if [ "$sig" != " 137 80 78 71 13 10 26 10" ]; then
    echo "not-a-png"
    return
  fi
  read -r -a b <<<"$(od -An -tu1 -j16 -N8 "$1")"
  echo "$(((b[0] << 24) | (b[1] << 16) | (b[2] << 8) | b[3]))x$(((b[4] << 24) | (b[5] << 16) | (b[6] << 8) | b[7]))"
}

expect_png() {  # expect_png WHAT FILE WIDTHxHEIGHT
  local size
  size=$(png_size "$2")
  if [ "$size" = "$3" ]; then ok; else fail "$1: $2 is $size, expected a $3 PNG"; fi
}

# A tiny hairstyle: 20 masters of 6 segments, 5 strands of 8 points per wisp (100 strands), and
# a 64 x 48 image at 2 samples per pixel. The body path is relative to this file's directory.
style() {  # style NAME EXTRA_RENDER_MEMBERS: writes $work/styles/NAME.json
  cat >"$work/styles/$1.json" <<EOF
{
  "description": "cli_render_test: a tiny head of hair",
  "body": "bodies/mannequin.json",
  "masters": {"count": 20, "seed": 4, "segments": 6, "points_per_segment": 2},
  "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.12, "seed": 2},
  "wisps": {"strands_per_wisp": 5, "points_per_strand": 8},
  "layers": {"count": 2, "thickness": 0.003},
  "render": {"width": 64, "height": 48, "samples_per_pixel": 2, "max_bounces": 2${2:+, $2}}
}
EOF
}
style tiny ""
TINY="$work/styles/tiny.json"

# ============================================================================================
# Bad input: exit 1, one line on stderr naming the field, no image and no directory.

# bad_render WHAT FIELD ARGS...: `render ARGS` with an output whose directory does not exist.
bad_render() {
  local what=$1 field=$2
  shift 2
  run render "$@" -o "$work/never/image.png"
  expect_rc "$what" 1
  expect_one_error_line "$what" "$field"
  [ -s "$work/stdout" ] && fail "$what: printed on stdout: $(cat "$work/stdout")" || ok
  if [ -e "$work/never" ]; then
    fail "$what: created $work/never: $(find "$work/never")"
    rm -rf "$work/never"
  else ok; fi
}

bad_render "missing hairstyle" "no_such_style.json" "$work/styles/no_such_style.json"
bad_render "missing .hair file" "no_such.hair" "$work/styles/no_such.hair"
echo "v 0 0 0" >"$work/styles/strands.obj"
bad_render "unknown extension" 'unknown extension ".obj"' "$work/styles/strands.obj"
grep -qF 'expected a hairstyle .json or a .hair file' "$work/stderr" && ok ||
  fail "unknown extension: the accepted kinds are not named"
bad_render "no extension" 'unknown extension ""' "$work/styles/README"
echo "not a hair file" >"$work/styles/broken.hair"
bad_render "broken .hair file" "broken.hair" "$work/styles/broken.hair"
bad_render "--width 0" "--width" "$TINY" --width 0
bad_render "--height -3" "--height" "$TINY" --height -3
bad_render "--spp 0" "--spp" "$TINY" --spp 0
bad_render "--spp not a number" "--spp" "$TINY" --spp many
bad_render "--shadows unknown" "--shadows" "$TINY" --shadows deep
bad_render "--exposure 0" "--exposure" "$TINY" --exposure 0
bad_render "--eumelanin -1" "--eumelanin" "$TINY" --eumelanin=-1
bad_render "--eccentricity 1" "--eccentricity" "$TINY" --eccentricity 1
bad_render "--view two numbers" "--view" "$TINY" --view 1,2
bad_render "--view zero" "--view" "$TINY" --view 0,0,0
bad_render "--view text" "--view" "$TINY" --view a,b,c
bad_render "--threads -1" "--threads" "$TINY" --threads -1
bad_render "--clamp -1" "--clamp" "$TINY" --clamp=-1
bad_render "--sampler unknown" "--sampler" "$TINY" --sampler halton
bad_render "unknown option" "--frobnicate" "$TINY" --frobnicate
bad_render "--body with a hairstyle" "--body" "$TINY" --body "$work/styles/bodies/mannequin.json"
bad_render "missing --settings file" "no_such_settings.json" "$TINY" --settings \
  "$work/styles/no_such_settings.json"

# Bad "render" objects in the hairstyle file name the field.
bad_style() {  # bad_style NAME FIELD RENDER_MEMBERS
  style "$1" "$3"
  bad_render "bad render settings $1" "$2" "$work/styles/$1.json"
}
bad_style seed 'render.seed: expected an integer between 0 and 2^53, got -64' '"seed": -64'
bad_style shadows 'render.shadows' '"shadows": "soft"'
bad_style fov 'render.camera.fov_degrees' '"camera": {"fov_degrees": 0}'
bad_style eccentricity 'render.hair.eccentricity: not a render setting' \
  '"hair": {"eccentricity": 0.5}'
bad_style typo 'render.exposre: unknown field (did you mean "exposure"?)' '"exposre": 2'
bad_style clamp 'render.clamp: expected a finite number >= 0' '"clamp": -2'
bad_style denoise 'render.denoise: expected true or false' '"denoise": "yes"'
# ... also for `groom`, with or without --render (the file is checked as a whole).
run groom "$work/styles/seed.json" -o "$work/never"
expect_rc "groom with bad render settings" 1
expect_one_error_line "groom with bad render settings" "render.seed"
[ -e "$work/never" ] && fail "groom with bad render settings created $work/never" || ok
run groom "$work/styles/seed.json" -o "$work/never" --render
expect_rc "groom --render with bad render settings" 1
expect_one_error_line "groom --render with bad render settings" "render.seed"
[ -e "$work/never" ] && fail "groom --render with bad render settings created $work/never" || ok
run groom "$TINY" -o "$work/never" --spp 4
expect_rc "groom --spp without --render" 1
expect_one_error_line "groom --spp without --render" "--spp: only with --render"
[ -e "$work/never" ] && fail "groom --spp without --render created $work/never" || ok
run groom "$TINY" -o "$work/never" --no-denoise
expect_rc "groom --no-denoise without --render" 1
expect_one_error_line "groom --no-denoise without --render" "--no-denoise: only with --render"
[ -e "$work/never" ] && fail "groom --no-denoise without --render created $work/never" || ok

# The output must be a .png file name, and not an existing file (without --force) or directory.
run render "$TINY" -o "$work/out/image.jpg"
expect_rc "-o image.jpg" 1
expect_one_error_line "-o image.jpg" "--output: expected a .png file name"
echo "precious" >"$work/out/existing.png"
run render "$TINY" -o "$work/out/existing.png"
expect_rc "existing image without --force" 1
expect_one_error_line "existing image without --force" "existing.png: already exists"
[ "$(cat "$work/out/existing.png")" = "precious" ] && ok ||
  fail "existing image was modified without --force"
mkdir -p "$work/out/dir.png"
run render "$TINY" -o "$work/out/dir.png" --force
expect_rc "output is a directory" 1
expect_one_error_line "output is a directory" "is a directory"
run render "$TINY"
expect_rc "missing --output" 1
expect_one_error_line "missing --output" "--output"
expect_files "bad outputs" "$work/out" existing.png dir.png

# Usage.
run render --help
expect_rc "render --help" 0
for option in --output --width --height --spp --seed --threads --shadows --eumelanin \
  --pheomelanin --exposure --view --body --eccentricity --force --quiet --clamp --sampler \
  --no-denoise; do
  grep -q -- "$option" "$work/stdout" && ok || fail "render --help does not mention $option"
done
run groom --help
grep -q -- "--render" "$work/stdout" && ok || fail "groom --help does not mention --render"

# ============================================================================================
# Happy paths: these need the ray tracer (Render) and the hair BSDF.

run render "$TINY" -o "$work/out/tiny.png"
expect_rc "render hairstyle" 0
expect_png "render hairstyle" "$work/out/tiny.png" 64x48
grep -q '^groomed 20 masters (20 converged, 0 unconverged, 0 unstable), 100 strands, 800 points' \
  "$work/stdout" && ok || fail "render hairstyle: no groom line on stdout: $(cat "$work/stdout")"
grep -q "^rendered 64 x 48 at 2 spp in .* rays (.* camera), 0 NaN samples, .* -> .*tiny.png$" \
  "$work/stdout" && ok || fail "render hairstyle: no summary line on stdout: $(cat "$work/stdout")"
[ -s "$work/stderr" ] && fail "render hairstyle: unexpected stderr: $(cat "$work/stderr")" || ok

# Options override the file; the image does not depend on the thread count.
run render "$TINY" -o "$work/out/t1.png" --width 40 --height 30 --spp 1 --threads 1 --quiet
expect_rc "--threads 1" 0
expect_png "--width 40 --height 30" "$work/out/t1.png" 40x30
[ -s "$work/stdout" ] || [ -s "$work/stderr" ] &&
  fail "--quiet printed: $(cat "$work/stdout" "$work/stderr")" || ok
run render "$TINY" -o "$work/out/t2.png" --width 40 --height 30 --spp 1 --threads 2 --quiet
expect_rc "--threads 2" 0
cmp -s "$work/out/t1.png" "$work/out/t2.png" && ok || fail "--threads 1 and 2 give different images"
run render "$TINY" -o "$work/out/seed.png" --width 40 --height 30 --spp 1 --seed 7 --quiet
expect_rc "--seed 7" 0
cmp -s "$work/out/t1.png" "$work/out/seed.png" && fail "--seed 7 gave the same image as seed 1" ||
  ok
run render "$TINY" -o "$work/out/fast.png" --shadows fibre_transmittance --eumelanin 8 \
  --pheomelanin 0 --exposure 2 --view=-1,0,0 --eccentricity 0.5 --quiet
expect_rc "all overrides" 0
expect_png "all overrides" "$work/out/fast.png" 64x48
# The unbiased estimate (no denoiser, no clamp, independent samples) is another image.
run render "$TINY" -o "$work/out/raw.png" --width 40 --height 30 --spp 1 --no-denoise --clamp 0 \
  --sampler independent --quiet
expect_rc "--no-denoise --clamp 0 --sampler independent" 0
expect_png "--no-denoise" "$work/out/raw.png" 40x30
cmp -s "$work/out/t1.png" "$work/out/raw.png" && fail "--no-denoise gave the default image" || ok

# --force replaces an existing image.
run render "$TINY" -o "$work/out/existing.png" --force --quiet
expect_rc "existing image with --force" 0
expect_png "existing image with --force" "$work/out/existing.png" 64x48

# A missing output directory is created.
run render "$TINY" -o "$work/out/new/dir/tiny.png" --quiet
expect_rc "new directory" 0
expect_png "new directory" "$work/out/new/dir/tiny.png" 64x48

# groom --render: the four files and render.png with the file's settings (or overrides).
run groom "$TINY" -o "$work/out/groom" --render
expect_rc "groom --render" 0
expect_files "groom --render" "$work/out/groom" \
  strands.hair strands.usda strands.obj body.obj masters.json render.png
expect_png "groom --render" "$work/out/groom/render.png" 64x48
grep -q "^rendered 64 x 48 at 2 spp .* -> .*render.png$" "$work/stdout" && ok ||
  fail "groom --render: no render summary on stdout: $(cat "$work/stdout")"
run groom "$TINY" -o "$work/out/groom" --render --width 32 --height 32 --spp 1 --quiet
expect_rc "groom --render existing without --force" 1
expect_one_error_line "groom --render existing without --force" "already exists"
run groom "$TINY" -o "$work/out/groom" --render --width 32 --height 32 --spp 1 --quiet --force
expect_rc "groom --render --force" 0
expect_png "groom --render --width 32 --height 32" "$work/out/groom/render.png" 32x32
# Without --render, groom writes no image.
run groom "$TINY" -o "$work/out/groom_plain" --quiet
expect_rc "groom without --render" 0
expect_files "groom without --render" "$work/out/groom_plain" \
  strands.hair strands.usda strands.obj body.obj masters.json

# `style --render`: the styled (here wet) hair's picture next to the style's files, with the
# file's render settings; bad render settings are refused before any work.
run style "$TINY" --wet -o "$work/out/style" --render
expect_rc "style --wet --render" 0
expect_files "style --wet --render" "$work/out/style" \
  strands.hair strands.usda strands.obj body.obj masters.json render.png
expect_png "style --wet --render" "$work/out/style/render.png" 64x48
grep -q "^rendered 64 x 48 at 2 spp .* -> .*render.png$" "$work/stdout" && ok ||
  fail "style --render: no render summary on stdout: $(cat "$work/stdout")"
run style "$work/styles/seed.json" --wet -o "$work/never" --render
expect_rc "style --render with bad render settings" 1
expect_one_error_line "style --render with bad render settings" "render.seed"
[ -e "$work/never" ] && fail "style --render with bad render settings created $work/never" || ok

# A .hair file: hair only, with a body, and in centimetres.
run render "$work/out/groom/strands.hair" -o "$work/out/hair.png" --width 32 --height 32 --spp 1
expect_rc "render .hair" 0
expect_png "render .hair" "$work/out/hair.png" 32x32
run render "$work/out/groom/strands.hair" -o "$work/out/hair_body.png" --width 32 --height 32 \
  --spp 1 --body "$work/styles/bodies/mannequin.json" --eccentricity 0.3 --quiet
expect_rc "render .hair --body" 0
expect_png "render .hair --body" "$work/out/hair_body.png" 32x32
cmp -s "$work/out/hair.png" "$work/out/hair_body.png" && fail "--body changed nothing" || ok
run groom "$TINY" -o "$work/out/cm" --formats hair --hair-units-per-metre 100 --quiet
run render "$work/out/cm/strands.hair" -o "$work/out/cm.png" --width 32 --height 32 --spp 1 \
  --hair-units-per-metre 100 --quiet
expect_rc "render .hair in cm" 0
cmp -s "$work/out/hair.png" "$work/out/cm.png" && ok ||
  fail "the same strands in cm (--hair-units-per-metre 100) rendered differently"

# A render file of its own (--settings) over a .hair input.
echo '{"render": {"width": 24, "height": 16, "samples_per_pixel": 1}}' >"$work/styles/settings.json"
run render "$work/out/groom/strands.hair" -o "$work/out/settings.png" --settings \
  "$work/styles/settings.json" --quiet
expect_rc "--settings" 0
expect_png "--settings" "$work/out/settings.png" 24x16

# --------------------------------------------------------------------------------------------
if [ "$failures" -ne 0 ]; then
  echo "cli_render_test: $failures of $((checks + failures)) checks FAILED" >&2
  exit 1
fi
echo "cli_render_test: all $checks checks passed"
