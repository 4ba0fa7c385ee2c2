"""Figure and tables of papers/robots-work-precision/ from the studies' CSVs.

    /usr/bin/python3 analyze.py OUT_DIR PAPER_DIR

OUT_DIR/models.txt lists "name|study dir" per model; each study dir holds the
study.csv of `lieflow study MODEL --with-mujoco` (one row per integrator and
step: wall_seconds, the median run's time; orientation_error, the largest
rotation angle of a body from the reference at T). OUT_DIR/formulations.csv
says which formulation each lieflow integrator ran in by default.
Writes PAPER_DIR/work_precision.png (error against run time, one panel per
model), PAPER_DIR/results.md and the table between the GENERATED markers of
PAPER_DIR/README.md.

Error at equal run time, as papers/mechanism-work-precision/analyze.py (whose
interpolation this reuses): each series is log error against log seconds,
linear between measured points, never extrapolated; for each MuJoCo error
level E = 1e-3 … 1e-9 rad that MuJoCo's fastest integrator reaches, the time t
it takes and lieflow's lowest error in t; the ratio E / that error. Each
engine's rows are measured against a converged run of its own model (lieflow's
reference, and MuJoCo's RK4 at the same small step: the study's "reference"
column), so that the two models' small difference (the study log's "MuJoCo RK4
at h = ... differs from it by D rad", reported beside the table) is no
integrator's error. A level within FLOOR_FACTOR of the larger of the two
references' own error estimates (the "reference_error" column) is not
compared: below it an error measures the reference.
"""
import csv
import importlib.util
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
from paper_common import splice_readme  # noqa: E402

_spec = importlib.util.spec_from_file_location(
    "mechanism_analyze", os.path.join(HERE, "..", "mechanism-work-precision", "analyze.py"))
mech = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mech)

MUJOCO_NAMES = {"mujoco-rk4": "RK4", "mujoco-euler": "Euler", "mujoco-implicit": "implicit"}


def rows_of(name, study_csv, formulations):
    """The study's rows as the mechanism paper's runs (engine, formulation,
    integrator, seconds, error), and the larger of the two engines'
    references' own error estimates (None without a row)."""
    out = []
    floor = None
    with open(study_csv) as f:
        for r in csv.DictReader(f):
            mujoco = r["integrator"] in MUJOCO_NAMES
            if r["reference_error"]:
                floor = max(floor or 0.0, float(r["reference_error"]))
            out.append({
                "scene": name,
                "engine": "mujoco" if mujoco else "lieflow",
                "integrator": MUJOCO_NAMES.get(r["integrator"], r["integrator"]),
                "formulation": "" if mujoco else formulations.get((name, r["integrator"]), "?"),
                "dt": r["dt"],
                "seconds": r["wall_seconds"],
                "error": r["orientation_error"],
                "failed": r["failed"],
            })
    return out, floor


# A MuJoCo error level is compared only when it lies at least this factor
# above the larger of the two references' own error estimates: below it an
# error measures the reference, not the integrator.
FLOOR_FACTOR = 10.0


def model_difference(log_path):
    """The study log's "MuJoCo RK4 at h = ... differs from it by D rad": D,
    or None without that line."""
    try:
        with open(log_path) as f:
            for line in f:
                m = re.search(r"MuJoCo RK4 at h = \S+ differs from it by (\S+) rad", line)
                if m:
                    return float(m.group(1))
    except OSError:
        pass
    return None


def main(out_dir, paper_dir):
    formulations = {}
    with open(os.path.join(out_dir, "formulations.csv")) as f:
        for name, integrator, formulation in csv.reader(f):
            formulations[(name, integrator)] = formulation
    models = []
    with open(os.path.join(out_dir, "models.txt")) as f:
        for line in f:
            name, path = line.rstrip("\n").split("|")
            rows, floor = rows_of(name, os.path.join(path, "study.csv"), formulations)
            models.append((name, rows, floor, model_difference(path + ".log")))
    cols = min(4, max(1, len(models)))
    nrows = math.ceil(len(models) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.4 * nrows), dpi=90, squeeze=False)
    table = ["| model | MuJoCo error [rad] | MuJoCo's fastest (time) | lieflow's best at that time | lieflow error "
             "| ratio |", "| --- | --- | --- | --- | --- | --- |"]
    pairs = ["| model | MuJoCo Euler error [rad] | its run time | lieflow lgvi error at that time | ratio |",
             "| --- | --- | --- | --- | --- |"]
    summary = []
    for k, (name, rows, floor, difference) in enumerate(models):
        ax = axes[k // cols][k % cols]
        s = mech.series_of(rows)
        for key, p in sorted(s.items()):
            color, style = mech.series_style(key)
            ax.loglog([t for t, _ in p], [e for _, e in p], style, color=color, ms=4, lw=1.2, label=key, alpha=0.9)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("run time [s]")
        ax.set_ylabel("max rotation from its engine's reference at T [rad]", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
        level_rows, ratios = mech.equal_time_rows(name, s, floor, FLOOR_FACTOR)
        table += level_rows
        lgvi = next((key for key in s if key.startswith("lieflow lgvi")), None)
        if lgvi:
            pairs += mech.lgvi_euler_rows(name, s, lgvi)
        difference = (f"; the engines' references (their models) differ by {difference:.2g} rad"
                      if difference is not None else "")
        if ratios:
            summary.append(f"{name}: lieflow's best error at MuJoCo's run time is {min(ratios):.3g}x to "
                           f"{max(ratios):.3g}x lower over the MuJoCo error levels it could be evaluated at "
                           f"({len(ratios)} of {len(mech.LEVELS)}){difference}")
        else:
            summary.append(f"{name}: no MuJoCo error level between 1e-3 and 1e-9 rad could be compared{difference}")
    for k in range(len(models), nrows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(paper_dir, "work_precision.png"))
    text = ("\n".join(table) + "\n\n" + "\n".join(f"- {line}" for line in summary) + "\n\n" +
            "lgvi (second order, symplectic) against MuJoCo's semi-implicit Euler (first order) at Euler's run "
            "time:\n\n" + "\n".join(pairs) + "\n")
    with open(os.path.join(out_dir, "machine.txt")) as f:
        machine = f.read()
    with open(os.path.join(paper_dir, "results.md"), "w") as f:
        f.write("# Results (generated by analyze.py)\n\n```\n" + machine + "```\n\n" + text)
    splice_readme(os.path.join(paper_dir, "README.md"), text)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
