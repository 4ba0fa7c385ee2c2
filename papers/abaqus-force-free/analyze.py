#!/usr/bin/python3
"""Tables and figures of the Abaqus force-free benchmark from lieflow's output.

Usage: analyze.py OUT_DIR PAPER_DIR
  OUT_DIR   what reproduce.sh wrote: hH/NAME.csv (trajectory), hH/NAME.json
            (--stats), hH/NAME.rc (exit status), study/study.csv, machine.txt
  PAPER_DIR where results.md and the PNG figures go

The analytic solution (Goldstein; the Abaqus document, restated in
shared/seeds/README.md): symmetric body, I1 = I2 = I, I3, no torque,
    omega_body(t) = (A cos(Om t), A sin(Om t), n),  Om = n (I3 - I)/I,
and, with R(0) = identity (the scene's initial orientation),
    R(t) = exp(t a^) exp(-t Om e3^),  a = L/I = (A, 0, I3 n / I),
since then R^T R' = exp(t Om e3^) a - Om e3 = omega_body(t). The angular
velocity seen in the global frame is R omega = exp(t a^) (A, 0, n): the vector
(A, 0, n) turning about L at the rate |L|/I, i.e. with period 2 pi I/|L|.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from paper_common import splice_readme  # noqa: E402

# The benchmark's data (shared/seeds/README.md; scenes/abaqus-force-free.json).
I_T, I_3, AMP, SPIN = 1.0, 2.0, 0.25, 2.0 * math.pi
OMEGA = SPIN * (I_3 - I_T) / I_T
A_VEC = np.array([I_T * AMP, 0.0, I_3 * SPIN]) / I_T  # L / I
W_GLOBAL0 = np.array([AMP, 0.0, SPIN])                 # R omega at t = 0

INTEGRATORS = ["rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "rkmk45", "cg3", "cf4",
               "lgvi", "splitting", "genalpha", "exact"]
IMPLICIT = {"lgvi", "genalpha"}
BENCH_H = "0.01"
DPI = 100
FLOOR = 1e-17  # plotted in place of an exact zero on log axes


def rot(axis_angle):
    """Rotation matrix of a rotation vector (Rodrigues)."""
    theta = np.linalg.norm(axis_angle)
    if theta == 0.0:
        return np.eye(3)
    k = axis_angle / theta
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(theta) * K + (1 - math.cos(theta)) * K @ K


def exact_body_omega(t):
    return np.stack([AMP * np.cos(OMEGA * t), AMP * np.sin(OMEGA * t), np.full_like(t, SPIN)], axis=1)


def exact_rotation(t):
    return rot(t * A_VEC) @ rot(np.array([0.0, 0.0, -OMEGA * t]))


def quat_to_matrix(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def rotation_angle(R):
    """Angle of a rotation matrix, accurate for small angles too."""
    skew = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return math.atan2(np.linalg.norm(skew), 0.5 * (np.trace(R) - 1.0))


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    data = np.array([[float(v) for v in r] for r in rows[1:]])
    # lieflow writes the last state once more after a failure; keep one copy.
    if len(data) > 1 and np.array_equal(data[-1], data[-2]):
        data = data[:-1]
    return {name: data[:, i] for i, name in enumerate(header)}


class Run:
    """One `lieflow simulate` run and its errors against the analytic solution."""

    def __init__(self, out, h, name):
        base = os.path.join(out, f"h{h}", name)
        self.name, self.h = name, float(h)
        with open(base + ".json") as f:
            self.stats = json.loads(f.read().strip().splitlines()[-1])
        with open(base + ".rc") as f:
            self.rc = int(f.read())
        self.failed = bool(self.stats["failed"])
        d = read_csv(base + ".csv")
        self.t = d["t"]
        self.w = np.stack([d["body.wx"], d["body.wy"], d["body.wz"]], axis=1)
        self.q = np.stack([d["body.qw"], d["body.qx"], d["body.qy"], d["body.qz"]], axis=1)
        self.energy, self.L = d["energy"], np.stack([d["Lx"], d["Ly"], d["Lz"]], axis=1)
        self.R = [quat_to_matrix(q) for q in self.q]
        self.w_global = np.array([R @ w for R, w in zip(self.R, self.w)])
        self.w_exact = exact_body_omega(self.t)
        self.R_exact = [exact_rotation(t) for t in self.t]
        self.w_global_exact = np.array([rot(t * A_VEC) @ W_GLOBAL0 for t in self.t])
        self.dw = self.w - self.w_exact
        self.err_body = np.linalg.norm(self.dw, axis=1)
        self.err_global = np.linalg.norm(self.w_global - self.w_global_exact, axis=1)
        self.err_rot = np.array([rotation_angle(Re.T @ R) for Re, R in zip(self.R_exact, self.R)])
        self.amplitude_ratio = math.hypot(self.w[-1, 0], self.w[-1, 1]) / AMP
        self.t_reached = self.t[-1]

    def max_component_errors(self):
        return np.max(np.abs(self.dw), axis=0)


def fmt(v, digits=2):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "—"
    if v == 0.0:
        return "0"
    return f"{v:.{digits}e}"


def failure_text(run):
    return f"failed at t = {run.t_reached:g}: {run.stats['failure']}"


def read_study(path):
    rows = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            rows[(r["integrator"], float(r["dt"]))] = r
    return rows


def phase_period(t, x, y):
    """2 pi / mean rate of the unwrapped angle of (x, y) over the run."""
    phase = np.unwrap(np.arctan2(y, x))
    return 2 * math.pi * (t[-1] - t[0]) / abs(phase[-1] - phase[0])


def measured_period(t, x):
    """Mean spacing of the maxima of x(t) (parabolic interpolation)."""
    peaks = []
    for i in range(1, len(x) - 1):
        if x[i] > x[i - 1] and x[i] >= x[i + 1]:
            denom = x[i - 1] - 2 * x[i] + x[i + 1]
            shift = 0.5 * (x[i - 1] - x[i + 1]) / denom if denom != 0 else 0.0
            peaks.append(t[i] + shift * (t[1] - t[0]))
    return (peaks[-1] - peaks[0]) / (len(peaks) - 1) if len(peaks) > 1 else math.nan


def main(out, paper):
    steps = sorted({d[1:] for d in os.listdir(out) if d.startswith("h")}, key=float)
    runs = {(h, n): Run(out, h, n) for h in steps for n in INTEGRATORS}
    study = read_study(os.path.join(out, "study", "study.csv"))
    with open(os.path.join(out, "machine.txt")) as f:
        machine = f.read().strip()
    md = []
    md.append(f"<!-- generated by analyze.py; {machine.replace(chr(10), '; ')} -->")

    # Table 1: the benchmark step.
    md.append(f"### Table 1 — h = {BENCH_H}, 2 s ({len(runs[(BENCH_H, 'exact')].t) - 1} increments): "
              "maximum errors over the run against the analytic solution\n")
    md.append("| integrator | max\\|ω₁−A cos Ωt\\| | max\\|ω₂−A sin Ωt\\| | max\\|ω₃−n\\| | "
              "max‖Rω − (Rω)ₑₓ‖ (global) | max rotation error [rad] | energy drift | momentum drift | "
              "Newton iterations / increment | ns/step (median) |")
    md.append("|---|---|---|---|---|---|---|---|---|---|")
    for n in INTEGRATORS:
        r = runs[(BENCH_H, n)]
        s = study.get((n, float(BENCH_H)))
        ns = f"{float(s['ns_per_step']):.0f}" if s and s["failed"] == "false" else "— (study reference)"
        newton = f"{r.stats['newton_iterations_mean']:.2f}" if n in IMPLICIT else "— (explicit)"
        if r.failed:
            md.append(f"| {n} | {failure_text(r)} | | | | | | | {newton} | |")
            continue
        e1, e2, e3 = r.max_component_errors()
        steps_note = f" ({r.stats['steps']} adaptive steps)" if n == "rkmk45" else ""
        md.append(f"| {n}{steps_note} | {fmt(e1)} | {fmt(e2)} | {fmt(e3)} | {fmt(r.err_global.max())} | "
                  f"{fmt(r.err_rot.max())} | {fmt(r.stats['energy_drift'])} | "
                  f"{fmt(r.stats['momentum_drift'])} | {newton} | {ns} |")
    md.append("")
    md.append("Energy drift = max |E − E₀|/E₀, momentum drift = max ‖L − L₀‖/‖L₀‖ (spatial angular "
              "momentum), both over the run, from `lieflow simulate --stats`. ns/step: `lieflow study` "
              "(median of repeated runs, diagnostics off). rkmk45 is adaptive (rtol 1e-8, atol 1e-10): "
              "h is only its output interval.\n")

    # Periods.
    ex = runs[(BENCH_H, "exact")]
    ga = runs[(BENCH_H, "genalpha")]
    period_global = 2 * math.pi / np.linalg.norm(A_VEC)
    md.append("### Periods (h = 0.01)\n")
    md.append("| quantity | analytic | measured on the exact-flow run | measured on the genalpha run |")
    md.append("|---|---|---|---|")
    md.append(f"| body frame, angle of (ω₁, ω₂) | 2π/Ω = {2 * math.pi / OMEGA:.5f} s | "
              f"{phase_period(ex.t, ex.w[:, 0], ex.w[:, 1]):.5f} s | "
              f"{phase_period(ga.t, ga.w[:, 0], ga.w[:, 1]):.5f} s |")
    md.append(f"| global frame, maxima of (Rω)_X | 2π I/‖L‖ = {period_global:.5f} s | "
              f"{measured_period(ex.t, ex.w_global[:, 0]):.5f} s | "
              f"{measured_period(ga.t, ga.w_global[:, 0]):.5f} s |")
    wz = ex.w_global[:, 2]
    xy = ex.w_global[:, :2]
    centre = 0.5 * (xy.max(axis=0) + xy.min(axis=0))
    md.append("")
    md.append(f"Global-frame trace (exact-flow run): (Rω)_X ∈ [{xy[:, 0].min():.5f}, {xy[:, 0].max():.5f}], "
              f"(Rω)_Y ∈ [{xy[:, 1].min():.5f}, {xy[:, 1].max():.5f}], a circle of diameter "
              f"{xy[:, 0].max() - xy[:, 0].min():.5f} (A = {AMP}) centred at ({centre[0]:.5f}, {centre[1]:.5f}); "
              f"(Rω)_Z ∈ [{wz.min():.5f}, {wz.max():.5f}].\n")

    # Table 2: larger steps, max body-frame error.
    big = steps
    md.append("### Table 2 — max over the run of ‖ω − ω_exact‖ (body frame) for each step h\n")
    md.append("| integrator | " + " | ".join(f"h = {h}" for h in big) + " |")
    md.append("|---|" + "---|" * len(big))
    for n in INTEGRATORS:
        cells = []
        for h in big:
            r = runs[(h, n)]
            cells.append(f"failed at t = {r.t_reached:g}" if r.failed else fmt(r.err_body.max()))
        md.append(f"| {n} | " + " | ".join(cells) + " |")
    md.append("")

    md.append("### Table 3 — amplitude |ω⊥(2 s)|/A (1 = exact; > 1 grows, < 1 decays) and energy drift\n")
    md.append("| integrator | " + " | ".join(f"h = {h}" for h in big) + " |")
    md.append("|---|" + "---|" * len(big))
    for n in INTEGRATORS:
        cells = []
        for h in big:
            r = runs[(h, n)]
            cells.append("failed" if r.failed else
                         f"{r.amplitude_ratio:.4f} / {fmt(r.stats['energy_drift'], 1)}")
        md.append(f"| {n} | " + " | ".join(cells) + " |")
    md.append("")
    md.append("Each cell: |ω⊥(2 s)|/A / max |E − E₀|/E₀.\n")

    # Check: with omega3 = n exactly, (omega1, omega2) obeys the linear
    # oscillation omega1 + i omega2 = z, z' = i Om z, so an explicit s-stage
    # order-s Runge-Kutta method (s <= 4) multiplies |z| by |T_s(i Om h)| per
    # step, T_s the degree-s Taylor polynomial of exp.
    md.append("Check of Table 3 against linear stability: |T_s(iΩh)|^(2 s/h), T_s = degree-s Taylor "
              "polynomial of exp (the stability function of every explicit s-stage order-s RK method, "
              "s ≤ 4):\n")
    md.append("| s (methods) | " + " | ".join(f"h = {h}" for h in big) + " |")
    md.append("|---|" + "---|" * len(big))
    families = ((1, ["rkmk-euler"]), (2, ["rkmk-heun"]), (3, ["rkmk3", "cg3"]), (4, ["rkmk4", "cf4"]))
    for s_, names in families:
        cells = []
        for h in big:
            z = 1j * OMEGA * float(h)
            gain = abs(sum(z ** k / math.factorial(k) for k in range(s_ + 1)))
            predicted = gain ** round(2.0 / float(h))
            measured = runs[(h, names[0])].amplitude_ratio
            cells.append(f"{predicted:.4f} (measured {measured:.4f})")
        md.append(f"| {s_} ({', '.join(names)}) | " + " | ".join(cells) + " |")
    md.append("")

    md.append("### Table 4 — max rotation error over the run [rad] (orientation against R(t) exact)\n")
    md.append("| integrator | " + " | ".join(f"h = {h}" for h in big) + " |")
    md.append("|---|" + "---|" * len(big))
    for n in INTEGRATORS:
        cells = []
        for h in big:
            r = runs[(h, n)]
            cells.append("failed" if r.failed else fmt(r.err_rot.max()))
        md.append(f"| {n} | " + " | ".join(cells) + " |")
    md.append("")

    md.append("### Table 5 — implicit methods: Newton iterations per increment (mean, `--stats`)\n")
    md.append("| integrator | " + " | ".join(f"h = {h}" for h in big) + " |")
    md.append("|---|" + "---|" * len(big))
    for n in sorted(IMPLICIT):
        cells = []
        for h in big:
            r = runs[(h, n)]
            it = r.stats["newton_iterations_mean"]
            cells.append(f"{it:.2f}" + (" (failed)" if r.failed else ""))
        md.append(f"| {n} | " + " | ".join(cells) + " |")
    md.append("")
    fails = [runs[k] for k in runs if runs[k].failed]
    if fails:
        md.append("Failed runs (`lieflow simulate` exit status 1, message from `--stats`):\n")
        for r in fails:
            md.append(f"- {r.name}, h = {r.h:g}: {r.stats['failure']}")
        md.append("")

    with open(os.path.join(paper, "results.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    splice_readme(os.path.join(paper, "README.md"), "\n".join(md))
    print("\n".join(md))

    figures(runs, steps, paper)


# One colour per integrator; methods that coincide on this linear problem
# (rkmk3/cg3, rkmk4/cf4, see README) share a colour family, dashed.
COLORS = {
    "rkmk-euler": "#1f77b4", "rkmk-heun": "#ff7f0e", "rkmk3": "#2ca02c", "cg3": "#98df8a",
    "rkmk4": "#d62728", "cf4": "#ff9896", "rkmk45": "#9467bd", "lgvi": "#8c564b",
    "splitting": "#bcbd22", "genalpha": "#17becf", "exact": "#000000",
}
STYLES = {n: ("--" if n in ("cg3", "cf4", "exact") else "-") for n in INTEGRATORS}


def figures(runs, steps, paper):
    t_fine = np.linspace(0.0, 2.0, 2001)
    w_fine = exact_body_omega(t_fine)
    wg_fine = np.array([rot(t * A_VEC) @ W_GLOBAL0 for t in t_fine])

    # Figure 1: body-frame omega against the analytic curves, h = 0.01 and 0.1.
    cols = [BENCH_H, "0.1"]
    fig, axes = plt.subplots(3, 2, figsize=(10, 7.5), sharex=True)
    for j, h in enumerate(cols):
        for i in range(3):
            ax = axes[i, j]
            ax.plot(t_fine, w_fine[:, i], "k-", lw=2.2, alpha=0.35, label="analytic")
            for n in INTEGRATORS:
                r = runs[(h, n)]
                ax.plot(r.t, r.w[:, i], STYLES[n], lw=0.9, color=COLORS[n], label=n)
            if i == 2:
                ax.set_ylim(SPIN - 0.05, SPIN + 0.05)
            else:
                ax.set_ylim(-0.6, 0.6)
            ax.set_ylabel(f"ω{'₁₂₃'[i]} [rad/s] (body)")
            ax.grid(alpha=0.3)
        axes[0, j].set_title(f"h = {h}")
        axes[2, j].set_xlabel("t [s]")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=6, fontsize=8)
    fig.suptitle("Force-free symmetric body: body-frame angular velocity (ω₃ axis: n ± 0.05)")
    fig.tight_layout(rect=(0, 0.07, 1, 0.97))
    fig.savefig(os.path.join(paper, "omega_body.png"), dpi=DPI)
    plt.close(fig)

    # Figure 2: global-frame omega components, h = 0.01 (the document's Figures 2-4).
    fig, axes = plt.subplots(3, 1, figsize=(8, 7.5), sharex=True)
    for i in range(3):
        ax = axes[i]
        ax.plot(t_fine, wg_fine[:, i], "k-", lw=2.2, alpha=0.35, label="analytic")
        for n in INTEGRATORS:
            r = runs[(BENCH_H, n)]
            ax.plot(r.t, r.w_global[:, i], STYLES[n], lw=0.9, color=COLORS[n], label=n)
        ax.set_ylabel(f"(Rω)_{'XYZ'[i]} [rad/s]")
        ax.grid(alpha=0.3)
    axes[2].ticklabel_format(useOffset=False)
    axes[2].set_xlabel("t [s]")
    axes[0].set_title(f"angular velocity in the global frame, h = {BENCH_H} (period 2πI/‖L‖ ≈ 0.5 s)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=6, fontsize=8)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(os.path.join(paper, "omega_global.png"), dpi=DPI)
    plt.close(fig)

    # Figure 3: X-Y trace of R omega (the document's Figure 5).
    fig, axes = plt.subplots(1, 2, figsize=(10, 5.2))
    for j, h in enumerate(cols):
        ax = axes[j]
        ax.plot(wg_fine[:, 0], wg_fine[:, 1], "k-", lw=3, alpha=0.3, label="analytic")
        for n in INTEGRATORS:
            r = runs[(h, n)]
            ax.plot(r.w_global[:, 0], r.w_global[:, 1], STYLES[n], lw=0.8, color=COLORS[n], label=n,
                    marker="." if h != BENCH_H else None, ms=3)
        half = 0.2 if h == BENCH_H else 0.45
        ax.set_xlim(0.125 - half, 0.125 + half)
        ax.set_ylim(-half, half)
        ax.set_aspect("equal")
        ax.set_xlabel("(Rω)_X [rad/s]")
        ax.set_ylabel("(Rω)_Y [rad/s]")
        ax.set_title(f"X–Y trace of Rω, h = {h}" + ("" if h == BENCH_H else " (dots: the steps)"))
        ax.grid(alpha=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=6, fontsize=8)
    fig.tight_layout(rect=(0, 0.09, 1, 1))
    fig.savefig(os.path.join(paper, "xy_trace.png"), dpi=DPI)
    plt.close(fig)

    # Figure 4: error against time, h = 0.01.
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8), sharey=True)
    for n in INTEGRATORS:
        r = runs[(BENCH_H, n)]
        axes[0].semilogy(r.t[1:], np.maximum(r.err_body[1:], FLOOR), STYLES[n], color=COLORS[n], label=n)
        axes[1].semilogy(r.t[1:], np.maximum(r.err_global[1:], FLOOR), STYLES[n], color=COLORS[n], label=n)
    axes[0].set_title(f"‖ω − ω_exact‖ (body frame), h = {BENCH_H}")
    axes[1].set_title(f"‖Rω − (Rω)_exact‖ (global frame), h = {BENCH_H}")
    for ax in axes:
        ax.set_xlabel("t [s]")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel(f"error [rad/s] (zero drawn at {FLOOR:g})")
    axes[1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    fig.savefig(os.path.join(paper, "error_vs_time.png"), dpi=DPI)
    plt.close(fig)

    # Figure 5: larger steps.
    hs = [float(h) for h in steps]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8))
    for n in INTEGRATORS:
        ok = [(float(h), runs[(h, n)]) for h in steps if not runs[(h, n)].failed]
        bad = [float(h) for h in steps if runs[(h, n)].failed]
        axes[0].loglog([p[0] for p in ok], [max(p[1].err_body.max(), FLOOR) for p in ok], "o" + STYLES[n],
                       ms=4, color=COLORS[n], label=n)
        axes[1].semilogx([p[0] for p in ok], [p[1].amplitude_ratio for p in ok], "o" + STYLES[n], ms=4,
                         color=COLORS[n], label=n)
        if bad:
            axes[0].loglog(bad, [3.0] * len(bad), "x", ms=9, mew=2, color=COLORS[n])
    axes[0].axhline(AMP, color="k", lw=0.8, ls="--")
    axes[0].text(hs[0], AMP * 1.3, "A (error as large as the wobble)", fontsize=8)
    axes[0].text(hs[0], 4.0, "x = run failed", fontsize=8)
    axes[0].set_xlabel("h [s]")
    axes[0].set_ylabel("max ‖ω − ω_exact‖ over 2 s [rad/s]")
    axes[0].set_title("larger steps: max body-frame error")
    axes[1].axhline(1.0, color="k", lw=0.8, ls="--")
    axes[1].set_yscale("log")
    axes[1].set_xlabel("h [s]")
    axes[1].set_ylabel("|ω⊥(2 s)| / A")
    axes[1].set_title("amplitude of the wobble at t = 2 s")
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
    axes[1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    fig.savefig(os.path.join(paper, "large_h.png"), dpi=DPI)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
