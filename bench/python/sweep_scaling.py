"""Measures lieflow.sweep on local Dask clusters (README "Sweeps on a cluster"):

- the speed-up of a 200-case sweep on 2 worker processes against 1 (wall
  time of the whole sweep, cluster start and the merged CSV included, and of
  the cases alone: the sum of the cases' own run times);
- the overhead per task: a sweep of 200 cases of one step each on 1 worker,
  minus the same cases run in this process, per case.

    PYTHONPATH=build/python python3 bench/python/sweep_scaling.py

Prints a table; the figures depend on the machine (this one has
os.cpu_count() CPUs, shared by the scheduler, the workers and this process).
"""
import os
import shutil
import tempfile
import time

import lieflow
from lieflow import sweep as sweep_module

# 200 cases of about 50 ms: a 3-body chain, 4 integrators x 50 steps, 10 s each.
WORK = {"scenes": ["chain-3"], "integrators": ["rkmk4", "cf4", "lgvi", "rkmk3"],
        "dt": [round(0.001 + 0.00002 * k, 6) for k in range(50)], "t_end": 10.0}
# 200 cases of one or two steps: what a task costs beyond its run.
TINY = {"scenes": ["pendulum"], "integrators": ["rkmk4", "cf4", "lgvi", "rkmk3"],
        "dt": [round(0.001 + 0.00002 * k, 6) for k in range(50)], "t_end": 0.002}


def timed_sweep(spec, workers):
    out = tempfile.mkdtemp(prefix="lieflow-sweep-bench-")
    try:
        start = time.perf_counter()
        summary = lieflow.sweep(spec, out=out, workers=workers)
        wall = time.perf_counter() - start
    finally:
        shutil.rmtree(out, ignore_errors=True)
    assert summary["cases"] == 200 and summary["failed"] == 0, summary["failed"]
    busy = sum(r["wall_seconds"] for r in summary["rows"])
    return wall, busy


def in_process(spec):
    start = time.perf_counter()
    for case in sweep_module.cases(spec):
        sweep_module.run_case(case)
    return time.perf_counter() - start


def main():
    print(f"lieflow {lieflow.__version__}, {os.cpu_count()} CPUs")
    serial = in_process(WORK)
    one, busy_one = timed_sweep(WORK, 1)
    two, busy_two = timed_sweep(WORK, 2)
    print(f"200 cases of chain-3 (sum of the runs {busy_one:.2f} s on 1 worker, {busy_two:.2f} s on 2):")
    print(f"  in this process, one by one: {serial:.2f} s")
    print(f"  sweep, 1 worker:  {one:.2f} s")
    print(f"  sweep, 2 workers: {two:.2f} s   speed-up {one / two:.2f}x")
    tiny_serial = in_process(TINY)
    tiny_one, _ = timed_sweep(TINY, 1)
    print(f"200 one-step cases: in process {tiny_serial:.3f} s, sweep on 1 worker {tiny_one:.2f} s")
    start = time.perf_counter()
    client, cluster = sweep_module._local_cluster(1)
    client.close()
    cluster.close()
    cluster_seconds = time.perf_counter() - start
    print(f"  starting and stopping a 1-worker local cluster: {cluster_seconds:.2f} s")
    print(f"  overhead per task: {1e3 * (tiny_one - tiny_serial) / 200:.1f} ms with the cluster's start, "
          f"{1e3 * (tiny_one - tiny_serial - cluster_seconds) / 200:.1f} ms without")


if __name__ == "__main__":
    main()
