"""Figures and tables of papers/humanoid-free-fall/ from the runs' CSV.

    /usr/bin/python3 analyze.py OUT_DIR PAPER_DIR

OUT_DIR/study/study.csv (lieflow study --with-mujoco over 1 s) and
OUT_DIR/drift/summary.csv, samples.csv (study_model_drift over the long
runs). Writes PAPER_DIR/work_precision.png (the torso's orientation error at
1 s against run time), drift.png (the relative drift of L_com and of energy +
dissipated work over time, every long run), drift_cost.png (the largest
drift of each long run against its run time), results.md and the tables
between the GENERATED markers of PAPER_DIR/README.md.

Equal run time: for each MuJoCo run, the lowest drift (or error) of any
lieflow run that took at most as long (no interpolation, nothing
extrapolated; n/a when no lieflow run was that fast).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from paper_common import splice_readme  # noqa: E402

FLOOR = 1e-17  # drawn instead of an exact zero on log axes
MARKERS = ["o", "s", "^", "v", "D", "P", "X"]


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def peer(name):
    return name.startswith("mujoco-")


def label(name):
    return ("MuJoCo " + name[len("mujoco-"):]) if peer(name) else "lieflow " + name


def style(name, index):
    if peer(name):
        return dict(color=["black", "dimgray", "darkgray"][index % 3], linestyle=":", marker=MARKERS[index % 7],
                    markerfacecolor="none")
    return dict(marker=MARKERS[index % 7], linestyle="-")


def styles(names):
    out, ours, theirs = {}, 0, 0
    for n in names:
        if n in out:
            continue
        out[n] = style(n, theirs if peer(n) else ours)
        if peer(n):
            theirs += 1
        else:
            ours += 1
    return out


def fmt(v):
    return f"{v:.2g}" if math.isfinite(v) else "n/a"


def best_lieflow(runs, wall, key):
    """The lowest `key` of a lieflow run that took at most `wall` seconds."""
    fits = [(num(r[key]), r) for r in runs if not peer(r["integrator"]) and r["failed"] != "true"
            and num(r["wall_seconds"]) <= wall and math.isfinite(num(r[key]))]
    return min(fits, key=lambda p: p[0]) if fits else (math.nan, None)


def work_precision(study, paper):
    fig, ax = plt.subplots(figsize=(8, 5))
    st = styles(r["integrator"] for r in study)
    for name, s in st.items():
        pts = sorted((num(r["wall_seconds"]), num(r["orientation_error"])) for r in study
                     if r["integrator"] == name and r["failed"] != "true")
        pts = [p for p in pts if p[0] > 0 and p[1] > 0]
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], label=label(name), **s)
    ref_error = num(study[0]["reference_error"])
    if ref_error > 0:
        ax.axhline(ref_error, color="grey", linewidth=0.8, linestyle="--", label="the reference's own error")
    ax.set_xlabel("run time for 1 s [s] (median of repeated runs)")
    ax.set_ylabel("torso orientation error at t = 1 s [rad]")
    ax.set_title("MuJoCo's humanoid thrown turning (27 dof): error against run time", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(paper, "work_precision.png"), dpi=120)
    plt.close(fig)


def drift_over_time(samples, paper):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharex=True)
    keys = [("L_com_error", "|L_com - L_com(0)| / |L_com(0)|"),
            ("energy_balance_error", "|E + W_dashpots - E(0)| / |E(0)|")]
    runs = []
    for r in samples:
        k = (r["integrator"], r["dt"])
        if k not in runs:
            runs.append(k)
    st = styles(k[0] for k in runs)
    for ax, (key, title) in zip(axes, keys):
        for k in runs:
            pts = [(num(r["t"]), max(abs(num(r[key])), FLOOR)) for r in samples
                   if (r["integrator"], r["dt"]) == k and math.isfinite(num(r[key]))]
            if pts:
                s = dict(st[k[0]])
                s["markevery"] = max(1, len(pts) // 8)
                s["markersize"] = 4
                ax.semilogy([p[0] for p in pts], [p[1] for p in pts], label=f"{label(k[0])} h={fmt(num(k[1]))}", **s)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("t [s]")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(os.path.join(paper, "drift.png"), dpi=120)
    plt.close(fig)


def drift_cost(summary, paper):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    st = styles(r["integrator"] for r in summary)
    for ax, key, title in zip(axes, ["L_com_drift", "energy_balance_drift"],
                              ["largest L_com drift", "largest drift of energy + dissipated work"]):
        for name, s in st.items():
            pts = sorted((num(r["wall_seconds"]), max(num(r[key]), FLOOR)) for r in summary
                         if r["integrator"] == name and r["failed"] != "true" and math.isfinite(num(r[key])))
            if pts:
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], label=label(name), **s)
        ax.set_xlabel("run time [s]")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(paper, "drift_cost.png"), dpi=120)
    plt.close(fig)


def every_run(title, runs, first):
    """A markdown table of runs: steps, time, the `first` columns, then the drifts."""
    columns = [("time [s]", "wall_seconds")] + first + [("energy drift", "energy_drift"),
                                                        ("L_com drift", "L_com_drift"),
                                                        ("energy+W drift", "energy_balance_drift")]
    text = f"## {title}\n\n| run | steps | " + " | ".join(c[0] for c in columns) + " |\n"
    text += "| --- " * (len(columns) + 2) + "|\n"
    for r in runs:
        text += f"| {label(r['integrator'])} h={fmt(num(r['dt']))} | {r['steps']} | "
        if r["failed"] == "true":
            text += f"failed: {r['failure']} |" + " |" * (len(columns) - 1) + "\n"
        else:
            text += " | ".join(fmt(num(r.get(c[1]))) for c in columns) + " |\n"
    return text + "\n"


def main(out, paper):
    study = rows(os.path.join(out, "study", "study.csv"))
    summary = rows(os.path.join(out, "drift", "summary.csv"))
    samples = rows(os.path.join(out, "drift", "samples.csv"))
    with open(os.path.join(out, "machine.txt")) as f:
        machine = f.read().strip()
    t_drift = next((line.split(":")[1].strip() for line in machine.splitlines() if line.startswith("long runs")), "?")
    work_precision(study, paper)
    drift_over_time(samples, paper)
    drift_cost(summary, paper)

    zero_g = rows(os.path.join(out, "drift-zero-g", "summary.csv"))
    drifts = [("L_com drift", "L_com_drift"), ("energy+W drift", "energy_balance_drift")]
    lines = equal_time_table(f"Long runs in free fall ({t_drift}), each engine measuring its own run; equal run "
                             "time: lieflow's lowest drift among its runs that took at most as long as MuJoCo's.",
                             summary, drifts) + [""] + \
        equal_time_table(f"Long runs without gravity ({t_drift}), the same.", zero_g, drifts)
    lines += [""] + equal_time_table(
        "Work-precision over 1 s: the torso's orientation at t = 1 s against " + study[0]["reference"] +
        "; equal run time: lieflow's lowest error among its runs that took at most as long as MuJoCo's.",
        study, [("error [rad]", "orientation_error")])
    generated = "\n".join(lines)
    splice_readme(os.path.join(paper, "README.md"), generated)

    with open(os.path.join(paper, "results.md"), "w") as f:
        f.write("# humanoid-free-fall: measured\n\n" + machine.replace("\n", "  \n") + "\n\n" + generated + "\n\n")
        f.write(every_run("Every long run in free fall", summary, [("ns/step", "ns_per_step")]))
        f.write(every_run("Every long run without gravity", zero_g, [("ns/step", "ns_per_step")]))
        f.write(every_run("Every 1 s run", study, [("error [rad]", "orientation_error")]))
    print(generated)


def equal_time_table(intro, runs, columns):
    """A markdown table of MuJoCo's runs: each column (header, CSV key) and,
    beside it, the lowest value of a lieflow run that took at most as long."""
    lines = [intro, "", "| MuJoCo run | time [s] | " +
             " | ".join(f"{header} | lieflow's lowest at that time" for header, _ in columns) + " |",
             "| --- " * (2 + 2 * len(columns)) + "|"]
    for r in runs:
        if not peer(r["integrator"]):
            continue
        name = f"{label(r['integrator'])} h={fmt(num(r['dt']))}"
        if r["failed"] == "true":
            lines.append(f"| {name} | | failed: {r['failure']} |" + " |" * (2 * len(columns) - 1))
            continue
        wall = num(r["wall_seconds"])
        cells = []
        for _, key in columns:
            best, who = best_lieflow(runs, wall, key)
            cells += [fmt(num(r[key])), f"{fmt(best)} ({who['integrator']} h={fmt(num(who['dt']))}, "
                      f"{fmt(num(who['wall_seconds']))} s)" if who else "n/a (no lieflow run that fast)"]
        lines.append(f"| {name} | {fmt(wall)} | " + " | ".join(cells) + " |")
    return lines


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
