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
    # At the sizes the study draws them: every integrator of `lieflow
    # integrators` and MuJoCo's three get colours of their own, and the
    # work-precision title holds the whole reference of the main job (a long
    # one), inside the figure.
    sys.path.insert(0, HERE)
    import plot_study
    names = ["rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "rkmk6", "rkmk45", "cg3", "cf4", "lgvi", "splitting",
             "genalpha", "radau5", "exact", "mujoco-euler", "mujoco-rk4", "mujoco-implicit"]
    styles = plot_study.style_of(names)
    colours = [styles[n]["color"] for n in names]
    check(len(set(colours)) == len(colours), f"colours repeat: {list(zip(names, colours))}")
    reference = ("projected rkmk4 at h = 6.25e-05; its orientation error is estimated at 1.82356e-13 rad by "
                 "Richardson from a run at h = 0.000125; MuJoCo RK4 at h = 6.25e-05 differs from it by 3.79136e-14 "
                 "rad (MuJoCo's compiler balanced an inertia of the file that breaks A + B >= C)")
    with tempfile.TemporaryDirectory() as d:
        study_files(d, ["L_z", "spin"], 1e-12)
        study = plot_study.read_rows(os.path.join(d, "study.csv"))
        for r in study:
            r["reference"] = reference
        fig = plot_study.work_precision(d, study, plot_study.style_of(["rkmk4", "lgvi", "cf4", "rkmk-euler"]), "s",
                                        keep=True)
        fig.canvas.draw()
        title = fig.axes[0].title
        box, frame = title.get_window_extent(), fig.bbox
        text = title.get_text().replace("\n", " ")
        check("..." not in text and "breaks A + B >= C)" in text, f"the title cuts the reference: {text!r}")
        check(box.x0 >= frame.x0 and box.x1 <= frame.x1 and box.y1 <= frame.y1,
              f"the title leaves the figure: {box} outside {frame}")
        drift = plot_study.read_rows(os.path.join(d, "drift.csv"))
        fig = plot_study.drift_figure(d, drift, plot_study.style_of(["rkmk4", "lgvi", "cf4"]), "s",
                                      [("L_z_error", "L_z"), ("spin_error", "spin")], "errors", "m.png", "none",
                                      keep=True)
        seen = {}
        for line in fig.axes[0].get_lines():
            key = (line.get_color(), line.get_linestyle(), line.get_marker())
            check(key not in seen, f"series {line.get_label()!r} and {seen.get(key)!r} look the same")
            seen[key] = line.get_label()
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
