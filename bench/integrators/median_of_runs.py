#!/usr/bin/python3
"""ns/step table, median over several bench_integrators runs.

usage: median_of_runs.py RUN1.json RUN2.json ...   (bench_integrators
       --benchmark_out=RUNi.json --benchmark_out_format=json)

For every benchmark, takes each run's median over its repetitions (CPU time;
Google Benchmark's "median" aggregate, else the single iteration run) and
prints the median of those across the runs, as the markdown tables of
bench/README.md: ns/step per stepper (FreeBodySystem, RotorSystem, mj_step),
the MuJoCo speed-ups (each run's own ratio, as the issue measures them, their
median, and PASS only if every run passes: RKMK4, CF4 vs RK4 >= 10; LGVI,
splitting vs Euler >= 3) and Simulation::run against the bare stepper loop.
"""
import json
import statistics
import sys

STEPS_PER_SIMULATE = 1000  # bench_integrators' kStepsPerRestart
# Registration order of bench_integrators (the JSON follows the interleaved run order).
ORDER = ["rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "dopri5-step", "dopri5-step+error", "cg3",
         "cf4", "lgvi", "lgvi-cayley", "splitting", "splitting-axis", "genalpha"]
TARGETS = [("rkmk4", "mujoco/rk4", "MuJoCo RK4", 10.0), ("cf4", "mujoco/rk4", "MuJoCo RK4", 10.0),
           ("lgvi", "mujoco/euler", "MuJoCo Euler", 3.0),
           ("splitting", "mujoco/euler", "MuJoCo Euler", 3.0)]


def per_run_ns(path):
    with open(path) as f:
        data = json.load(f)
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}
    medians, singles = {}, {}
    for b in data["benchmarks"]:
        if b.get("error_occurred"):
            continue
        name = b.get("run_name", b["name"])
        ns = b["cpu_time"] * scale[b.get("time_unit", "ns")]
        if name.startswith("simulate_1000/"):
            ns /= STEPS_PER_SIMULATE
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") == "median":
                medians[name] = ns
        else:
            singles.setdefault(name, []).append(ns)
    out = {k: statistics.median(v) for k, v in singles.items()}
    out.update(medians)
    return out, data.get("context", {})


def is_number(cell):
    try:
        float(cell.replace("≥", "").replace(">=", "").split()[0])
        return True
    except (ValueError, IndexError):
        return False


def table(header, rows):
    right = [bool(rows) and all(is_number(r[i]) for r in rows) for i in range(len(header))]
    lines = ["| " + " | ".join(header) + " |",
             "| " + " | ".join("---:" if r else "---" for r in right) + " |"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def main(paths):
    if not paths:
        print(__doc__.strip())
        return 2
    runs = [per_run_ns(p) for p in paths]
    names = []
    for ns, _ in runs:
        names += [n for n in ns if n not in names]
    med = {n: statistics.median([ns[n] for ns, _ in runs if n in ns]) for n in names}
    fmt = lambda x: "%.1f" % x if x is not None else "-"

    steppers = []
    for n in names:
        group, _, stepper = n.partition("/")
        if group in ("free", "rotor") and stepper not in steppers:
            steppers.append(stepper)
    steppers.sort(key=lambda s: ORDER.index(s) if s in ORDER else len(ORDER))
    rows = [[s, fmt(med.get("free/" + s)), fmt(med.get("rotor/" + s))] for s in steppers]
    for m in ("mujoco/euler", "mujoco/rk4"):
        if m in med:
            rows.append([m + " (mj_step)", fmt(med[m]), "-"])
    print(table(["stepper", "FreeBodySystem ns/step", "RotorSystem ns/step"], rows))
    print()

    rows = []
    for stepper, peer, peer_name, target in TARGETS:
        if "free/" + stepper not in med or peer not in med:
            continue
        # The ratios are measured within one run: one speed-up per run.
        per_run = [ns[peer] / ns["free/" + stepper] for ns, _ in runs
                   if peer in ns and "free/" + stepper in ns]
        speedup = statistics.median(per_run)
        rows.append([stepper, fmt(med["free/" + stepper]), peer_name, fmt(med[peer]),
                     "%.1f" % speedup, ", ".join("%.1f" % r for r in per_run), ">= %g" % target,
                     "PASS" if min(per_run) >= target else "MISS"])
    if rows:
        print(table(["lieflow (free body)", "ns/step", "peer", "ns/step", "speed-up (median)",
                     "speed-up per run", "target", "result (every run)"], rows))
        print()

    rows = []
    for n in sorted(names, key=lambda n: ORDER.index(n.split("/")[-1]) if n.split("/")[-1] in ORDER else 99):
        if n.startswith("simulate_1000/free/"):
            s = n.split("/")[-1]
            if "free/" + s in med:
                rows.append([s, fmt(med["free/" + s]), fmt(med[n]), "%.2f" % (med[n] / med["free/" + s])])
    if rows:
        print(table(["integrator", "stepper loop ns/step", "Simulation::run ns/step", "ratio"], rows))
        print()
    ctx = runs[0][1]
    print("%d runs; context of the first: %s, %s CPUs at %s MHz, build: %s" % (
        len(runs), ctx.get("host_name", "?"), ctx.get("num_cpus", "?"), ctx.get("mhz_per_cpu", "?"),
        ctx.get("lieflow_build", "?")))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
