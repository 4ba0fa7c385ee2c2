#!/usr/bin/env python3
"""lieflow against MuJoCo on public robot descriptions, as a user gets them.

For each model of bench/models/robots (and MuJoCo's own samples where
installed), one `lieflow study MODEL --ignore all --with-mujoco` run with the
defaults (the default formulation, the default options), which times lieflow's
rkmk4, lgvi and genalpha and MuJoCo's RK4, Euler and implicit integrators on
the same file at the same step in one process, and checks lieflow's reference
against MuJoCo RK4 at a small step. Prints a markdown table: the step cost of
each lieflow integrator over its MuJoCo counterpart's (targets: rkmk4 <= 0.7x
MuJoCo RK4, lgvi <= 2x MuJoCo Euler, genalpha <= 3x MuJoCo implicit), the
formulation each ran in, and the agreement after T.

Usage: robots_vs_mujoco.py [--lieflow PATH] [--t-end T] [--dt H] [--min-time S] [MODEL[:floating] ...]
(MODEL:floating: a URDF's root on a free joint, turning at SPIN.)
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROBOTS = os.path.join(ROOT, "bench", "models", "robots")
# The floating robots turn (--spin, both engines from the same start): falling
# from rest in uniform gravity a floating tree does not move relative to
# itself, and an implicit integrator's Newton iteration then has nothing to do.
SPIN = ["--spin", "0.5,1,2"]
# (file, extra flags): the legged robots and the humanoid float.
DEFAULT_MODELS = [
    ("ur5.urdf", []),
    ("panda.urdf", []),
    ("solo12.urdf", ["--floating-base", *SPIN]),
    ("anymal.urdf", ["--floating-base", *SPIN]),
    ("talos.urdf", ["--floating-base", *SPIN]),
    ("talos_full.urdf", ["--floating-base", *SPIN]),
    ("/usr/share/mujoco/model/humanoid/humanoid.xml", SPIN),
    ("/usr/share/mujoco/model/slider_crank/slider_crank.xml", []),
    ("/usr/share/mujoco/model/tendon_arm/arm26.xml", []),
]
PAIRS = [("rkmk4", "mujoco-rk4", 0.7), ("lgvi", "mujoco-euler", 2.0), ("genalpha", "mujoco-implicit", 3.0)]


def formulation(lieflow, model, flags, integrator, dt):
    out = subprocess.run([lieflow, "simulate", model, "--ignore", "all", *flags, "--integrator", integrator,
                          "--dt", str(dt), "--t-end", str(dt), "--stats", "--quiet"],
                         capture_output=True, text=True)
    m = re.search(r'"formulation":"(\w+)"', out.stdout)
    return m.group(1) if m else "-"


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--lieflow", default=os.path.join(ROOT, "build", "app", "lieflow"))
    p.add_argument("--t-end", type=float, default=1.0)
    p.add_argument("--dt", type=float, default=0.002)
    p.add_argument("--min-time", type=float, default=0.3)
    p.add_argument("models", nargs="*")
    a = p.parse_args()
    # MODEL or MODEL:floating (a URDF's root on a free joint).
    models = [(m.split(":")[0], ["--floating-base", *SPIN] if m.endswith(":floating") else []) for m in a.models] \
        if a.models else DEFAULT_MODELS
    print("| model | " + " | ".join(f"{l} (formulation) us / {m} us = ratio (target)" for l, m, _ in PAIRS)
          + f" | lieflow reference vs MuJoCo RK4 after {a.t_end:g} s |")
    print("|---|" + "---|" * (len(PAIRS) + 1))
    for model, flags in models:
        path = model if os.path.isabs(model) else os.path.join(ROBOTS, model)
        if not os.path.exists(path):
            print(f"| {model} | absent |" + " |" * len(PAIRS))
            continue
        with tempfile.TemporaryDirectory() as out:
            run = subprocess.run([a.lieflow, "study", path, "--ignore", "all", *flags, "--with-mujoco",
                                  "--integrators", ",".join(l for l, _, _ in PAIRS), "--dt", str(a.dt),
                                  "--t-end", str(a.t_end), "--min-time", str(a.min_time), "--no-plots",
                                  "--out", out], capture_output=True, text=True)
            name = os.path.basename(path) + (" (floating)" if flags else "")
            if run.returncode != 0:
                print(f"| {name} | study failed: {run.stderr.strip().splitlines()[-1]} |" + " |" * len(PAIRS))
                continue
            with open(os.path.join(out, "study.csv"), newline="") as f:
                rows = {r["integrator"]: r for r in csv.DictReader(f)}
        cells = []
        for l, m, target in PAIRS:
            if rows[l]["failed"] == "true" or rows[m]["failed"] == "true":
                cells.append(f"failed: {rows[l]['failure'] or rows[m]['failure']}"[:80])
                continue
            lf, mj = float(rows[l]["ns_per_step"]) / 1e3, float(rows[m]["ns_per_step"]) / 1e3
            ratio = lf / mj
            mark = "ok" if ratio <= target else "MISS"
            cells.append(f"{l} ({formulation(a.lieflow, path, flags, l, a.dt)}) {lf:.1f} / {mj:.1f} = "
                         f"{ratio:.2f} ({mark})")
        ref = re.search(r"differs from it by ([0-9.e+-]+) rad", rows[PAIRS[0][0]]["reference"])
        print(f"| {name} | " + " | ".join(cells) + f" | {ref.group(1) if ref else '-'} rad |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
