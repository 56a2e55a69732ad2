#!/usr/bin/env python3
"""Measures `ringlet solve`'s CPU time per strand against the library's SolveStrand (issue 11).

  scripts/cli_overhead.py BUILD_DIR [--strands 10000] [--rounds 8]

BUILD_DIR is a Release build with benchmarks (-DRINGLET_BUILD_BENCHMARKS=ON) holding `ringlet` and
`bench/ringlet_cli_bench`. The scene is N copies of the 15-segment curly strand of
examples/vertical_curly.json (scripts/make_many_strands.py). Each round runs the command once
(`ringlet solve SCENE -o OUT --force --quiet --threads 1`; its user + sys CPU time from the
kernel's child accounting) and then the library benchmark once (BM_LibrarySolveStrand/stability:1,
Google Benchmark's CPU time per solve), so that both see the same state of the machine; the
machine's drift (several per cent within an hour on the 2-core VM, docs/benchmarks.md) then cancels
in each round's ratio. Prints every round, then the median and the smallest ratio.
"""
import argparse
import json
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def command_cpu_seconds(argv):
    """User + sys CPU seconds of one run of argv (which must succeed)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def library_seconds_per_solve(bench):
    """CPU seconds of one SolveStrand of the example strand, stability check on."""
    out = subprocess.run(
        [bench, "--benchmark_filter=BM_LibrarySolveStrand/stability:1$",
         "--benchmark_min_time=0.5", "--benchmark_format=json"],
        check=True, capture_output=True, text=True).stdout
    run = json.loads(out)["benchmarks"][0]
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[run["time_unit"]]
    return run["cpu_time"] * scale


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", help="Release build directory with benchmarks")
    parser.add_argument("--strands", type=int, default=10000, help="strands in the scene")
    parser.add_argument("--rounds", type=int, default=8, help="command + benchmark pairs")
    args = parser.parse_args()
    if args.strands < 1 or args.rounds < 1:
        sys.exit("cli_overhead.py: --strands and --rounds must be at least 1")
    build = pathlib.Path(args.build)
    ringlet = build / "ringlet"
    bench = build / "bench" / "ringlet_cli_bench"
    for path in (ringlet, bench):
        if not path.is_file():
            sys.exit(f"cli_overhead.py: {path} not found (build with -DRINGLET_BUILD_BENCHMARKS=ON)")

    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "many.json")
        out = os.path.join(tmp, "out.json")
        subprocess.run([sys.executable, str(ROOT / "scripts" / "make_many_strands.py"),
                        str(ROOT / "examples" / "vertical_curly.json"), str(args.strands), scene],
                       check=True)
        ratios = []
        for k in range(args.rounds):
            command = command_cpu_seconds([str(ringlet), "solve", scene, "-o", out, "--force",
                                           "--quiet", "--threads", "1"]) / args.strands
            library = library_seconds_per_solve(str(bench))
            ratios.append(command / library)
            print(f"round {k + 1}: command {command * 1e6:.1f} us/strand, "
                  f"library {library * 1e6:.1f} us, ratio {ratios[-1]:.3f}", flush=True)
    print(f"ratio: median {statistics.median(ratios):.3f}, smallest {min(ratios):.3f}, "
          f"largest {max(ratios):.3f} over {args.rounds} rounds")


if __name__ == "__main__":
    main()
