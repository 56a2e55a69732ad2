#!/usr/bin/env python3
"""Plots of the strand dynamics' validation and cost (docs/validation.md "Dynamics",
docs/benchmarks.md "Hair in motion") from the CSVs in docs/data/dynamics/:

  ./build/tools/dynamics_study docs/data/dynamics          # rotating_clamp*, time_convergence,
                                                           # energy*, stable_steps
  ./build-bench/bench/ringlet_dynamics_bench --benchmark_filter=BM_StrandStep \
      --benchmark_out=docs/data/dynamics/step_cost.csv --benchmark_out_format=csv
  /usr/bin/python3 scripts/plot_dynamics.py [DATA_DIR] [IMAGE_DIR]

Writes dynamics_rotating_clamp.png, dynamics_time_convergence.png, dynamics_energy.png and
dynamics_step_cost.png, and prints the fitted exponent of the step cost against n.
"""
import csv
import io
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DATA = sys.argv[1] if len(sys.argv) > 1 else "docs/data/dynamics"
IMAGES = sys.argv[2] if len(sys.argv) > 2 else "docs/images"


def rows(name):
    with open(os.path.join(DATA, name), newline="") as f:
        text = f.read()
    # Google Benchmark's CSV starts with context lines before the header.
    start = text.find("name,iterations")
    if start > 0:
        text = text[start:]
    return list(csv.DictReader(io.StringIO(text)))


def rotating_clamp():
    data = rows("rotating_clamp_shapes.csv")
    fig, ax = plt.subplots(figsize=(6, 4))
    styles = {"static": ("0.6", "--", "at rest (SolveStrand)"),
              "reference": ("k", "-", "reference: shooting, relative equilibrium"),
              "simulated": ("C3", ":", "simulated (BDF2, n = 40, 3 s)")}
    for curve, (colour, line, label) in styles.items():
        pts = [r for r in data if r["curve"] == curve]
        ax.plot([100 * float(r["x"]) for r in pts], [100 * float(r["z"]) for r in pts],
                line, color=colour, lw=2 if curve != "simulated" else 2.5, label=label)
    ax.axvline(0.0, color="0.8", lw=1)
    ax.set_xlabel("distance from the rotation axis (cm)")
    ax.set_ylabel("height (cm)")
    ax.set_title("15-cm rod on a clamp turning at 10 rad/s")
    ax.set_aspect("equal")
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(os.path.join(IMAGES, "dynamics_rotating_clamp.png"), dpi=110)


def time_convergence():
    data = rows("time_convergence.csv")
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for scheme, label, colour in (("backward_euler", "backward Euler", "C0"), ("bdf2", "BDF2", "C1")):
        pts = [r for r in data if r["scheme"] == scheme]
        h = np.array([float(r["h"]) for r in pts])
        e = np.array([float(r["error_L"]) for r in pts])
        ax.loglog(h, e, "o-", color=colour, label=label)
    h = np.array([6.5e-4, 4.2e-2])
    ax.loglog(h, 6 * h, "k:", lw=1, label="slope 1")
    ax.loglog(h, 20 * h ** 2, "k--", lw=1, label="slope 2")
    ax.axvline(1 / 24, color="0.8", lw=1)
    ax.set_xlabel("time step h (s)")
    ax.set_ylabel("max centreline error at t = 0.5 s (/ L)")
    ax.set_title("curly strand released horizontally")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(IMAGES, "dynamics_time_convergence.png"), dpi=110)


def energy():
    data = rows("energy.csv")
    fig, ax = plt.subplots(figsize=(6, 4))
    for case, label, colour in (("backward_euler_1ms", "backward Euler, h = 1 ms", "C0"),
                                ("bdf2_1ms", "BDF2, h = 1 ms", "C1"),
                                ("backward_euler_frame", "backward Euler, h = 1/24 s", "C2"),
                                ("bdf2_frame", "BDF2, h = 1/24 s", "C3")):
        pts = [r for r in data if r["case"] == case]
        t = [float(r["time"]) for r in pts]
        e = [max(float(r["energy_above_equilibrium_rel"]), 1e-12) for r in pts]
        ax.semilogy(t, e, color=colour, label=label)
    ax.set_xlim(0, 10)
    ax.set_ylim(1e-7, 2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy above equilibrium / at start")
    ax.set_title("undamped 10-cm curly strand (10\u2074 steps per scheme)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(IMAGES, "dynamics_energy.png"), dpi=110)


def step_cost():
    data = [r for r in rows("step_cost.csv") if r["name"].startswith("BM_StrandStep/")]
    n = np.array([int(r["name"].split("/")[1]) for r in data])
    per_step = np.array([float(r["us_per_step"]) for r in data]) * 1e6  # us
    per_newton = np.array([float(r["us_per_newton"]) for r in data]) * 1e6
    fits = {}
    for name, y in (("step", per_step), ("newton", per_newton)):
        slope, intercept = np.polyfit(np.log(n), np.log(y), 1)
        fits[name] = (slope, intercept)
        print(f"cost per {name} ~ n^{slope:.3f} (n = {n.min()}..{n.max()})")
    keep = n >= 10
    slope10 = np.polyfit(np.log(n[keep]), np.log(per_step[keep]), 1)[0]
    print(f"cost per step ~ n^{slope10:.3f} (n = 10..{n.max()}, constant Newton count)")
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.loglog(n, per_step, "o-", label=f"per step (fit n^{fits['step'][0]:.2f})")
    ax.loglog(n, per_newton, "s-", label=f"per Newton iteration (fit n^{fits['newton'][0]:.2f})")
    ax.set_xlabel("segments n")
    ax.set_ylabel("CPU time (\u00b5s)")
    ax.set_title("one implicit step, h = 1/24 s, one thread")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(IMAGES, "dynamics_step_cost.png"), dpi=110)


if __name__ == "__main__":
    os.makedirs(IMAGES, exist_ok=True)
    rotating_clamp()
    time_convergence()
    energy()
    step_cost()
