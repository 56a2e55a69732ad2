#!/usr/bin/python3
"""Images of docs/validation.md, "Hanging curls", from the CSV files of tools/hanging_curl_study.

usage: /usr/bin/python3 scripts/plot_hanging_curls.py CSV_DIRECTORY IMAGE_DIRECTORY

Writes hanging_curl_phase_diagram.png, hanging_curls.png, curl_regularity.png and
hanging_curl_profile.png into IMAGE_DIRECTORY.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LOCALIZED_FRACTION = 0.2  # tests/hanging_curl_measures.h, kLocalizedFraction
PLANAR_BOUNDARY = 1.7     # measured kappa0 l_gb between planar and 3D (see docs)


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def phase_diagram(rows, out):
    fig, ax = plt.subplots(figsize=(10.5, 5.5))
    styles = {
        "planar": dict(marker="s", color="tab:blue", label="planar curl"),
        "planar_self": dict(marker="x", color="tab:gray",
                            label="planar, passes through itself (no self-contact)"),
        "localized": dict(marker="o", color="tab:orange", label="localized helix"),
        "global": dict(marker="^", color="tab:green", label="global helix"),
    }
    seen = set()
    c0 = None
    for r in rows:
        k, load = float(r["kappa0_L"]), float(r["load"])
        regime = r["regime"]
        if regime == "planar" and float(r["self_distance_over_diameter"]) < 1.0:
            regime = "planar_self"
        style = dict(styles[regime])
        label = style.pop("label")
        ax.scatter(k, load, s=40, label=None if regime in seen else label, **style)
        seen.add(regime)
        if r["termination"] != "converged":
            ax.scatter(k, load, s=140, facecolors="none", edgecolors="red",
                       label=None if "nc" in seen else "not converged (5000 iterations)")
            seen.add("nc")
        c0 = float(r["spring_curled_fraction"]) * load / k**2
    ks = [10 ** (i / 50) for i in range(0, 101)]
    ax.plot(ks, [c0 * k * k / (1 - LOCALIZED_FRACTION) for k in ks], "k-",
            label="helical spring: curled length = %.1f L" % (1 - LOCALIZED_FRACTION))
    ax.plot(ks, [(k / PLANAR_BOUNDARY) ** 3 for k in ks], "k--",
            label="measured planar/3D: $\\kappa^0 \\ell_{gb}$ = %.1f" % PLANAR_BOUNDARY)
    ax.axvline(2 * math.pi, color="k", ls=":", label="$\\kappa^0 L = 2\\pi$ (one natural turn)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(0.8, 100)
    ax.set_ylim(0.7, 1.5e4)
    ax.set_xlabel("natural curvature $\\kappa^0 L$")
    ax.set_ylabel("weight $w L^3 / EI$")
    ax.set_title("Hanging naturally curved strand (circular, $\\tau^0 = 0$), clamped pointing down\n"
                 "planar: out of plane < 1e-3 L; localized: stretched part > 0.2 L "
                 "($\\kappa < \\kappa^0/2$)", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def shapes(rows, out):
    cases = []
    for r in rows:
        if r["case"] not in cases:
            cases.append(r["case"])
    fig = plt.figure(figsize=(4 * len(cases), 5.5))
    for i, case in enumerate(cases):
        pts = [(float(r["x_over_L"]), float(r["y_over_L"]), float(r["z_over_L"]))
               for r in rows if r["case"] == case]
        ax = fig.add_subplot(1, len(cases), i + 1, projection="3d")
        xs, ys, zs = zip(*pts)
        ax.plot(xs, ys, zs, lw=1.2)
        ax.scatter([0], [0], [0], color="k", s=15)
        half = max(max(map(abs, xs)), max(map(abs, ys)), 0.05)
        ax.set_xlim(-half, half)
        ax.set_ylim(-half, half)
        ax.set_zlim(min(zs) - 0.02, 0.02)
        ax.set_box_aspect((1, 1, max(1.0, (0.04 - min(zs)) / (2 * half))))
        ax.set_title(case, fontsize=8)
        ax.set_xlabel("x/L", fontsize=7)
        ax.set_ylabel("y/L", fontsize=7)
        ax.set_zlabel("z/L", fontsize=7)
        ax.tick_params(labelsize=6)
        ax.locator_params(nbins=3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def regularity(rows, out):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, series in zip(axes, ["same fibre", "same load"]):
        bases = sorted({float(r["base_load"]) for r in rows if r["series"] == series})
        for base in bases:
            sel = [r for r in rows if r["series"] == series and float(r["base_load"]) == base]
            e = [float(r["eccentricity"]) for r in sel]
            irr = [float(r["irregularity_lower_half"]) for r in sel]
            ax.plot(e, irr, "o-", label="$wL^3/EI_1$ = %g at e = 0" % base)
        ax.set_xlabel("eccentricity e")
        ax.set_title(series + (" (density fixed: load grows as 1/$\\sqrt{1-e^2}$)"
                               if series == "same fibre" else " (density set to keep $wL^3/EI_1$)"),
                     fontsize=9)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("curl irregularity, lower half\n(RMS wobble of ($\\kappa$, $\\tau$) / $|\\Omega^0|$)")
    fig.suptitle("Natural helix R0 = p0 = 1 cm, L = 25 cm; lower = more regular", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def profile(rows, out):
    s = [float(r["s_over_L"]) for r in rows]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.plot(s, [float(r["kappa_over_kappa0"]) for r in rows], "o", ms=3, label="ringlet, $\\kappa/\\kappa^0$")
    ax.plot(s, [float(r["spring_kappa_over_kappa0"]) for r in rows], "-",
            label="helical spring at $F = w(L-s)$")
    ax.plot(s, [float(r["radius_over_R0"]) for r in rows], "s", ms=3, label="ringlet, $R/R^0$")
    ax.plot(s, [float(r["descent"]) for r in rows], "^", ms=3, label="descent $-t\\cdot\\hat z$")
    ax.axhline(0.5, color="gray", lw=0.5)
    ax.set_xlabel("s / L (root to tip)")
    ax.set_title("Natural helix R0 = p0 = 5 mm, $wL^3/EI$ = 6000, n = 100", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_hanging_curls.py CSV_DIRECTORY IMAGE_DIRECTORY")
    data, images = sys.argv[1], sys.argv[2]
    phase_diagram(read(os.path.join(data, "phase_diagram.csv")),
                  os.path.join(images, "hanging_curl_phase_diagram.png"))
    shapes(read(os.path.join(data, "shapes.csv")), os.path.join(images, "hanging_curls.png"))
    regularity(read(os.path.join(data, "regularity.csv")),
               os.path.join(images, "curl_regularity.png"))
    profile(read(os.path.join(data, "profile.csv")),
            os.path.join(images, "hanging_curl_profile.png"))


if __name__ == "__main__":
    main()
