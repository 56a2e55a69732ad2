# Shared helpers of the command-line contract tests (cli_test.sh, cli_groom_test.sh,
# cli_render_test.sh): sourced after the caller has made its scratch directory $work.
# Every check calls ok or fail; the caller ends with a summary and exits non-zero on failures.

checks=0
failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}
ok() { checks=$((checks + 1)); }

# run ARGS...: runs the binary from / (so that only paths relative to the input file can work);
# sets $rc and leaves stdout and stderr in $work/stdout, $work/stderr.
run() {
  (cd / && "$RINGLET" "$@") >"$work/stdout" 2>"$work/stderr"
  rc=$?
}

# Line count of a file (0 for an empty file; a last line without newline counts).
lines() { awk 'END { print NR }' "$1"; }

expect_rc() {  # expect_rc WHAT EXPECTED
  if [ "$rc" -eq "$2" ]; then ok; else
    fail "$1: exit code $rc, expected $2 (stderr: $(head -c 300 "$work/stderr"))"
  fi
}

expect_one_error_line() {  # expect_one_error_line WHAT SUBSTRING
  local n
  n=$(lines "$work/stderr")
  if [ "$n" -eq 1 ]; then ok; else
    fail "$1: $n lines on stderr, expected exactly 1: $(cat "$work/stderr")"
  fi
  if grep -q '^ringlet: error: ' "$work/stderr"; then ok; else
    fail "$1: stderr does not start with 'ringlet: error: ': $(cat "$work/stderr")"
  fi
  if grep -qF -- "$2" "$work/stderr"; then ok; else
    fail "$1: stderr does not mention '$2': $(cat "$work/stderr")"
  fi
}

expect_files() {  # expect_files WHAT DIR NAME... : DIR holds exactly these files
  local what=$1 dir=$2
  shift 2
  local want have
  want=$(printf '%s\n' "$@" | sort | tr '\n' ' ')
  have=$(ls -A "$dir" 2>/dev/null | sort | tr '\n' ' ')
  if [ "$want" = "$have" ]; then ok; else
    fail "$what: $dir holds [$have], expected [$want]"
  fi
}
