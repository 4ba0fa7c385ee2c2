#!/usr/bin/env python3
"""Plot of a lieflow stability study: DIR/stability.csv in, DIR/stability.png out
(largest bounded h*omega_c per integrator, one group of bars per scene).

A limit below the grid (nothing bounded even at the smallest h*omega_c) is
drawn as a short red cross-hatched bar labelled "< 0.01", a run bounded on the whole grid as
a hatched bar labelled ">= 100" (a lower bound, not a measured limit).

Usage: plot_stability.py DIR
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

GRID_MIN, GRID_MAX = 0.01, 100.0


def human(v):
    return f"{v:.3g}"


def main(directory):
    with open(f"{directory}/stability.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    scenes = sorted({r["scene"] for r in rows})
    integrators = []
    for r in rows:
        if r["integrator"] not in integrators:
            integrators.append(r["integrator"])
    width = 0.8 / max(1, len(scenes))
    fig, ax = plt.subplots(figsize=(10, 6))
    floor = GRID_MIN / 3
    for k, scene in enumerate(scenes):
        xs = [i + (k - (len(scenes) - 1) / 2) * width for i in range(len(integrators))]
        color = f"C{k}"
        labelled = False
        for x, name in zip(xs, integrators):
            match = [r for r in rows if r["scene"] == scene and r["integrator"] == name]
            if not match:
                continue
            v = float(match[0]["h_omega_max"] or 0.0)
            whole = match[0]["bounded_on_whole_grid"] == "true"
            label = None if labelled else scene
            if v <= 0:
                ax.bar(x, GRID_MIN - floor, width, bottom=floor, color="none", edgecolor="darkred", hatch="xx")
                ax.text(x, GRID_MIN * 1.1, f"< {human(GRID_MIN)}", ha="center", va="bottom", fontsize=7,
                        color="darkred", rotation=90)
            else:
                ax.bar(x, v - floor, width, bottom=floor, color=color, label=label, hatch="//" if whole else None)
                labelled = True
                ax.text(x, v * 1.1, (">= " if whole else "") + human(v), ha="center", va="bottom", fontsize=7,
                        rotation=90)
    ax.set_yscale("log")
    ax.set_ylim(floor, GRID_MAX * 20)
    ax.set_xticks(range(len(integrators)))
    ax.set_xticklabels(integrators, rotation=30, ha="right")
    ax.set_ylabel("largest bounded h * omega_c\n(hatched: bounded on the whole grid, a lower bound;\n"
                  "red x: not bounded even at the grid's start)", fontsize=9)
    ax.set_title(f"stability limits (grid {human(GRID_MIN)} ... {human(GRID_MAX)})")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{directory}/stability.png", dpi=120)
    plt.close(fig)
    below = sum(1 for r in rows if float(r["h_omega_max"] or 0.0) <= 0)
    beyond = sum(1 for r in rows if r["bounded_on_whole_grid"] == "true")
    print(f"stability.png: {len(rows)} bars, {below} below the grid, {beyond} bounded on the whole grid")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
