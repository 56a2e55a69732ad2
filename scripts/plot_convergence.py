#!/usr/bin/env python3
"""Plots the tip error of the 3D solver against the heavy-elastica reference.

    /usr/bin/python3 scripts/plot_convergence.py docs/data/convergence.csv docs/images/convergence.png

Reads the CSV written by tools/convergence_study (columns load, grading, n, ratio,
tip_error_over_L, iterations, seconds, converged) and draws tip error / L against the segment
count n on log-log axes: one colour per load w L^3 / EI, solid lines for graded segments, dashed
for uniform ones, with the 1e-4 L target. Prints the fitted order of each curve (n >= 10).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
import numpy as np  # noqa: E402

TARGET = 1e-4
MIN_FIT_SEGMENTS = 10


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    required = {"load", "grading", "n", "ratio", "tip_error_over_L"}
    if not rows or not required.issubset(rows[0].keys()):
        raise SystemExit(f"{path}: expected a CSV with columns {sorted(required)}")
    return rows


def main(argv):
    if len(argv) != 3:
        raise SystemExit(f"usage: {argv[0]} CONVERGENCE.csv OUTPUT.png")
    csv_path, png_path = argv[1], argv[2]
    rows = read_rows(csv_path)
    loads = sorted({float(r["load"]) for r in rows})
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, len(loads)))

    fig, ax = plt.subplots(figsize=(9.5, 5.0), dpi=120)
    for load, colour in zip(loads, colours):
        for grading, style in (("graded", "-"), ("uniform", "--")):
            curve = sorted(
                (int(r["n"]), float(r["tip_error_over_L"]), float(r["ratio"]))
                for r in rows
                if float(r["load"]) == load and r["grading"] == grading
            )
            if not curve:
                continue
            n = np.array([c[0] for c in curve], dtype=float)
            err = np.array([c[1] for c in curve])
            ratio = curve[0][2]
            fit = n >= MIN_FIT_SEGMENTS
            order = -np.polyfit(np.log(n[fit]), np.log(err[fit]), 1)[0]
            label = f"wL³/EI = {load:g}, {grading}"
            if grading == "graded":
                label += f" (ratio {ratio:.3g})"
            label += f", order {order:.2f}"
            ax.loglog(n, err, style, marker="o", markersize=3.5, color=colour, label=label)
            print(f"load {load:g} {grading}: order {order:.2f}")
    ax.axhline(TARGET, color="crimson", linewidth=1.0, linestyle=":", label="target 1e-4 L")
    ax.set_xlabel("segments n")
    ax.set_ylabel("tip error / L")
    ax.set_title("Heavy cantilever (horizontal clamp): 3D solver vs planar elastica")
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()

    # Write to a temporary file and rename: nothing half-written.
    directory = os.path.dirname(png_path)
    if directory:
        os.makedirs(directory, exist_ok=True)
    temporary = png_path + ".tmp.png"
    fig.savefig(temporary)
    os.replace(temporary, png_path)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    main(sys.argv)
