#!/usr/bin/env python3
"""Checks of the plot scripts on fabricated CSVs: with and without the
invariant columns, with failed rows, saturated errors, a reference error above
and below the points, and stability limits below and beyond the grid. Each
script must exit 0 and write a non-empty PNG; the drift figure of a scene
without any conserved quantity must say so rather than draw nothing.

Usage: test_plots.py   (needs Debian's python3-matplotlib)
Prints "N passed, M failed" last; exits 0 only when none failed.
"""
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
STUDY_HEADER = ("scene,integrator,dt,steps,repeats,wall_seconds,ns_per_step,orientation_error,omega_error,"
                "energy_drift,momentum_drift,newton_iterations_mean,failed,failure,reference,reference_error,options")


def study_files(directory, invariants, reference_error):
    extra = "".join("," + n + "_drift" for n in invariants)
    rows = [STUDY_HEADER + extra]
    for name, errors in (("rkmk4", [2.0, 1e-3, 6e-5, 4e-6]), ("lgvi", [3.0, 0.3, 0.08, 0.02]),
                         ("cf4", [2.0, 1e-3, 6e-5, 4e-6])):
        for k, e in enumerate(errors):
            dt = 0.004 / 2 ** k
            rows.append(f"s,{name},{dt},{int(1 / dt)},3,{1e-4 * 2 ** k},{100.0},{e},{e},1e-3,,,false,\"\","
                        f"\"converged rkmk45 run\",{reference_error},\"\"" + ",1e-9" * len(invariants))
    rows.append("s,rkmk-euler,0.004,76,0,,,,,,,,true,\"blow-up at t = 0.3\",\"converged rkmk45 run\","
                f"{reference_error},\"\"" + "," * len(invariants))
    with open(os.path.join(directory, "study.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")
    header = "integrator,dt,t,energy_error,momentum_error" + "".join("," + n + "_error" for n in invariants)
    drift = [header]
    for name in ("rkmk4", "lgvi", "cf4"):
        for i in range(50):
            drift.append(f"{name},0.001,{i * 0.04},{1e-8 * (i + 1)}," + ("," + str(1e-12 * (i + 1))) *
                         len(invariants))
    with open(os.path.join(directory, "drift.csv"), "w") as f:
        f.write("\n".join(drift) + "\n")


def stability_file(directory):
    with open(os.path.join(directory, "stability.csv"), "w") as f:
        f.write("scene,integrator,omega_c,h_omega_max,bounded_on_whole_grid,first_failure,options\n"
                "a,rkmk-euler,100,0,false,\"energy\",\"\"\n"
                "a,rkmk4,100,2.83,false,\"energy\",\"\"\n"
                "b,rkmk4,1000,36.8,false,\"energy\",\"\"\n"
                "b,genalpha,1000,100,true,\"\",\"rho_inf=1\"\n")


def run(script, directory):
    p = subprocess.run([sys.executable, os.path.join(HERE, script), directory], capture_output=True, text=True)
    return p.returncode, p.stderr + p.stdout


def main():
    passed = failed = 0

    def check(ok, what):
        nonlocal passed, failed
        if ok:
            passed += 1
        else:
            failed += 1
            print("FAILED: " + what)

    for invariants, reference_error in (([], 1e-12), (["L_z", "spin"], 1e-5)):
        with tempfile.TemporaryDirectory() as d:
            study_files(d, invariants, reference_error)
            code, err = run("plot_study.py", d)
            check(code == 0, f"plot_study.py with invariants {invariants}: exit {code}\n{err}")
            for png in ("work_precision.png", "energy_drift.png", "momentum_drift.png"):
                path = os.path.join(d, png)
                check(os.path.exists(path) and os.path.getsize(path) > 10000, f"{png} with invariants {invariants}")
            # Failed runs are listed, saturated errors marked, invariants drawn
            # (or their absence said), never silently dropped.
            check("work_precision.png: 3 curves, 3 saturated points, 1 failed runs listed" in err, err)
            expected = ("momentum_drift.png: L_z, spin" if invariants else
                        "momentum_drift.png: nothing conserved (said so in the figure)")
            check(expected in err, f"expected '{expected}' in:\n{err}")
    with tempfile.TemporaryDirectory() as d:
        stability_file(d)
        code, err = run("plot_stability.py", d)
        check(code == 0, f"plot_stability.py: exit {code}\n{err}")
        path = os.path.join(d, "stability.png")
        check(os.path.exists(path) and os.path.getsize(path) > 10000, "stability.png")
        check("stability.png: 4 bars, 1 below the grid, 1 bounded on the whole grid" in err, err)
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
