#!/usr/bin/python3
"""Work-precision diagram from bench_work_precision's CSV.

usage: plot_work_precision.py OUTDIR/work_precision.csv [OUT.png]

Orientation error at T against run time (both log scales), one line per
method (nominal order, and the observed order: median slope over step
doublings with errors in [1e-11, 1e-2]); lieflow solid, MuJoCo dashed; the 1e-6 line where the issue's
accuracy target applies. Writes OUT.png (default: next to the CSV).
Needs matplotlib (Debian: python3-matplotlib); without it, says so and exits 0.
"""
import csv
import os
import sys


def observed_order(pts):
    """Median of log2(e(N)/e(2N)) over successive step doublings whose errors
    lie in [1e-11, 1e-2] (above the rounding floor, in the asymptotic range)."""
    import math
    by_n = {p[2]: p[1] for p in pts}
    slopes = [math.log2(by_n[n] / by_n[2 * n]) for n in sorted(by_n)
              if 2 * n in by_n and 1e-11 <= by_n[2 * n] and by_n[n] <= 1e-2]
    if not slopes:
        return "-"
    slopes.sort()
    return "%.1f" % slopes[len(slopes) // 2]


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 2 if len(argv) < 2 else 0
    csv_path = argv[1]
    out = argv[2] if len(argv) > 2 else os.path.join(os.path.dirname(csv_path) or ".",
                                                     "work_precision.png")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot skipped: matplotlib not found (apt-get install python3-matplotlib)")
        return 0

    series = {}
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            if row["failed"] != "0" or float(row["orientation_error"]) <= 0.0:
                continue
            key = (row["family"], row["method"], int(row["order"]))
            series.setdefault(key, []).append(
                (float(row["seconds"]), float(row["orientation_error"]), int(row["steps"])))
    if not series:
        print("no data in", csv_path)
        return 1

    fig, ax = plt.subplots(figsize=(9.5, 4.8), dpi=90)
    markers = "osD^v<>ph*"
    for i, ((family, method, order), pts) in enumerate(sorted(series.items())):
        pts.sort()
        t = [p[0] for p in pts]
        e = [p[1] for p in pts]
        label = ("MuJoCo " if family == "mujoco" else "lieflow ") + \
            method.replace("mujoco-", "") + " (order %d, observed %s)" % (order, observed_order(pts))
        ax.loglog(t, e, marker=markers[i % len(markers)], markersize=3.5, linewidth=1.2,
                  linestyle="--" if family == "mujoco" else "-", label=label)
    ax.axhline(1e-6, color="0.5", linewidth=0.8, linestyle=":")
    ax.text(ax.get_xlim()[0] * 1.3, 1.4e-6, "1e-6", color="0.4", fontsize=8)
    ax.set_xlabel("run time of the N steps over T = 10 s (s, median of repeats)")
    ax.set_ylabel("orientation error at T (rad)")
    ax.set_title("Free rigid body, T = 10 s: error vs run time", fontsize=10)
    ax.grid(True, which="major", linewidth=0.4, alpha=0.6)
    ax.legend(fontsize=7.5, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(out)
    print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
