#!/usr/bin/env python3
"""Plots of a lieflow work-precision study: DIR/study.csv and DIR/drift.csv in,
DIR/work_precision.png, DIR/energy_drift.png and DIR/momentum_drift.png out.

- Each integrator keeps one marker and line style in all three figures, so
  that overlapping curves stay visible.
- The work-precision figure says what the errors are measured against, draws
  the reference's own error as a band (points below it are not meaningful),
  marks saturated errors (>= 1 rad: no correct digit) with hollow markers and
  lists the failed runs instead of dropping them.
- A peer engine's rows (MuJoCo's integrators, `--with-mujoco`: names
  starting with "mujoco-") are drawn in black and shades of grey with open
  markers, so they stand apart from lieflow's; when MuJoCo is absent from
  the build the figure says so instead of listing failed runs.
- The momentum figure shows the spatial angular momentum where the scene
  conserves it, and every other invariant of the scene (drift.csv columns
  NAME_error: L_z, spin, L_com, ...); with nothing conserved it says so.

Usage: plot_study.py DIR
"""
import csv
import math
import sys
import textwrap
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = ["o", "s", "^", "v", "D", "P", "X", "<", ">", "*", "h"]
STYLES = ["-", "--", "-.", ":"]
SATURATED = 1.0  # rad: an orientation error this large has no correct digit


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def human(v):
    """A number for people: 0.005, 5e-05, 2."""
    return f"{v:.3g}" if math.isfinite(v) else "?"


PEER_PREFIX = "mujoco-"
PEER_COLORS = ["black", "dimgray", "darkgray"]
# lieflow's integrators, one colour each: matplotlib's ten-colour cycle
# repeats after ten series (rkmk-euler and splitting shared blue), so the
# tab10 colours are followed by Dark2's eight; none is black or grey (the
# peers').
OUR_COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf",
              "#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#0b3d91", "#8b0000"]
# Characters per line of the work-precision title at its font size in a
# 10-inch figure (the reference is wrapped there, never cut).
TITLE_WIDTH = 120


def style_of(names):
    styles, ours, peers = {}, 0, 0
    for n in names:
        if n.startswith(PEER_PREFIX):
            styles[n] = dict(marker=MARKERS[peers % len(MARKERS)], linestyle=":", color=PEER_COLORS[peers % 3],
                             markerfacecolor="none")
            peers += 1
        else:
            styles[n] = dict(marker=MARKERS[ours % len(MARKERS)], color=OUR_COLORS[ours % len(OUR_COLORS)],
                             linestyle=STYLES[(ours // len(MARKERS) + ours) % len(STYLES)])
            ours += 1
    return styles


def peer_absent(study):
    """The reason MuJoCo's rows give when this build has no MuJoCo, or None."""
    for r in study:
        if r["integrator"].startswith(PEER_PREFIX) and r["failure"].startswith("MuJoCo is absent"):
            return r["failure"]
    return None


def title_of(scene, reference):
    """The work-precision title: the scene, then the reference wrapped whole."""
    lines = textwrap.wrap("errors against: " + reference, TITLE_WIDTH) if reference else ["errors against: ?"]
    return "\n".join([f"work-precision: {scene}"] + lines)


def work_precision(directory, study, styles, scene, keep=False):
    """Draws work_precision.png; with keep, returns the figure open (tests)."""
    fig, ax = plt.subplots(figsize=(10, 5.5))
    failed = []
    any_saturated = False
    absent = peer_absent(study)
    for name in styles:
        pts = []
        for r in study:
            if r["integrator"] != name:
                continue
            if r["failed"] == "true" and absent and name.startswith(PEER_PREFIX):
                continue
            if r["failed"] == "true":
                failed.append(f"{name} dt={human(number(r['dt']))}")
                continue
            err, t = number(r["orientation_error"]), number(r["wall_seconds"])
            if err > 0 and t > 0 and math.isfinite(err):
                pts.append((t, err))
        if not pts:
            continue
        pts.sort()
        st = styles[name]
        line, = ax.loglog([p[0] for p in pts], [p[1] for p in pts], label=name, markersize=5, alpha=0.85, **st)
        sat = [p for p in pts if p[1] >= SATURATED]
        if sat:
            any_saturated = True
            ax.loglog([p[0] for p in sat], [p[1] for p in sat], linestyle="none", marker=st["marker"],
                      markersize=9, markerfacecolor="none", markeredgecolor=line.get_color())
    reference = study[0].get("reference", "") if study else ""
    ref_error = number(study[0].get("reference_error")) if study else math.nan
    if ref_error > 0:
        bottom = ax.get_ylim()[0]
        if ref_error > bottom:
            ax.axhspan(bottom, ref_error, color="grey", alpha=0.15,
                       label=f"below the reference's own error ({human(ref_error)} rad)")
            ax.set_ylim(bottom=bottom)
        else:
            ax.plot([], [], linestyle="none", label=f"reference's own error {human(ref_error)} rad (below the axis)")
    if any_saturated:
        ax.axhline(SATURATED, color="black", linewidth=0.6, linestyle=":")
        ax.plot([], [], linestyle="none", marker="o", markerfacecolor="none", markeredgecolor="black",
                label=f"hollow: saturated (>= {human(SATURATED)} rad, no correct digit)")
    ax.set_xlabel("run time [s] (median of repeated runs)")
    ax.set_ylabel("orientation error at t_end [rad]")
    ax.set_title(title_of(scene, reference), fontsize=8)
    if absent:
        ax.text(0.99, 0.01, absent, transform=ax.transAxes, ha="right", va="bottom", fontsize=8, color="darkred",
                wrap=True)
    if failed:
        fig.text(0.01, 0.005, "failed (no point): " + ", ".join(failed), fontsize=7, color="darkred", va="bottom",
                 wrap=True)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(f"{directory}/work_precision.png", dpi=120)
    if keep:
        return fig
    plt.close(fig)
    curves = len([n for n in styles if any(r["integrator"] == n and r["failed"] != "true" for r in study)])
    saturated = sum(1 for r in study if r["failed"] != "true" and number(r["orientation_error"]) >= SATURATED)
    print(f"work_precision.png: {curves} curves, {saturated} saturated points, {len(failed)} failed runs listed"
          + (f"; {absent}" if absent else ""))


def drift_figure(directory, drift, styles, scene, columns, ylabel, filename, empty_note, keep=False):
    """Draws one drift figure and prints the quantities drawn; with keep,
    returns the figure open (tests). With several quantities, each has its
    own line style and each integrator keeps its colour and marker."""
    fig, ax = plt.subplots(figsize=(10, 5.5))
    plotted = False
    drawn = []
    for ci, (column, column_label) in enumerate(columns):
        for name in styles:
            pts = [(number(r["t"]), abs(number(r.get(column)))) for r in drift if r["integrator"] == name]
            pts = [p for p in pts if math.isfinite(p[1]) and p[1] > 0]
            if not pts:
                continue
            st = dict(styles[name])
            if len(columns) > 1:
                st["linestyle"] = STYLES[ci % len(STYLES)]
            label = name if len(columns) == 1 else f"{name}: {column_label}"
            ax.semilogy([p[0] for p in pts], [p[1] for p in pts], label=label, markevery=max(1, len(pts) // 12),
                        markersize=4, alpha=0.85, **st)
            plotted = True
            if column_label not in drawn:
                drawn.append(column_label)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(ylabel)
    dt = human(number(drift[0]["dt"])) if drift else "?"
    ax.set_title(f"{scene}, dt = {dt}" + ("" if plotted else f"\n({empty_note})"), fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    if plotted:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    else:
        ax.text(0.5, 0.5, empty_note, transform=ax.transAxes, ha="center", va="center")
    fig.tight_layout()
    fig.savefig(f"{directory}/{filename}", dpi=120)
    print(f"{filename}: " + (", ".join(drawn) if drawn else "nothing conserved (said so in the figure)"))
    if keep:
        return fig
    plt.close(fig)


def main(directory):
    study = read_rows(f"{directory}/study.csv")
    drift = read_rows(f"{directory}/drift.csv")
    scene = study[0]["scene"] if study else "?"
    names = []
    for r in study + drift:
        if r["integrator"] not in names:
            names.append(r["integrator"])
    styles = style_of(names)
    work_precision(directory, study, styles, scene)
    drift_figure(directory, drift, styles, scene, [("energy_error", "energy")],
                 "relative energy error |E - E0|/|E0|", "energy_drift.png", "no drift samples")
    header = list(drift[0].keys()) if drift else []
    invariants = [(c, c[:-len("_error")]) for c in header
                  if c.endswith("_error") and c not in ("energy_error", "momentum_error")]
    columns = ([("momentum_error", "L")] if any(r.get("momentum_error") for r in drift) else []) + invariants
    label = ("relative error of the conserved quantities: " + ", ".join(c[1] for c in columns)) if columns else \
        "relative momentum error"
    drift_figure(directory, drift, styles, scene, columns or [("momentum_error", "L")], label, "momentum_drift.png",
                 "this scene conserves no angular momentum component (external moments)")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
