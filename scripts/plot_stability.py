#!/usr/bin/env python3
"""Plot of a lieflow stability study: DIR/stability.csv in, DIR/stability.png out
(largest bounded h*omega_c per integrator, one group of bars per scene).

Usage: plot_stability.py DIR
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(directory):
    with open(f"{directory}/stability.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    scenes = sorted({r["scene"] for r in rows})
    integrators = []
    for r in rows:
        if r["integrator"] not in integrators:
            integrators.append(r["integrator"])
    width = 0.8 / max(1, len(scenes))
    fig, ax = plt.subplots(figsize=(9, 5))
    for k, scene in enumerate(scenes):
        values, hatches = [], []
        for name in integrators:
            match = [r for r in rows if r["scene"] == scene and r["integrator"] == name]
            v = float(match[0]["h_omega_max"]) if match else 0.0
            values.append(v if v > 0 else float("nan"))
            hatches.append(match and match[0]["bounded_on_whole_grid"] == "true")
        xs = [i + (k - (len(scenes) - 1) / 2) * width for i in range(len(integrators))]
        bars = ax.bar(xs, values, width, label=scene)
        for bar, whole in zip(bars, hatches):
            if whole:
                bar.set_hatch("//")
    ax.set_yscale("log")
    ax.set_xticks(range(len(integrators)))
    ax.set_xticklabels(integrators, rotation=30, ha="right")
    ax.set_ylabel("largest bounded h * omega_c (hatched: bounded on the whole grid)")
    ax.set_title("stability limits")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(f"{directory}/stability.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
