#!/usr/bin/env bash
# `ringlet batch --slurm-script` against a real Slurm (docs/batch.md, "Slurm"; issue 28 items 4
# and 6): starts munged, slurmctld and slurmd on this machine (one node on loopback, everything in
# a temporary directory, free ports), then
#   1. writes the job array of examples/batch/small.json (12 items, 4 tasks of 3), submits it
#      with sbatch, waits for it (squeue) and checks every task COMPLETED and the dataset equal,
#      byte for byte, to a single-process `ringlet batch` of the spec (every file of every item
#      folder but timing.json; the manifests' lines as sorted sets);
#   2. the fault case: a second array (3 tasks of 4) in a fresh directory; task 1's ringlet is
#      frozen (SIGSTOP) as soon as it runs and let run 10 ms at a time until it has finished an
#      item (so that the cancel lands mid-run whatever the load), then the task is cancelled
#      with `scancel JOB_1` (Slurm sends SIGCONT and SIGTERM: ringlet abandons its item and
#      ends); the task is CANCELLED, no partial folder is left,
#      `--slurm-unfinished` names exactly task 1; `sbatch --array=1` resubmits it, it skips the
#      items done and completes the dataset, equal to the single-process one, each item in the
#      manifests once.
# The daemons (and any job left) are stopped on exit, failure or not. About 20-40 s.
#
# What Slurm needs in a container without systemd, as root (found by hand, Debian 12's
# slurm-wlm 22.05.8 and munge 0.5.15):
#   - munged runs in the foreground (-F) with its own key (1024 random bytes, mode 0400, owned
#     by the user running it) and socket; the socket's directory must be searchable by everyone
#     (0755), or munged stops with "Socket is inaccessible: execute permissions for all
#     required". slurm.conf's AuthInfo=socket=PATH points Slurm (auth/munge and cred/munge) to it.
#   - slurmctld -D and slurmd -D in the foreground, the configuration from $SLURM_CONF (the
#     commands, sbatch included, read it too). SlurmctldHost=localhost is accepted whatever the
#     host name; the node is named with `slurmd -N ringlet1` (NodeHostname=localhost,
#     NodeAddr=127.0.0.1), so nothing depends on the container's host name.
#   - ProctrackType=proctrack/linuxproc and TaskPlugin=task/none: no cgroups (the default
#     proctrack/cgroup needs a writable cgroup hierarchy); JobAcctGatherType=jobacct_gather/none
#     and AccountingStorageType=accounting_storage/none (no slurmdbd: no sacct; finished jobs
#     stay visible to `scontrol show job` for MinJobAge, 300 s by default).
#   - SlurmUser=root and SlurmdUser=root: slurmd must be root to start jobs as their users.
#   - MailProg=/bin/true (Debian has no /bin/mail: slurmctld logs an error otherwise). The
#     "mpi/pmix ... can not load PMIx library" errors in the logs are harmless (MpiDefault=none).
#   - Non-default SlurmctldPort and SlurmdPort (free ports picked at start), state, spool, pid
#     and log files in the temporary directory: several runs, or a real Slurm, do not collide.
#
# Needs RINGLET (the built binary) and EXAMPLES (the examples/ directory); run by ctest as
# `slurm` (normal builds only: not in the sanitizer pass). Exits 77 (skipped) without the Slurm
# and munge programs or when not root; non-zero if any check failed.
set -u

: "${RINGLET:?set RINGLET to the ringlet binary}"
: "${EXAMPLES:?set EXAMPLES to the examples directory}"
PYTHON=/usr/bin/python3

for tool in munged slurmctld slurmd sbatch squeue sinfo scancel scontrol; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIP: $tool not found (scripts/setup.sh installs slurm-wlm and munge)"
    exit 77
  fi
done
if [ "$(id -u)" -ne 0 ]; then
  echo "SKIP: slurmd must run as root to start jobs"
  exit 77
fi

SPEC=$(cd "$EXAMPLES/batch" && pwd)/small.json
RINGLET=$(readlink -f "$RINGLET")  # as the script names it (/proc/self/exe)
work=$(mktemp -d "${TMPDIR:-/tmp}/ringlet_slurm.XXXXXX") || exit 1
chmod 0755 "$work"  # munged: the socket's directory must be searchable by everyone
export SLURM_CONF=$work/slurm.conf
daemons=()
jobs_submitted=()

watchdog=
cleanup() {
  [ -z "$watchdog" ] || kill "$watchdog" 2>/dev/null
  # Jobs first (slurmstepd outlives slurmd), then the daemons, youngest first.
  if [ ${#jobs_submitted[@]} -gt 0 ]; then
    timeout 10 scancel "${jobs_submitted[@]}" 2>/dev/null
    local deadline=$((SECONDS + 15))
    while [ -n "$(timeout 5 squeue -h 2>/dev/null)" ] && [ $SECONDS -lt $deadline ]; do
      sleep 0.2
    done
  fi
  local i
  for ((i = ${#daemons[@]} - 1; i >= 0; i--)); do kill "${daemons[i]}" 2>/dev/null; done
  for ((i = ${#daemons[@]} - 1; i >= 0; i--)); do wait "${daemons[i]}" 2>/dev/null; done
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # checks, fail, ok, run, expect_*

show_logs() {
  echo "--- slurmctld.log ---" >&2
  tail -n 30 "$work/slurmctld.log" >&2 2>/dev/null
  echo "--- slurmd.log ---" >&2
  tail -n 30 "$work/slurmd.log" >&2 2>/dev/null
  echo "--- squeue ---" >&2
  timeout 5 squeue >&2 2>/dev/null
}
die() {
  echo "FAIL: $*" >&2
  show_logs
  exit 1
}

# --- The daemons ---
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 2>/dev/null
chmod 0400 "$work/munge.key"
munged -F --socket="$work/munge.sock" --key-file="$work/munge.key" \
  --log-file="$work/munged.log" --pid-file="$work/munged.pid" --seed-file="$work/munged.seed" \
  >"$work/munged.out" 2>&1 &
daemons+=($!)

read -r ctl_port node_port < <("$PYTHON" -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
mkdir -p "$work/state" "$work/spool"
cat >"$SLURM_CONF" <<EOF
ClusterName=ringlettest
SlurmctldHost=localhost
SlurmctldPort=$ctl_port
SlurmdPort=$node_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge.sock
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
KillWait=5
NodeName=ringlet1 NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=ringlet1 Default=YES MaxTime=INFINITE State=UP
EOF

deadline=$((SECONDS + 20))
until [ -S "$work/munge.sock" ]; do
  [ $SECONDS -lt $deadline ] || die "munged did not start: $(cat "$work/munged.out")"
  sleep 0.1
done
slurmctld -D -i >"$work/slurmctld.out" 2>&1 &
daemons+=($!)
slurmd -D -N ringlet1 >"$work/slurmd.out" 2>&1 &
daemons+=($!)
# A watchdog for when this script is killed without its EXIT trap (ctest's timeout sends
# SIGKILL): once the script is gone, it stops every process that runs with this test's
# SLURM_CONF in its environment (the daemons, slurmstepd and the jobs, which slurmd would
# otherwise leave behind; no other process has this temporary path) and removes the directory.
test_pid=$$
(
  exec >/dev/null 2>&1  # ctest waits for the test's output to close: not for the watchdog's
  while kill -0 "$test_pid"; do sleep 1; done
  for signal in TERM KILL; do
    for entry in /proc/[0-9]*; do
      [ "${entry#/proc/}" != "$BASHPID" ] || continue
      mapfile -d '' environment 2>/dev/null <"$entry/environ" || continue
      for variable in "${environment[@]}"; do
        if [ "$variable" = "SLURM_CONF=$SLURM_CONF" ]; then
          kill "-$signal" "${entry#/proc/}"
          break
        fi
      done
    done
    sleep 1
  done
  rm -rf "$work"
) &
watchdog=$!
start=$SECONDS
deadline=$((SECONDS + 60))
until [ "$(sinfo -h -n ringlet1 -o %t 2>/dev/null)" = idle ]; do
  [ $SECONDS -lt $deadline ] || die "the node did not become idle: sinfo says \"$(sinfo -h -o %t 2>&1)\""
  sleep 0.2
done
echo "slurm: node idle after $((SECONDS - start)) s"

# wait_array JOB: until squeue lists none of its tasks (120 s at most).
wait_array() {
  local deadline=$((SECONDS + 120))
  while [ -n "$(timeout 10 squeue -h -j "$1" 2>/dev/null)" ]; do
    [ $SECONDS -lt $deadline ] || die "array $1 still queued or running after 120 s"
    sleep 0.1
  done
}

# task_state JOB TASK: "STATE EXITCODE" of one task from scontrol (kept for MinJobAge).
task_state() {
  scontrol -o show job "$1_$2" 2>/dev/null |
    sed -n 's/.*JobState=\([A-Z_]*\).* ExitCode=\([0-9:]*\).*/\1 \2/p' | head -n 1
}

# same_dataset WHAT DIR: DIR's items equal the reference's (all files but timing.json, no other
# file or folder but the manifests and slurm-logs), its manifests' lines the reference's.
same_dataset() {
  if diff -r -x timing.json -x 'manifest-*.jsonl' -x slurm-logs "$work/reference" "$2" \
    >"$work/diff" 2>&1; then ok; else
    fail "$1: the dataset differs from the single-process run: $(head -c 600 "$work/diff")"
  fi
  local missing=0 folder
  for folder in "$2"/item-*; do [ -f "$folder/timing.json" ] || missing=$((missing + 1)); done
  if [ "$missing" -eq 0 ]; then ok; else fail "$1: $missing item folders without timing.json"; fi
  if [ "$(cat "$2"/manifest-*.jsonl | sort)" = "$(sort "$work/reference/manifest-all.jsonl")" ]; then
    ok
  else
    fail "$1: the manifests' lines differ from the single-process run's (each item once):
$(cat "$2"/manifest-*.jsonl | sort | diff - <(sort "$work/reference/manifest-all.jsonl"))"
  fi
}

# --- The reference: one process ---
start=$(date +%s.%N)
"$RINGLET" batch "$SPEC" -o "$work/reference" -q || die "the single-process run failed"
single_s=$("$PYTHON" -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" \
  "$start" "$(date +%s.%N)")
[ "$(ls -d "$work/reference"/item-* | wc -l)" -eq 12 ] || die "the reference has not 12 items"

# --- 1. The undisturbed array: 4 tasks of 3 items ---
run batch "$SPEC" -o "$work/array" --slurm-script "$work/array.sh" --slurm-items-per-task 3 \
  --slurm-time 5
expect_rc "--slurm-script" 0
if grep -qx '#SBATCH --array=0-3' "$work/array.sh" &&
  grep -qF -- "--shard \"\${SLURM_ARRAY_TASK_ID}/4\"" "$work/array.sh" &&
  grep -qF -- "'$RINGLET' batch '$SPEC' -o '$work/array'" "$work/array.sh"; then ok; else
  fail "--slurm-script: the script lacks the array, the shard or the absolute paths: $(cat "$work/array.sh")"
fi
start=$(date +%s.%N)
job=$(cd / && sbatch --parsable "$work/array.sh") || die "sbatch failed"
jobs_submitted+=("$job")
wait_array "$job"
array_s=$("$PYTHON" -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" \
  "$start" "$(date +%s.%N)")
for task in 0 1 2 3; do
  state=$(task_state "$job" $task)
  if [ "$state" = "COMPLETED 0:0" ]; then ok; else
    fail "array task $task: \"$state\", expected COMPLETED 0:0; its log: $(cat "$work/array/slurm-logs/"*"-${job}_$task.out" 2>&1)"
  fi
done
same_dataset "the array of 4 tasks" "$work/array"
expect_files "the array's manifests" "$work/array" spec.json slurm-logs \
  $(cd "$work/reference" && ls -d item-*) manifest-shard-{0,1,2,3}-of-4.jsonl
run batch "$SPEC" -o "$work/array" --slurm-unfinished --slurm-items-per-task 3
if [ "$rc" -eq 0 ] && [ ! -s "$work/stdout" ]; then ok; else
  fail "--slurm-unfinished after a complete array: rc $rc, printed \"$(cat "$work/stdout")\""
fi
echo "slurm: 12 items: single process ${single_s} s; array of 4 tasks, sbatch to the last task's end ${array_s} s"

# --- 2. A task cancelled mid-run, then resubmitted: 3 tasks of 4 items ---
run batch "$SPEC" -o "$work/fault" --slurm-script "$work/fault.sh" --slurm-tasks 3
expect_rc "--slurm-script --slurm-tasks 3" 0
job=$(cd / && sbatch --parsable "$work/fault.sh") || die "sbatch failed"
jobs_submitted+=("$job")
log=$work/fault/slurm-logs/ringlet-small-${job}_1.out
# Task 1's ringlet (the script execs it), found by its exact command line (unique: it names
# this test's temporary directory), frozen as soon as it runs, then let run 10 ms at a time
# until it has finished an item (the small items take 20 ms or more: 50-ms steps often let two
# through): cancelled with 1 (rarely 2) of its 4 items done, whatever the machine's load. Every signal goes to that one checked pid only.
task_line="$RINGLET batch $SPEC -o $work/fault --shard 1/3 --threads 1"
# read_command_line PID: $cmdline = its arguments joined by spaces (builtins only, no fork).
read_command_line() {
  local args
  cmdline=
  mapfile -d '' args 2>/dev/null <"/proc/$1/cmdline" || return 1
  cmdline="${args[*]}"
}
task_pid() {  # the processes whose command line is $task_line (none: nothing printed)
  local entry found=
  for entry in /proc/[0-9]*; do
    read_command_line "${entry#/proc/}" && [ "$cmdline" = "$task_line" ] &&
      found="$found${found:+ }${entry#/proc/}"
  done
  printf '%s' "$found"
}
pid=
deadline=$((SECONDS + 60))
while [ -z "$pid" ]; do
  [ $SECONDS -lt $deadline ] || die "task 1 did not start in 60 s"
  pid=$(task_pid)
  [ -n "$pid" ] || sleep 0.02
done
signal_task() {  # signal_task SIGNAL: to task 1's ringlet, after checking the pid is still it
  if ! [[ "$pid" =~ ^[1-9][0-9]*$ ]] || [ "$pid" -le 1 ] ||
    ! read_command_line "$pid" || [ "$cmdline" != "$task_line" ]; then
    die "task 1's process \"$pid\" is not (or no longer) $task_line"
  fi
  kill "-$1" "$pid"
}
signal_task STOP
done_items() { ls "$work/fault"/item-00000000{4,5,6,7}/done 2>/dev/null | wc -l; }
deadline=$((SECONDS + 60))
until [ "$(done_items)" -ge 1 ]; do
  [ $SECONDS -lt $deadline ] || die "task 1 finished no item in 60 s: $(cat "$log" 2>&1)"
  signal_task CONT
  sleep 0.01
  signal_task STOP
done
scancel "${job}_1"
wait_array "$job"
state=$(task_state "$job" 1)
if [ "${state%% *}" = CANCELLED ]; then ok; else fail "cancelled task 1: \"$state\""; fi
for task in 0 2; do
  state=$(task_state "$job" $task)
  if [ "$state" = "COMPLETED 0:0" ]; then ok; else fail "array task $task: \"$state\""; fi
done
if grep -q 'stopped by a signal' "$log"; then ok; else
  fail "task 1 did not end by its SIGTERM: $(cat "$log")"
fi
done_before=$(ls "$work/fault"/item-00000000{4,5,6,7}/done 2>/dev/null | wc -l)
echo "slurm: task 1 cancelled with $done_before of its 4 items done"
if [ "$done_before" -ge 1 ] && [ "$done_before" -le 3 ]; then ok; else
  fail "task 1 (items 4 to 7) had $done_before items done when cancelled, expected 1 to 3"
fi
partial=$(find "$work/fault" -maxdepth 1 \( -name '.item-*' -o \( -name 'item-*' \
  ! -exec test -f '{}/done' \; \) \) -print | wc -l)
if [ "$partial" -eq 0 ]; then ok; else fail "$partial partial item folders after the cancel"; fi
run batch "$SPEC" -o "$work/fault" --slurm-unfinished --slurm-tasks 3
if [ "$rc" -eq 0 ] && [ "$(cat "$work/stdout")" = 1 ]; then ok; else
  fail "--slurm-unfinished after the cancel: rc $rc, printed \"$(cat "$work/stdout")\", expected 1"
fi
ids=$(cat "$work/stdout")
job2=$(cd / && sbatch --parsable --array="$ids" "$work/fault.sh") || die "sbatch --array=$ids failed"
jobs_submitted+=("$job2")
wait_array "$job2"
state=$(task_state "$job2" 1)
if [ "$state" = "COMPLETED 0:0" ]; then ok; else fail "resubmitted task 1: \"$state\""; fi
if grep -q "$((4 - done_before)) done, 0 flagged, 0 failed, $done_before skipped" \
  "$work/fault/slurm-logs/ringlet-small-${job2}_1.out"; then ok; else
  fail "the resubmitted task did not skip the $done_before items done: $(cat "$work/fault/slurm-logs/ringlet-small-${job2}_1.out")"
fi
same_dataset "the array with a task cancelled and resubmitted" "$work/fault"

echo "slurm: $checks checks, $failures failed"
[ "$failures" -eq 0 ] || show_logs
[ "$failures" -eq 0 ]
