"""Sweeps: the cartesian product of scenes x integrators x steps x options x
seeds, each case one task on a Dask distributed cluster.

    lieflow.sweep(spec, client=None, out=DIR, workers=None, case_timeout=None)
    python3 -m lieflow.sweep SPEC.json --out DIR [--scheduler ADDRESS | --workers N] [--case-timeout S]

SPEC (../shared/DESIGN.md): {"scenes": [...], "integrators": [...],
"dt": [...], "options": [{...}], "seeds": [...], "t_end": T}; lists form a
cartesian product, a missing list means the scene's own value. Seeds seed the
recording noise, so a spec with seeds also gives "noise" ({"gyro": s,
"angle": s, "quat": s}, as lieflow.simulate). A scene is a built-in name, a
file or a dict in the scene schema. "case_timeout" (seconds, default 3600)
bounds each case's run.

Every case runs in a process of its own that the worker keeps for its cases
(lieflow._sweep_child): a case that crashes it, hangs past the time limit or
is killed is a failed row saying so, and the sweep goes on. Each case is
written to DIR/cases/ID.json once it has finished, atomically (written aside,
then renamed): a sweep that is interrupted, or whose worker dies, loses no
finished case, and running it again runs only the cases without a valid file.
The ID is a hash of what the case runs: the scene's content (a file's bytes,
not its path), the integrator, step, options, seed and noise, and lieflow's
version, so an edited scene file is run again. DIR/results.csv, written at
the end whatever happened (also when the sweep is interrupted: the cases it
did not finish are rows that say so), holds one row per case, in the spec's
order: the case's keys (case_id, scene, integrator, dt, t_end, options, seed,
with the values in force), then the ``--stats`` keys of the run. DIR/spec.json
keeps the spec; a different spec is refused in the same DIR.

Without a client the sweep starts a local cluster of `workers` processes
(default: the number of CPUs) and closes it at the end; with a client (or
--scheduler ADDRESS) it runs on that cluster, whose workers must be able to
`import lieflow`.
"""
import argparse
import csv
import fcntl
import hashlib
import io
import itertools
import json
import logging
import math
import numbers
import os
import select
import signal
import subprocess
import sys
import tempfile
import threading
import time
import types

from . import commands
from ._lieflow import ComputationError, InputError, __version__

_SPEC_KEYS = {"scenes", "integrators", "dt", "options", "seeds", "t_end", "noise", "case_timeout"}
_NOISE_KEYS = {"gyro", "angle", "quat", "acc", "bias_gyro"}
_CASE_KEYS = ["case_id", "scene", "integrator", "dt", "t_end", "options", "seed"]
_STATS_KEYS = ["steps", "wall_seconds", "ns_per_step", "energy_drift", "momentum_drift", "constraint_error",
               "newton_iterations_mean", "invariants", "failed", "failure"]
# Every output row is dropped but the first and the last: a sweep keeps stats.
_EVERY = 1_000_000_000
# A case's run may take this long [s] unless the spec or the caller says otherwise.
DEFAULT_CASE_TIMEOUT = 3600.0
# The longest a case may be given [s]: a year (the clock's waits take no more).
MAX_CASE_TIMEOUT = 365.0 * 86400.0
# Local worker processes beyond this many per CPU only compete for it.
_MAX_WORKERS_PER_CPU = 4
# Cases handed to the cluster at once per worker: enough to keep every worker
# busy, few enough that the first results come back at once on 10^5 cases.
_IN_FLIGHT_PER_WORKER = 4


def _list(spec, key):
    if key not in spec:
        return [None]
    values = spec[key]
    if not isinstance(values, list) or not values:
        raise InputError(f"sweep spec: '{key}' must be a non-empty list")
    return values


def _positive(what, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
        raise InputError(f"{what} must be a positive number, got {value!r}")
    return float(value)


def _scene_identity(scene):
    """What a scene is, for the case id: a dict's content, a file's bytes
    (hashed: an edited file is a new case), a built-in scene's name."""
    if isinstance(scene, dict):
        return {"dict": scene}
    if os.path.isfile(scene):
        digest = hashlib.sha256()
        try:
            with open(scene, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    digest.update(block)
        except OSError as e:
            raise InputError(f"sweep spec: scene {scene!r}: {e.strerror}") from None
        return {"file": scene, "sha256": digest.hexdigest()}
    return {"name": scene}


def cases(spec):
    """The cases of a spec, in order, each once (InputError naming the key if
    malformed). Cases that run the same thing (a repeated value, `{}` and
    no options) are one case."""
    return _cases(spec)[0]


def _plain_spec(spec):
    """The spec as plain JSON data (NumPy values as numbers, every number
    finite), or InputError."""
    if not isinstance(spec, dict):
        raise InputError("sweep spec: expected a JSON object")
    try:
        return commands._plain(spec, "")
    except InputError as e:
        raise InputError(f"sweep spec: {e}") from None
    except RecursionError:
        raise InputError("sweep spec: nested too deeply (or it contains itself)") from None


def _cases(spec):
    """(cases, number of duplicates dropped)."""
    spec = _plain_spec(spec)
    unknown = set(spec) - _SPEC_KEYS
    if unknown:
        raise InputError(f"sweep spec: unknown key(s) {sorted(unknown)} (known: {sorted(_SPEC_KEYS)})")
    if "scenes" not in spec:
        raise InputError("sweep spec: 'scenes' is required")
    t_end = spec.get("t_end")
    if t_end is not None:
        t_end = _positive("sweep spec: 't_end'", t_end)
    if spec.get("case_timeout") is not None and \
            _positive("sweep spec: 'case_timeout'", spec["case_timeout"]) > MAX_CASE_TIMEOUT:
        raise InputError(f"sweep spec: 'case_timeout' is beyond {MAX_CASE_TIMEOUT:g} s (a year)")
    noise = spec.get("noise")
    if noise is not None:
        if not isinstance(noise, dict):
            raise InputError("sweep spec: 'noise' must be an object like {\"gyro\": 0.01}")
        unknown_noise = set(noise) - _NOISE_KEYS
        if unknown_noise:
            raise InputError(f"sweep spec: 'noise' has unknown key(s) {sorted(unknown_noise)} "
                             f"(known: {sorted(_NOISE_KEYS)})")
        for key, value in noise.items():
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) \
                    or value < 0:
                raise InputError(f"sweep spec: noise '{key}' must be a finite number >= 0, got {value!r}")
    seeds = _list(spec, "seeds")
    if seeds != [None] and not noise:
        raise InputError("sweep spec: 'seeds' seed the recording noise: give 'noise' too")
    for seed in seeds:
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**63):
            raise InputError(f"sweep spec: each seed must be an integer from 0 to 2^63 - 1, got {seed!r}")
    for key in ("integrators", "dt", "options"):
        _list(spec, key)
    for o in _list(spec, "options"):
        if o is not None and not isinstance(o, dict):
            raise InputError(f"sweep spec: each 'options' entry must be an object, got {o!r}")
    for dt in _list(spec, "dt"):
        if dt is not None:
            _positive("sweep spec: each 'dt'", dt)
    for scene in _list(spec, "scenes"):
        if not isinstance(scene, (str, dict)):
            raise InputError(f"sweep spec: a scene is a name, a file or an object, got {scene!r}")
    identities = {}
    out, seen, duplicates = [], set(), 0
    for index, (scene, integrator, dt, options, seed) in enumerate(itertools.product(
            _list(spec, "scenes"), _list(spec, "integrators"), _list(spec, "dt"), _list(spec, "options"), seeds)):
        options = options or None  # {} runs as no options
        dt = None if dt is None else float(dt)
        key = json.dumps(scene, sort_keys=True) if isinstance(scene, dict) else scene
        if key not in identities:
            identities[key] = _scene_identity(scene)
        case = {"scene": scene, "integrator": integrator, "dt": dt, "t_end": t_end, "options": options,
                "seed": seed, "noise": noise}
        what = dict(case, scene=identities[key], lieflow=__version__)
        case["case_id"] = hashlib.sha1(json.dumps(what, sort_keys=True).encode()).hexdigest()[:16]
        if case["case_id"] in seen:
            duplicates += 1
            continue
        seen.add(case["case_id"])
        out.append(case)
    return out, duplicates


def _scene_name(scene):
    return scene.get("name", "scene dict") if isinstance(scene, dict) else scene


def _case_row(case):
    return {"case_id": case["case_id"], "scene": _scene_name(case["scene"]), "integrator": case["integrator"],
            "dt": case["dt"], "t_end": case["t_end"], "options": case["options"], "seed": case["seed"]}


def _failed_row(case, failure):
    row = _case_row(case)
    row.update({key: None for key in _STATS_KEYS})
    row.update({"failed": True, "failure": failure})
    return row


def run_case(case):
    """Runs one case in this process and returns its results row: the case's
    keys with the values in force, then the stats. Bad input and failed runs
    are rows too (failed, failure), so one bad case does not stop a sweep."""
    row = _case_row(case)
    noise = dict(case["noise"] or {})
    if case["seed"] is not None:
        noise["seed"] = case["seed"]
    try:
        result = commands.simulate(case["scene"], integrator=case["integrator"], dt=case["dt"], t_end=case["t_end"],
                                   every=_EVERY, options=case["options"], noise=noise or None, partial=True)
    except (InputError, ComputationError) as e:
        kind = "bad input" if isinstance(e, InputError) else "computation failed"
        return _failed_row(case, f"{kind}: {e}")
    stats = result.stats
    row["integrator"] = stats.get("integrator")
    row["dt"] = stats.get("dt")
    row["t_end"] = float(result.columns["t"][-1]) if len(result.columns["t"]) else None
    row.update({key: stats.get(key) for key in _STATS_KEYS})
    return row


def _signal_name(number):
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


class _IsolatedRunner:
    """A worker's process for its cases (lieflow._sweep_child), started on
    first use and again after a case ended it."""

    def __init__(self):
        self._child = None
        self._pending = b""

    def _start(self):
        package_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        env = dict(os.environ)
        paths = [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
        env["PYTHONPATH"] = os.pathsep.join([package_parent] + [p for p in paths if p != package_parent])
        # A session of its own: a Ctrl-C in the terminal reaches the sweep,
        # which stops its workers, not every case process with a traceback.
        self._child = subprocess.Popen([sys.executable, "-m", "lieflow._sweep_child"], stdin=subprocess.PIPE,
                                       stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env,
                                       start_new_session=True)
        self._pending = b""

    def _stop(self):
        if self._child is not None:
            try:
                self._child.kill()
            except OSError:
                pass
            self._child.wait()
            self._child = None

    def run(self, case, timeout):
        if self._child is None or self._child.poll() is not None:
            self._start()
        child = self._child
        try:
            child.stdin.write((json.dumps(case) + "\n").encode())
            child.stdin.flush()
        except OSError:
            pass  # it died before reading: reported below
        deadline = time.monotonic() + timeout
        fd = child.stdout.fileno()
        while b"\n" not in self._pending:
            left = deadline - time.monotonic()
            if left <= 0:
                self._stop()
                return _failed_row(case, f"timed out: the case ran longer than its limit of {timeout:g} s "
                                         "(case_timeout)")
            ready, _, _ = select.select([fd], [], [], left)
            if not ready:
                continue
            block = os.read(fd, 1 << 16)
            if not block:  # the process ended
                status = child.wait()
                self._child = None
                how = f"with {_signal_name(-status)}" if status < 0 else f"with exit status {status}"
                hint = " (out of memory?)" if status == -signal.SIGKILL else ""
                return _failed_row(case, f"crashed: the process running the case ended {how}{hint}")
            self._pending += block
        line, self._pending = self._pending.split(b"\n", 1)
        return json.loads(line)


_runners = threading.local()


def _run_isolated(case, timeout):
    """A sweep task (on a worker): the case in the worker's own case process."""
    runner = getattr(_runners, "runner", None)
    if runner is None:
        runner = _runners.runner = _IsolatedRunner()
    return runner.run(case, timeout)


def _file_mode():
    """The mode open() gives a new file under the current umask (mkstemp's
    files are 0600; the sweep's files are for the user's other tools too)."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def _write_atomically(path, text):
    directory = os.path.dirname(path)
    fd, temporary = tempfile.mkstemp(dir=directory, prefix=".partial-")
    try:
        os.fchmod(fd, _file_mode())
        with os.fdopen(fd, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise


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


def _finished_row(directory, case):
    """The case's row from its file, or None when there is none that belongs
    to it (missing, empty, cut short, another case's or not a row at all)."""
    try:
        with open(os.path.join(directory, case["case_id"] + ".json")) as f:
            row = json.load(f)
    except (OSError, ValueError):
        return None
    if not isinstance(row, dict) or row.get("case_id") != case["case_id"] or "failed" not in row:
        return None
    return row


def _merge(all_cases, directory, path, stopped=None):
    rows = []
    for case in all_cases:
        row = _finished_row(directory, case)
        if row is None:
            row = _failed_row(case, f"not run: the sweep stopped before it ({stopped or 'unknown reason'})")
        rows.append(row)
    text = io.StringIO(newline="")
    writer = csv.writer(text)
    writer.writerow(_CASE_KEYS + _STATS_KEYS)
    for row in rows:
        writer.writerow([_cell(row.get(key)) for key in _CASE_KEYS + _STATS_KEYS])
    try:
        _write_atomically(path, text.getvalue())
    except OSError as e:
        raise InputError(f"out: cannot write {path} ({e.strerror or e})") from None
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


def _lock(out):
    """An exclusive lock on DIR for the sweep's life (flock on DIR/.lock):
    two sweeps into one directory would overwrite each other's spec and
    results. The lock goes with the process, also when it is killed."""
    path = os.path.join(out, ".lock")
    try:
        f = open(path, "a")
    except OSError as e:
        raise InputError(f"out: cannot create {path} ({e.strerror or e})") from None
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        f.close()
        raise InputError(f"out: {out!r} is in use by another sweep (it holds {path}); give another directory "
                         "or wait for it") from None
    return f


def _prepare_directory(out, spec):
    """DIR and DIR/cases, checked writable; DIR/spec.json written, or
    InputError when DIR holds another spec's sweep."""
    if out is None:
        raise InputError("sweep: give out=DIR (where the cases and results.csv go)")
    if not isinstance(out, (str, os.PathLike)):
        raise InputError(f"out: expected a directory path, got {type(out).__name__}")
    out = os.fspath(out)
    case_dir = os.path.join(out, "cases")
    try:
        os.makedirs(case_dir, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=case_dir, prefix=".probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as e:
        raise InputError(f"out: {out!r} cannot hold the sweep ({e.strerror or e}): give a writable directory") \
            from None
    lock = _lock(out)
    spec_path = os.path.join(out, "spec.json")
    spec_text = json.dumps(spec, sort_keys=True, indent=1)
    if os.path.exists(spec_path):
        try:
            with open(spec_path) as f:
                earlier = json.load(f)
        except (OSError, ValueError):
            earlier = None
        if json.dumps(earlier, sort_keys=True, indent=1) != spec_text:
            raise InputError(f"out: {out!r} holds the sweep of another spec ({spec_path}); give another directory, "
                             "or remove its spec.json and results.csv to replace that sweep")
    else:
        _write_atomically(spec_path, spec_text + "\n")
    return out, case_dir, lock


def _importing_a_worker():
    """Whether this call runs while a local worker process imports the
    caller's script: Dask starts workers by spawning Python processes that
    import the script as __mp_main__, and a script without an
    ``if __name__ == "__main__":`` guard would start a sweep in each of them,
    and they theirs, without end. There the call does nothing; the script's
    own process runs the sweep."""
    # multiprocessing runs the script as the module "__mp_main__" in a
    # spawned process (its parent_process() is not set yet at that point).
    frame = sys._getframe(1)
    while frame is not None:
        if frame.f_globals.get("__name__") == "__mp_main__":
            return True
        frame = frame.f_back
    return False


def sweep(spec, client=None, out=None, workers=None, progress=None, case_timeout=None, log=None):
    """Runs the cases of `spec` not yet in `out` on a Dask cluster and merges
    every case into out/results.csv. Returns a dict: cases, ran, reused,
    duplicates (cases spelled twice, run once), failed (cases whose run
    failed), seconds, results (the CSV's path), rows (the merged rows, as
    dicts). `progress`: called with (done, to_run) as cases finish; `log`:
    called with a line of text when the sweep starts. `case_timeout`: the
    seconds a case may run (default: the spec's, else 3600)."""
    if _importing_a_worker():
        return None
    if isinstance(workers, numbers.Integral) and not isinstance(workers, bool):
        workers = int(workers)
    most = _MAX_WORKERS_PER_CPU * (os.cpu_count() or 1)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= most):
        raise InputError(f"sweep: workers must be an integer from 1 to {most} ({_MAX_WORKERS_PER_CPU} per CPU), "
                         f"got {workers!r}")
    spec = _plain_spec(spec)
    if case_timeout is None:
        case_timeout = spec.get("case_timeout")
    timeout = DEFAULT_CASE_TIMEOUT if case_timeout is None else _positive("case_timeout", case_timeout)
    if timeout > MAX_CASE_TIMEOUT:
        raise InputError(f"case_timeout: {timeout:g} s is beyond {MAX_CASE_TIMEOUT:g} s (a year)")
    all_cases, duplicates = _cases(spec)
    out, case_dir, lock = _prepare_directory(out, spec)
    try:
        return _run_sweep(spec, all_cases, duplicates, out, case_dir, client, workers, progress, timeout, log)
    finally:
        lock.close()


def _run_sweep(spec, all_cases, duplicates, out, case_dir, client, workers, progress, timeout, log):
    for case in all_cases:
        path = os.path.join(case_dir, case["case_id"] + ".json")
        if os.path.lexists(path) and not os.path.isfile(path):
            raise InputError(f"out: {path} is not a file (a case's result goes there): remove it")
    to_run = [c for c in all_cases if _finished_row(case_dir, c) is None]
    if log:
        log(f"{len(all_cases)} cases: {len(to_run)} to run, {len(all_cases) - len(to_run)} done before"
            + (f", {duplicates} duplicate(s) dropped" if duplicates else ""))
    start = time.perf_counter()
    results = os.path.join(out, "results.csv")
    stopped = None
    try:
        if to_run:
            distributed = _distributed()
            own = None
            if client is None:
                client, own = _local_cluster(workers or os.cpu_count() or 1)
            try:
                n_workers = max(1, len(client.scheduler_info().get("workers", {})) or (workers or 1))
                window = _IN_FLIGHT_PER_WORKER * n_workers
                pending = iter(to_run)
                by_key = {}

                def submit(case):
                    future = client.submit(_run_isolated, case, timeout, key=f"lieflow-case-{case['case_id']}",
                                           pure=False)
                    by_key[future.key] = case
                    return future

                running = distributed.as_completed([submit(c) for c in itertools.islice(pending, window)])
                for done, future in enumerate(running, start=1):
                    case = by_key.pop(future.key)
                    try:
                        row = future.result()
                    except Exception as e:  # the worker died with it (KilledWorker), or the cluster failed
                        row = _failed_row(case, f"crashed: the worker running the case died "
                                                f"({type(e).__name__}: {e})")
                    finally:
                        future.release()
                    _write_atomically(os.path.join(case_dir, case["case_id"] + ".json"), json.dumps(row))
                    following = next(pending, None)
                    if following is not None:
                        running.add(submit(following))
                    if progress:
                        progress(done, len(to_run))
            finally:
                if own is not None:
                    client.close()
                    own.close()
    except BaseException as e:
        stopped = f"{type(e).__name__}: {e}" if str(e) else type(e).__name__
        raise
    finally:
        rows = _merge(all_cases, case_dir, results, stopped)
    seconds = time.perf_counter() - start
    return {"cases": len(all_cases), "ran": len(to_run), "reused": len(all_cases) - len(to_run),
            "duplicates": duplicates, "failed": sum(1 for r in rows if r.get("failed")), "seconds": seconds,
            "results": results, "rows": rows}


class _Progress:
    """Progress lines on stderr: every case while they are few, else at most
    one a second (and the last)."""

    def __init__(self):
        self._last = 0.0

    def __call__(self, done, total):
        now = time.monotonic()
        if total <= 100 or done == total or now - self._last >= 1.0:
            self._last = now
            print(f"lieflow sweep: {done}/{total} cases done", file=sys.stderr, flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m lieflow.sweep",
                                     description="Run a lieflow sweep (SPEC.json) on a Dask cluster.")
    parser.add_argument("spec", help="the sweep's SPEC.json")
    parser.add_argument("--out", required=True, help="directory for the cases and results.csv")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786)")
    where.add_argument("--workers", type=int, help="local worker processes (default: the number of CPUs)")
    parser.add_argument("--case-timeout", type=float,
                        help=f"seconds a case may run (default: the spec's case_timeout, else {DEFAULT_CASE_TIMEOUT:g})")
    args = parser.parse_args(argv)
    client = None
    try:
        try:
            with open(args.spec) as f:
                spec = json.load(f)
        except (OSError, ValueError) as e:
            raise InputError(f"{args.spec}: {e}") from None
        if args.scheduler:
            client = _distributed().Client(args.scheduler)
        summary = sweep(spec, client=client, out=args.out, workers=args.workers, progress=_Progress(),
                        case_timeout=args.case_timeout,
                        log=lambda text: print(f"lieflow sweep: {text}", file=sys.stderr, flush=True))
    except InputError as e:
        print(f"lieflow sweep: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        # Dask's workers and nannies report their own shutdown: not the user's news.
        logging.getLogger("distributed").setLevel(logging.CRITICAL)
        print(f"lieflow sweep: interrupted; {os.path.join(args.out, 'results.csv')} holds the cases finished so far "
              "(the others are rows saying they were not run); run the sweep again to finish it", file=sys.stderr)
        return 130
    finally:
        if client is not None:
            client.close()
    print(f"{summary['cases']} cases: {summary['ran']} run, {summary['reused']} already done, "
          f"{summary['failed']} failed, {summary['seconds']:.2f} s; results in {summary['results']}")
    return 0


class _CallableModule(types.ModuleType):
    """lieflow.sweep is this module and a function: lieflow.sweep(spec, ...)."""

    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule

if __name__ == "__main__":
    # Run as `python3 -m lieflow.sweep`, this file is __main__, whose
    # functions Dask would pickle by value (with this module's state); the
    # imported lieflow.sweep's are sent by name, as workers import them.
    from lieflow.sweep import main as _imported_main

    sys.exit(_imported_main())
