#!/usr/bin/python3
"""Table and figure of the Cardan-joint speed ratio from lieflow's output.

Usage: analyze.py OUT_DIR PAPER_DIR
  OUT_DIR   what reproduce.sh wrote: betaB_hH.csv (trajectories, every step)
            and betaB_hH.json (--stats) for each bend angle B (degrees) and
            step H, machine.txt
  PAPER_DIR where speed_ratio.png goes and whose README.md receives the table
            (between the GENERATED markers)

The formula: omega2 = omega1 cos(beta) / (1 - sin(beta)^2 cos(theta1)^2), with
theta1 the input joint angle (column input-bearing.phi), zero where the input's
cross arm lies in the plane of the two shafts; omega1 = input-bearing.phidot,
omega2 = output-bearing.phidot (the output's rate about its bearing).
"""
import csv
import glob
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from paper_common import splice_readme  # noqa: E402

DPI = 100
H_FIGURE = 0.001  # the step of the figure and of the headline column


def formula(theta1, omega1, beta):
    return omega1 * np.cos(beta) / (1.0 - np.sin(beta) ** 2 * np.cos(theta1) ** 2)


def sensitivity(omega1, beta):
    """max over a revolution of |∂ω₂/∂θ₁| (rad/s per rad), from the formula."""
    theta = np.linspace(0.0, 2 * math.pi, 200001)
    return float(np.abs(np.gradient(formula(theta, omega1, beta), theta)).max())


def read_run(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    col = lambda name: np.array([float(r[name]) for r in rows])  # noqa: E731
    return {
        "t": col("t"),
        "theta1": col("input-bearing.phi"),
        "omega1": col("input-bearing.phidot"),
        "omega2": col("output-bearing.phidot"),
        "spin2": col("output.wx"),
    }


def fmt(v, digits=2):
    if v is None or not math.isfinite(v):
        return "—"
    return "0" if v == 0 else f"{v:.{digits}e}"


def main(out, paper):
    runs = {}
    for path in glob.glob(os.path.join(out, "beta*_h*.csv")):
        m = re.match(r"beta(\d+)_h([0-9.e-]+)\.csv$", os.path.basename(path))
        beta_deg, h = int(m.group(1)), float(m.group(2))
        run = read_run(path)
        with open(path[:-4] + ".json") as f:
            run["stats"] = json.load(f)
        beta = math.radians(beta_deg)
        run["formula"] = formula(run["theta1"], run["omega1"], beta)
        run["error"] = np.abs(run["omega2"] - run["formula"])
        if run["theta1"][-1] < 2 * math.pi:
            sys.exit(f"analyze.py: {path} covers theta1 up to {run['theta1'][-1]:.3f} rad, less than a revolution")
        runs[(beta_deg, h)] = run
    betas = sorted({b for b, _ in runs})
    steps = sorted({h for _, h in runs}, reverse=True)
    if not betas or H_FIGURE not in steps:
        sys.exit(f"analyze.py: no runs at h = {H_FIGURE} in {out}")

    with open(os.path.join(out, "machine.txt")) as f:
        machine = f.read().strip().splitlines()
    md = ["`" + "`, `".join(machine) + "`", ""]
    head = "| β | ω₂/ω₁ simulated: min … max | cos β … 1/cos β |"
    sep = "|---|---|---|"
    for h in steps:
        head += f" max \\|ω₂ − formula\\| (rad/s), h = {h:g} |"
        sep += "---|"
    head += (" max relative error | max \\|ω₂ − output.wx\\| | constraint error |"
             " 1e-12 rad × max \\|∂ω₂/∂θ₁\\| |")
    sep += "---|---|---|---|"
    md += [head, sep]
    for b in betas:
        r = runs[(b, H_FIGURE)]
        beta = math.radians(b)
        ratio = r["omega2"] / r["omega1"]
        line = (f"| {b}° | {ratio.min():.10f} … {ratio.max():.10f} | "
                f"{math.cos(beta):.10f} … {1 / math.cos(beta):.10f} |")
        errs = [runs[(b, h)]["error"].max() for h in steps]
        line += "".join(f" {fmt(e)} |" for e in errs)
        line += (f" {fmt((r['error'] / r['formula']).max())} | {fmt(np.abs(r['spin2'] - r['omega2']).max())} |"
                 f" {fmt(r['stats']['constraint_error'])} | {fmt(1e-12 * sensitivity(r['omega1'][0], beta))} |")
        md.append(line)
    md += ["", f"Over t ∈ [0, {runs[(betas[0], H_FIGURE)]['t'][-1]:g}] s, θ₁ ∈ [0, "
               f"{runs[(betas[0], H_FIGURE)]['theta1'][-1]:.3f}] rad (more than one revolution), every step; "
               f"ω₁ = {runs[(betas[0], H_FIGURE)]['omega1'][0]:g} rad/s. Relative error: max of "
               f"\\|ω₂ − formula\\| / formula at h = {H_FIGURE:g}; constraint error: max \\|Φ\\| of the run "
               f"(`--stats`), h = {H_FIGURE:g}."]
    text = "\n".join(md)
    splice_readme(os.path.join(paper, "README.md"), text)
    print(text)

    # Figure: the ratio over one revolution, simulation against the formula,
    # and the error along it (largest error in each 5° bin: the row-to-row
    # values jump between rounding level and the bin's maximum).
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 5.2))
    colors = plt.cm.viridis(np.linspace(0.0, 0.85, len(betas)))
    fine = np.linspace(0.0, 2 * math.pi, 721)
    edges = np.arange(0, 361, 5)
    for b, c in zip(betas, colors):
        r = runs[(b, H_FIGURE)]
        mask = r["theta1"] <= 2 * math.pi + 1e-9
        deg = np.degrees(r["theta1"][mask])
        ax1.plot(deg, (r["omega2"] / r["omega1"])[mask], color=c, lw=2.4, label=f"β = {b}°")
        ax1.plot(np.degrees(fine), formula(fine, 1.0, math.radians(b)), color="k", ls="--", lw=0.9,
                 label="formula" if b == betas[-1] else None)
        err = r["error"][mask]
        binned = [err[(deg >= lo) & (deg < hi)].max() for lo, hi in zip(edges[:-1], edges[1:])]
        ax2.step(edges, [binned[0]] + binned, where="pre", color=c, lw=1.4, label=f"β = {b}°")
    ax1.set_xlabel("input angle θ₁ from the plane of the shafts (degrees)")
    ax1.set_ylabel("ω₂ / ω₁")
    ax1.set_yscale("log")
    ticks = [0.25, 0.5, 0.707, 1, 1.414, 2, 4]
    ax1.set_yticks(ticks)
    ax1.set_yticklabels([f"{t:g}" for t in ticks])
    ax1.minorticks_off()
    ax1.set_xticks(range(0, 361, 45))
    ax1.set_xlim(0, 360)
    ax1.set_title("Cardan joint: ω₂/ω₁, lieflow (rkmk4, h = 1e-3) and formula")
    ax1.grid(True, alpha=0.3)
    ax2.set_yscale("log")
    ax2.set_xlabel("θ₁ (degrees)")
    ax2.set_ylabel("max |ω₂ − formula| per 5° of θ₁ (rad/s)")
    ax2.set_xticks(range(0, 361, 45))
    ax2.set_xlim(0, 360)
    ax2.set_title("error of the output speed, ω₁ = 10 rad/s")
    ax2.grid(True, which="both", alpha=0.3)
    handles, labels = ax1.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=9, frameon=False)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(os.path.join(paper, "speed_ratio.png"), dpi=DPI)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
