#!/usr/bin/python3
"""The section "estimators" of papers/hinge-axis-identification/README.md.

Usage: analyze_estimators.py ESTIMATORS_TSV MACHINE_TXT PAPER_DIR
  ESTIMATORS_TSV what bench/calibration/study_hinge_estimators wrote (one row
                 per trial and method: case, method, parameter, trial, status,
                 error_main, error_secondary, sigma_main, sigma_secondary,
                 bound_main, bound_secondary [deg], seconds)
  MACHINE_TXT    reproduce.sh's machine stamp
  PAPER_DIR      where estimators.png goes and whose README.md receives the table
                 (between the markers of section "estimators", as analyze.py)

Per point: trials answered (the rest refused as not identifiable); the median
and 95th percentile of a trial's error (the larger of its two axes'); the
share within 0.5 deg; errors within 3 sigma (both axes counted); the mean of
(error/sigma)^2 per axis (1 for an honest sigma); sigma over the Cramer-Rao
bound at the true motion (median, both axes); the median fit time.
"""
import csv
import os
import statistics
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from analyze import splice_section  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASE_TITLES = {
    "noise": "gyroscope noise [rad/s], N = 1000",
    "samples": "samples N at 100 Hz, gyroscopes 0.1 rad/s",
    "acc_random": "random motions, gyroscopes 0.01 rad/s, accelerometers 0.05 m/s², N = 1000",
    "acc_knee": "knee-like motions (wobble 0.05 rad), same noise",
    "bias": "gyroscope biases N(0, 0.05²) rad/s per axis, noise 0.01 rad/s, N = 1000",
    "wobble": "sensors wobbling at 10–20 Hz [rad/s amplitude], gyroscopes 0.05 rad/s, N = 1000",
}


def read(path):
    points = defaultdict(list)
    order = []
    with open(path) as f:
        for row in csv.DictReader(f, delimiter="\t"):
            key = (row["case"], row["method"], float(row["parameter"]))
            if key not in points:
                order.append(key)
            points[key].append(row)
    return order, points


def percentile(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, int(q * len(values)))] if values else float("nan")


def summarize(rows):
    # "unconverged": answered with converged = false (the fit's own misfit flag).
    ok = [r for r in rows if r["status"] in ("ok", "unconverged")]
    s = {"trials": len(rows), "answered": len(ok), "flagged": sum(r["status"] == "unconverged" for r in rows)}
    if not ok:
        return s
    e = [(float(r["error_main"]), float(r["error_secondary"])) for r in ok]
    sg = [(float(r["sigma_main"]), float(r["sigma_secondary"])) for r in ok]
    worst = [max(a, b) for a, b in e]
    s["median"] = statistics.median(worst)
    s["p95"] = percentile(worst, 0.95)
    s["half"] = sum(w <= 0.5 for w in worst) / len(ok)
    s["within"] = sum(ei <= 3 * si for pair, spair in zip(e, sg) for ei, si in zip(pair, spair))
    s["ratio"] = [statistics.fmean((pair[a] / spair[a]) ** 2 for pair, spair in zip(e, sg)) for a in (0, 1)]
    bounds = [(float(r["bound_main"]), float(r["bound_secondary"])) for r in ok]
    if all(b[0] > 0 for b in bounds):
        s["efficiency"] = statistics.median(
            spair[a] / b[a] for spair, b in zip(sg, bounds) for a in (0, 1))
        s["bound"] = statistics.median(max(b) for b in bounds)
    s["sigma"] = statistics.median(max(p) for p in sg)
    s["seconds"] = statistics.median(float(r["seconds"]) for r in ok)
    return s


def table(order, points):
    lines = ["| point | method | answered | median error [°] | 95 % [°] | ≤ 0.5° | within 3σ | "
             "mean (error/σ)² main / secondary | σ / bound | fit time [ms] |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    current = None
    for key in order:
        case, method, parameter = key
        if case != current:
            lines.append(f"| **{CASE_TITLES.get(case, case)}** | | | | | | | | | |")
            current = case
        s = summarize(points[key])
        if s["answered"] == 0:
            lines.append(f"| {parameter:g} | {method} | 0 of {s['trials']} | | | | | | | |")
            continue
        eff = f"{s['efficiency']:.3f}" if "efficiency" in s else "–"
        flagged = f" ({s['flagged']} not converged)" if s["flagged"] else ""
        lines.append(
            f"| {parameter:g} | {method} | {s['answered']} of {s['trials']}{flagged} | {s['median']:.3g} | {s['p95']:.3g} | "
            f"{100 * s['half']:.0f} % | {s['within']} of {2 * s['answered']} | "
            f"{s['ratio'][0]:.2f} / {s['ratio'][1]:.2f} | {eff} | {1000 * s['seconds']:.3g} |")
    return "\n".join(lines)


def figure(order, points, path):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, case, xlabel in ((axes[0], "noise", "gyroscope noise σ [rad/s]"),
                             (axes[1], "samples", "samples N (100 Hz)")):
        for method, style in (("constraint", "o-"), ("likelihood", "s-")):
            keys = [k for k in order if k[0] == case and k[1] == method]
            xs, med, sig = [], [], []
            for k in keys:
                s = summarize(points[k])
                if s["answered"]:
                    xs.append(k[2])
                    med.append(s["median"])
                    sig.append(s["sigma"])
            ax.loglog(xs, med, style, label=f"{method}: median error")
            ax.loglog(xs, sig, style.replace("-", "--"), alpha=0.6, label=f"{method}: median σ")
        keys = [k for k in order if k[0] == case and k[1] == "likelihood"]
        xs = [k[2] for k in keys if "bound" in summarize(points[k])]
        ax.loglog(xs, [summarize(points[k])["bound"] for k in keys if "bound" in summarize(points[k])], "k:",
                  label="Cramér–Rao bound (median)")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("axis angle [deg] (larger of the two axes)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Hinge axis from two gyroscopes: Seel's constraint, maximum likelihood and the bound")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(tsv, machine, paper):
    order, points = read(tsv)
    with open(machine) as f:
        stamp = "`" + "`, `".join(f.read().strip().splitlines()) + "`"
    text = stamp + "\n\n" + table(order, points)
    figure(order, points, os.path.join(paper, "estimators.png"))
    splice_section(os.path.join(paper, "README.md"), "estimators", text)
    print(text)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
