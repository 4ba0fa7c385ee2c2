"""Sweeps: the cartesian product of scenes x integrators x steps x options x
seeds, each case one task on a Dask distributed cluster.

    lieflow.sweep(spec, client=None, out=DIR, workers=None)
    python3 -m lieflow.sweep SPEC.json --out DIR [--scheduler ADDRESS | --workers N]

SPEC (../shared/DESIGN.md): {"scenes": [...], "integrators": [...],
"dt": [...], "options": [{...}], "seeds": [...], "t_end": T}; lists form a
cartesian product, a missing list means the scene's own value. Seeds seed the
recording noise, so a spec with seeds also gives "noise" ({"gyro": s,
"angle": s, "quat": s}, as lieflow.simulate). A scene is a built-in name, a
file or a dict in the scene schema.

Each case is written to DIR/cases/ID.json (ID: a hash of the case) once it
has finished, atomically (written aside, then renamed): a sweep that is
interrupted, or whose worker dies, loses no finished case, and running it
again runs only the cases without a file. At the end DIR/results.csv holds
one row per case, in the spec's order: the case's keys (case_id, scene,
integrator, dt, t_end, options, seed, with the values in force), then the
``--stats`` keys of the run.

Without a client the sweep starts a local cluster of `workers` processes
(default: the number of CPUs) and closes it at the end; with a client (or
--scheduler ADDRESS) it runs on that cluster, whose workers must be able to
`import lieflow`.
"""
import argparse
import csv
import hashlib
import itertools
import json
import math
import os
import sys
import tempfile
import time
import types

from . import commands
from ._lieflow import ComputationError, InputError

_SPEC_KEYS = {"scenes", "integrators", "dt", "options", "seeds", "t_end", "noise"}
_CASE_KEYS = ["case_id", "scene", "integrator", "dt", "t_end", "options", "seed"]
_STATS_KEYS = ["steps", "wall_seconds", "ns_per_step", "energy_drift", "momentum_drift", "constraint_error",
               "newton_iterations_mean", "invariants", "failed", "failure"]
# Every output row is dropped but the first and the last: a sweep keeps stats.
_EVERY = 1_000_000_000


def _list(spec, key):
    if key not in spec:
        return [None]
    values = spec[key]
    if not isinstance(values, list) or not values:
        raise InputError(f"sweep spec: '{key}' must be a non-empty list")
    return values


def cases(spec):
    """The cases of a spec, in order (InputError naming the key if malformed)."""
    if not isinstance(spec, dict):
        raise InputError("sweep spec: expected a JSON object")
    unknown = set(spec) - _SPEC_KEYS
    if unknown:
        raise InputError(f"sweep spec: unknown key(s) {sorted(unknown)} (known: {sorted(_SPEC_KEYS)})")
    if "scenes" not in spec:
        raise InputError("sweep spec: 'scenes' is required")
    t_end = spec.get("t_end")
    if t_end is not None and (isinstance(t_end, bool) or not isinstance(t_end, (int, float))
                              or not math.isfinite(t_end) or t_end <= 0):
        raise InputError(f"sweep spec: 't_end' must be a positive number, got {t_end!r}")
    noise = spec.get("noise")
    if noise is not None and not isinstance(noise, dict):
        raise InputError("sweep spec: 'noise' must be an object like {\"gyro\": 0.01}")
    seeds = _list(spec, "seeds")
    if seeds != [None] and not noise:
        raise InputError("sweep spec: 'seeds' seed the recording noise: give 'noise' too")
    for key in ("integrators", "dt", "options"):
        _list(spec, key)
    for o in _list(spec, "options"):
        if o is not None and not isinstance(o, dict):
            raise InputError(f"sweep spec: each 'options' entry must be an object, got {o!r}")
    out = []
    for scene, integrator, dt, options, seed in itertools.product(
            _list(spec, "scenes"), _list(spec, "integrators"), _list(spec, "dt"), _list(spec, "options"), seeds):
        if not isinstance(scene, (str, dict)):
            raise InputError(f"sweep spec: a scene is a name, a file or an object, got {scene!r}")
        case = {"scene": scene, "integrator": integrator, "dt": dt, "t_end": t_end, "options": options,
                "seed": seed, "noise": noise}
        case["case_id"] = hashlib.sha1(json.dumps(case, sort_keys=True).encode()).hexdigest()[:16]
        out.append(case)
    return out


def _scene_name(scene):
    return scene.get("name", "scene dict") if isinstance(scene, dict) else scene


def run_case(case):
    """Runs one case (on a worker) and returns its results row: the case's
    keys with the values in force, then the stats. Bad input and failed runs
    are rows too (failed, failure), so one bad case does not stop a sweep."""
    row = {"case_id": case["case_id"], "scene": _scene_name(case["scene"]), "integrator": case["integrator"],
           "dt": case["dt"], "t_end": case["t_end"], "options": case["options"], "seed": case["seed"]}
    noise = dict(case["noise"] or {})
    if case["seed"] is not None:
        noise["seed"] = case["seed"]
    try:
        result = commands.simulate(case["scene"], integrator=case["integrator"], dt=case["dt"], t_end=case["t_end"],
                                   every=_EVERY, options=case["options"], noise=noise or None, partial=True)
    except (InputError, ComputationError) as e:
        kind = "bad input" if isinstance(e, InputError) else "computation failed"
        row.update({key: None for key in _STATS_KEYS})
        row.update({"failed": True, "failure": f"{kind}: {e}"})
        return row
    stats = result.stats
    row["integrator"] = stats.get("integrator")
    row["dt"] = stats.get("dt")
    row["t_end"] = float(result.columns["t"][-1]) if len(result.columns["t"]) else None
    row.update({key: stats.get(key) for key in _STATS_KEYS})
    return row


def _write_atomically(path, text):
    directory = os.path.dirname(path)
    fd, temporary = tempfile.mkstemp(dir=directory, prefix=".partial-")
    with os.fdopen(fd, "w") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(temporary, path)


def _cell(value):
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (dict, list)):
        return json.dumps(value, sort_keys=True)
    return str(value)


def _merge(all_cases, directory, path):
    rows = []
    for case in all_cases:
        with open(os.path.join(directory, case["case_id"] + ".json")) as f:
            rows.append(json.load(f))
    fd, temporary = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".partial-")
    with os.fdopen(fd, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(_CASE_KEYS + _STATS_KEYS)
        for row in rows:
            writer.writerow([_cell(row.get(key)) for key in _CASE_KEYS + _STATS_KEYS])
    os.replace(temporary, path)
    return rows


def _distributed():
    """dask.distributed, or an ImportError that says what to install."""
    try:
        import dask.distributed
    except ImportError as e:
        raise ImportError("lieflow.sweep runs on Dask distributed: apt-get install python3-distributed "
                          f"(or pip install distributed) ({e})") from None
    return dask.distributed


def _local_cluster(workers):
    distributed = _distributed()
    Client, LocalCluster = distributed.Client, distributed.LocalCluster

    # Worker processes import lieflow from where this process found it.
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    if package_parent not in paths:
        os.environ["PYTHONPATH"] = os.pathsep.join([package_parent] + paths)
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")
    return Client(cluster), cluster


def sweep(spec, client=None, out=None, workers=None, progress=None):
    """Runs the cases of `spec` not yet in `out` on a Dask cluster and merges
    every case into out/results.csv. Returns a dict: cases, ran, reused,
    failed (cases whose run failed), seconds, results (the CSV's path), rows
    (the merged rows, as dicts). `progress`: called with (done, to_run) as
    cases finish."""
    if out is None:
        raise InputError("sweep: give out=DIR (where the cases and results.csv go)")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InputError(f"sweep: workers must be a positive integer, got {workers!r}")
    all_cases = cases(spec)
    ids = [c["case_id"] for c in all_cases]
    if len(set(ids)) != len(ids):
        raise InputError("sweep spec: a case appears twice (repeated values in a list)")
    out = os.fspath(out)
    case_dir = os.path.join(out, "cases")
    os.makedirs(case_dir, exist_ok=True)
    to_run = [c for c in all_cases if not os.path.exists(os.path.join(case_dir, c["case_id"] + ".json"))]
    start = time.perf_counter()
    if to_run:
        as_completed = _distributed().as_completed
        own = None
        if client is None:
            client, own = _local_cluster(workers or os.cpu_count() or 1)
        try:
            futures = [client.submit(run_case, c, key=f"lieflow-case-{c['case_id']}", pure=False) for c in to_run]
            for done, future in enumerate(as_completed(futures), start=1):
                row = future.result()
                _write_atomically(os.path.join(case_dir, row["case_id"] + ".json"), json.dumps(row))
                if progress:
                    progress(done, len(to_run))
        finally:
            if own is not None:
                client.close()
                own.close()
    seconds = time.perf_counter() - start
    results = os.path.join(out, "results.csv")
    rows = _merge(all_cases, case_dir, results)
    return {"cases": len(all_cases), "ran": len(to_run), "reused": len(all_cases) - len(to_run),
            "failed": sum(1 for r in rows if r.get("failed")), "seconds": seconds, "results": results, "rows": rows}


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m lieflow.sweep",
                                     description="Run a lieflow sweep (SPEC.json) on a Dask cluster.")
    parser.add_argument("spec", help="the sweep's SPEC.json")
    parser.add_argument("--out", required=True, help="directory for the cases and results.csv")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786)")
    where.add_argument("--workers", type=int, help="local worker processes (default: the number of CPUs)")
    args = parser.parse_args(argv)
    try:
        try:
            with open(args.spec) as f:
                spec = json.load(f)
        except (OSError, ValueError) as e:
            raise InputError(f"{args.spec}: {e}") from None
        client = None
        if args.scheduler:
            client = _distributed().Client(args.scheduler)

        def report(done, total):
            print(f"lieflow sweep: {done}/{total} cases done", file=sys.stderr, flush=True)

        summary = sweep(spec, client=client, out=args.out, workers=args.workers, progress=report)
        if client is not None:
            client.close()
    except InputError as e:
        print(f"lieflow sweep: {e}", file=sys.stderr)
        return 2
    print(f"{summary['cases']} cases: {summary['ran']} run, {summary['reused']} already done, "
          f"{summary['failed']} failed, {summary['seconds']:.2f} s; results in {summary['results']}")
    return 0


class _CallableModule(types.ModuleType):
    """lieflow.sweep is this module and a function: lieflow.sweep(spec, ...)."""

    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule

if __name__ == "__main__":
    sys.exit(main())
