"""Figure and tables of papers/mechanism-work-precision/ from the study's CSV.

    /usr/bin/python3 analyze.py OUT_DIR PAPER_DIR

OUT_DIR/runs.csv (study_mechanism_work_precision): one row per run (scene,
engine, formulation, integrator, dt or rtol, steps, seconds, error [m], or
[rad] on a scene of rotation-only bodies). A scene with a closed loop (its
MuJoCo series named "... (loop solref ...)", or none) also gets the joint
formulation against the maximal one.
Writes PAPER_DIR/work_precision.png (error against run time, one panel per
scene), PAPER_DIR/results.md and the table between the GENERATED markers of
PAPER_DIR/README.md.

Error at equal run time. Each series (one integrator, its steps or
tolerances) is a curve log error(log seconds), linear between measured
points and never extrapolated; "best" is the lowest error any series of an
engine reaches in a given time. For each MuJoCo error level E = 1e-3, 1e-4,
..., 1e-9 that MuJoCo's best reaches: the time t it takes, and lieflow's best
error in that same time; the ratio E / that error is how many times lower
lieflow's error is at equal run time (n/a where lieflow has no run that
short or that long).
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

LEVELS = [10.0 ** -k for k in range(3, 10)]
# MuJoCo's first-order Euler reaches 1e-4 at best within the study's steps.
EULER_LEVELS = [10.0 ** -k for k in range(1, 5)]


def label(r):
    if r["engine"] == "mujoco":
        return "MuJoCo " + r["integrator"]
    return f"lieflow {r['integrator']} ({r['formulation']})"


def series_of(rows):
    series = {}
    for r in rows:
        if r["failed"] == "true" or not r["error"]:
            continue
        e, t = float(r["error"]), float(r["seconds"])
        if e <= 0 or t <= 0:
            continue
        series.setdefault(label(r), []).append((t, e))
    return {k: sorted(v) for k, v in series.items()}


def error_at(points, t):
    """log-log interpolation of a series' error at time t (None outside it)."""
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if t0 <= t <= t1 and t1 > t0:
            w = (math.log(t) - math.log(t0)) / (math.log(t1) - math.log(t0))
            return math.exp((1 - w) * math.log(e0) + w * math.log(e1))
    return None


def time_for(points, level):
    """Time a series needs to reach error `level` (first crossing, log-log)."""
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if e0 >= level >= e1 and e0 > e1:
            w = (math.log(e0) - math.log(level)) / (math.log(e0) - math.log(e1))
            return math.exp((1 - w) * math.log(t0) + w * math.log(t1))
    return None


def best_lieflow(all_series, t, only=None):
    """lieflow's lowest error within time t: (error, series, bound). A series
    whose longest run is shorter than t counts with that run's error (bound
    True: more time would not be worse, so the ratio is a lower bound)."""
    best, who, bound = None, None, False
    for k, p in all_series.items():
        if not k.startswith("lieflow") or (only is not None and k != only):
            continue
        v, longest = error_at(p, t), False
        if v is None and p and t > p[-1][0]:
            v, longest = p[-1][1], True
        if v is not None and (best is None or v < best):
            best, who, bound = v, k, longest
    return best, who, bound


# Colour by method, line and marker by engine and formulation.
METHOD_COLOURS = {"rkmk4": "C0", "cf4": "C1", "rkmk45": "C2", "lgvi": "C3", "genalpha": "C4",
                  "RK4": "C5", "Euler": "C6", "implicit": "C7"}


def series_style(name):
    method = name.split()[1]
    if name.startswith("MuJoCo"):
        return METHOD_COLOURS.get(method, "C9"), ("x--" if "0.02 s" in name else "s--")
    return METHOD_COLOURS.get(method, "C8"), ("^:" if name.endswith("(maximal)") else "o-")


def fastest_mujoco(all_series, level, only=None):
    best, who = None, None
    for k, p in all_series.items():
        if not k.startswith("MuJoCo") or (only is not None and k != only):
            continue
        t = time_for(p, level)
        if t is not None and (best is None or t < best):
            best, who = t, k
    return best, who


def equal_time_rows(scene, s, floor=None, floor_factor=10.0, floor_what="the references' own errors"):
    """The table rows of lieflow's best error at MuJoCo's fastest time for
    each level of LEVELS, and the ratios that could be evaluated. With
    `floor` (what an error cannot be measured below, `floor_what` in words),
    a level below floor_factor times it is not compared (a row says so)."""
    rows, ratios = [], []
    for level in LEVELS:
        if floor is not None and level < floor_factor * floor:
            rows.append(f"| {scene} | {level:.0e} | not compared: within {floor_factor:g}x of {floor_what} "
                        f"({floor:.2g} rad) | | | |")
            continue
        t, who = fastest_mujoco(s, level)
        if t is None:
            rows.append(f"| {scene} | {level:.0e} | not reached | | | |")
            continue
        e, lf, bound = best_lieflow(s, t)
        if e is None:
            rows.append(f"| {scene} | {level:.0e} | {who} ({t:.3g} s) | no lieflow run that short | | n/a |")
            continue
        ratios.append(level / e)
        rows.append(f"| {scene} | {level:.0e} | {who} ({t:.3g} s) | {lf}" +
                    (" (its longest run, shorter)" if bound else "") +
                    f" | {e:.3g} | {'≥ ' if bound else ''}{level / e:.3g} |")
    return rows, ratios


def lgvi_euler_rows(scene, s, lgvi_key):
    """The table rows of lieflow's lgvi (series lgvi_key) at MuJoCo Euler's
    time for each level of EULER_LEVELS (none without that series)."""
    lgvi = s.get(lgvi_key, [])
    rows = []
    for level in EULER_LEVELS if lgvi else []:
        t, _ = fastest_mujoco(s, level, only="MuJoCo Euler")
        e, _, bound = best_lieflow(s, t, only=lgvi_key) if t is not None else (None, None, False)
        if t is None:
            rows.append(f"| {scene} | {level:.0e} | not reached | | |")
        elif e is not None and bound:
            # Euler needs longer than lgvi's longest run: that run, shorter
            # and more accurate, bounds the ratio from below.
            rows.append(f"| {scene} | {level:.0e} | {t:.3g} s | {e:.3g} in {lgvi[-1][0]:.3g} s (its longest "
                        f"run) | ≥ {level / e:.3g} |")
        elif e is not None:
            rows.append(f"| {scene} | {level:.0e} | {t:.3g} s | {e:.3g} | {level / e:.3g} |")
        else:
            rows.append(f"| {scene} | {level:.0e} | {t:.3g} s | no lgvi run that short | n/a |")
    return rows


def main(out_dir, paper_dir):
    with open(os.path.join(out_dir, "runs.csv")) as f:
        rows = list(csv.DictReader(f))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(1, len(scenes), figsize=(7.5 * len(scenes), 5.6), dpi=100, squeeze=False)
    table = ["| scene | MuJoCo error | MuJoCo's fastest (time) | lieflow's best at that time | lieflow error | ratio |",
             "| --- | --- | --- | --- | --- | --- |"]
    # The second-order symplectic method against the first-order one of the
    # same cost class: lieflow's lgvi in joint coordinates at MuJoCo Euler's
    # run time.
    pairs = ["| scene | MuJoCo Euler error | its run time | lieflow lgvi (joint) error at that time | ratio |",
             "| --- | --- | --- | --- | --- |"]
    loops = ["| scene | maximal coordinates' best error | its run time | joint coordinates' best error at that "
             "time | ratio |", "| --- | --- | --- | --- | --- |"]
    summary = []
    for ax, scene in zip(axes[0], scenes):
        s = series_of([r for r in rows if r["scene"] == scene])
        for k, p in sorted(s.items()):
            color, style = series_style(k)
            ax.loglog([t for t, _ in p], [e for _, e in p], style, color=color, ms=4, lw=1.2, label=k, alpha=0.9)
        ax.set_xlabel("run time [s]")
        with_mujoco = any(k.startswith("MuJoCo") for k in s)
        loop = not with_mujoco or any("(loop solref" in k for k in s)
        ax.set_ylabel("max rotation angle from the reference at T [rad]" if loop
                      else "max |Δ centre of mass| at T [m]")
        ax.set_title(scene + (" (closed loop" + ("" if with_mujoco else "; MuJoCo not run") + ")" if loop else ""))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        if loop:
            # A closed loop: the joint formulation (multipliers on the ABA)
            # against the maximal one at equal run time.
            for level in LEVELS:
                t = min((x for x in (time_for(p, level) for k, p in s.items() if k.endswith("(maximal)"))
                         if x is not None), default=None)
                if t is None:
                    loops.append(f"| {scene} | {level:.0e} | not reached | | |")
                    continue
                e = min((x for x in (error_at(p, t) for k, p in s.items() if k.endswith("(joint)"))
                         if x is not None), default=None)
                loops.append(f"| {scene} | {level:.0e} | {t:.3g} s | " +
                             (f"{e:.3g} | {level / e:.3g} |" if e else "no joint run that short | n/a |"))
        if not with_mujoco:
            continue
        level_rows, ratios = equal_time_rows(scene, s)
        table += level_rows
        pairs += lgvi_euler_rows(scene, s, "lieflow lgvi (joint)")
        if ratios:
            summary.append(f"{scene}: lieflow's best error at MuJoCo's run time is {min(ratios):.3g}x to "
                           f"{max(ratios):.3g}x lower over the MuJoCo error levels it could be evaluated at "
                           f"({len(ratios)} of {len(LEVELS)})")
    fig.tight_layout()
    fig.savefig(os.path.join(paper_dir, "work_precision.png"))
    text = ("\n".join(table) + "\n\n" + "\n".join(f"- {line}" for line in summary) + "\n\n" +
            "lgvi in joint coordinates (second order, symplectic) against MuJoCo's semi-implicit Euler (first "
            "order) at Euler's run time:\n\n" + "\n".join(pairs) + "\n")
    if len(loops) > 2:
        text += ("\nA closed loop in joint coordinates (the closing joint imposed with multipliers on the "
                 "articulated-body algorithm) against maximal coordinates, at the maximal formulation's run time "
                 "(errors in rad):\n\n" + "\n".join(loops) + "\n")
    with open(os.path.join(paper_dir, "results.md"), "w") as f:
        f.write("# Results (generated by analyze.py)\n\n" + text)
    splice_readme(os.path.join(paper_dir, "README.md"), text)
    print(text)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
