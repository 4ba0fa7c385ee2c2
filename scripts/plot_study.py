#!/usr/bin/env python3
"""Plots of a lieflow work-precision study: DIR/study.csv and DIR/drift.csv in,
DIR/work_precision.png, DIR/energy_drift.png and DIR/momentum_drift.png out.

Usage: plot_study.py DIR
"""
import csv
import math
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return math.nan
    return v


def main(directory):
    study = read_rows(f"{directory}/study.csv")
    scene = study[0]["scene"] if study else "?"
    by_integrator = defaultdict(list)
    for r in study:
        if r["failed"] == "true":
            continue
        err = number(r["orientation_error"])
        t = number(r["wall_seconds"])
        if err > 0 and t > 0 and math.isfinite(err):
            by_integrator[r["integrator"]].append((t, err, number(r["dt"])))

    fig, ax = plt.subplots(figsize=(7, 5))
    for name, pts in sorted(by_integrator.items()):
        pts.sort()
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=name, markersize=4)
    ax.set_xlabel("run time [s] (median of repeated runs)")
    ax.set_ylabel("orientation error at t_end [rad]")
    ax.set_title(f"work-precision: {scene}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{directory}/work_precision.png", dpi=120)
    plt.close(fig)

    drift = read_rows(f"{directory}/drift.csv")
    curves = defaultdict(lambda: ([], [], []))
    for r in drift:
        c = curves[r["integrator"]]
        c[0].append(number(r["t"]))
        c[1].append(abs(number(r["energy_error"])))
        c[2].append(number(r["momentum_error"]))
    for key, label, filename in ((1, "relative energy error |E - E0|/|E0|", "energy_drift.png"),
                                 (2, "relative momentum error |L - L0|/|L0|", "momentum_drift.png")):
        fig, ax = plt.subplots(figsize=(7, 5))
        plotted = False
        for name, c in sorted(curves.items()):
            pts = [(t, v) for t, v in zip(c[0], c[key]) if math.isfinite(v) and v > 0]
            if pts:
                ax.semilogy([p[0] for p in pts], [p[1] for p in pts], label=name)
                plotted = True
        ax.set_xlabel("t [s]")
        ax.set_ylabel(label)
        dt = drift[0]["dt"] if drift else "?"
        ax.set_title(f"{scene}, dt = {dt}" + ("" if plotted else " (not conserved in this scene)"))
        ax.grid(True, which="both", alpha=0.3)
        if plotted:
            ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(f"{directory}/{filename}", dpi=120)
        plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
