"""lieflow.sweep on a local Dask cluster of 2 worker processes: the same
results as running the cases one by one, no case lost when a worker is
killed mid-sweep, and a resumed sweep runs only what is missing."""
import csv
import json
import os
import signal
import subprocess
import sys
import time

import pytest

import lieflow
from lieflow import sweep as sweep_module

distributed = pytest.importorskip("distributed")

SPEC = {"scenes": ["pendulum", "heavy-top"], "integrators": ["rkmk4", "lgvi"], "dt": [0.002, 0.001],
        "t_end": 0.5}
TIMING = {"wall_seconds", "ns_per_step"}


def without_timing(row):
    return {k: v for k, v in row.items() if k not in TIMING}


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_results_equal_running_the_cases_one_by_one(tmp_path, client):
    summary = lieflow.sweep(SPEC, client=client, out=tmp_path)
    assert summary["cases"] == 8 and summary["ran"] == 8 and summary["failed"] == 0
    one_by_one = [sweep_module.run_case(case) for case in sweep_module.cases(SPEC)]
    assert [without_timing(r) for r in summary["rows"]] == [without_timing(r) for r in one_by_one]
    with open(tmp_path / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 8
    assert list(rows[0])[:7] == ["case_id", "scene", "integrator", "dt", "t_end", "options", "seed"]
    assert [(r["scene"], r["integrator"], float(r["dt"])) for r in rows] == [
        (s, i, d) for s in SPEC["scenes"] for i in SPEC["integrators"] for d in SPEC["dt"]]
    assert all(r["failed"] == "false" and int(r["steps"]) > 0 for r in rows)


def test_a_resumed_sweep_runs_only_the_missing_cases(tmp_path, client):
    first = lieflow.sweep(SPEC, client=client, out=tmp_path)
    case_files = sorted((tmp_path / "cases").glob("*.json"))
    assert len(case_files) == 8
    kept = {p.name: p.read_text() for p in case_files[3:]}
    for p in case_files[:3]:
        p.unlink()
    (tmp_path / "results.csv").unlink()
    second = lieflow.sweep(SPEC, client=client, out=tmp_path)
    assert second["ran"] == 3 and second["reused"] == 5
    for name, text in kept.items():  # finished cases are not redone
        assert (tmp_path / "cases" / name).read_text() == text
    assert [without_timing(r) for r in second["rows"]] == [without_timing(r) for r in first["rows"]]


def test_a_worker_killed_mid_sweep_loses_no_case(tmp_path):
    # 12 cases of 0.05-0.2 s; one worker process is killed (SIGKILL) once the
    # first case is in, in the middle of its next case, which Dask reschedules.
    spec = {"scenes": ["chain-5"], "integrators": ["rkmk4", "lgvi", "cf4"], "dt": [0.001, 0.0008, 0.0006, 0.0005],
            "t_end": 5.0}
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    killed = []
    with distributed.Client(cluster) as c:
        def kill_one(done, total):
            if not killed:
                pids = c.run(os.getpid)
                pid = sorted(pids.values())[0]
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)

        summary = lieflow.sweep(spec, client=c, out=tmp_path, progress=kill_one)
    cluster.close()
    assert killed
    assert summary["cases"] == 12 and summary["ran"] == 12 and summary["failed"] == 0
    assert len(list((tmp_path / "cases").glob("*.json"))) == 12


def test_the_command_line(tmp_path):
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps({"scenes": ["pendulum"], "dt": [0.01, 0.005], "t_end": 0.2}))
    env = dict(os.environ)
    done = subprocess.run([sys.executable, "-m", "lieflow.sweep", str(spec), "--out", str(tmp_path / "out"),
                           "--workers", "2"], capture_output=True, text=True, env=env, timeout=200)
    assert done.returncode == 0, done.stderr
    assert "2 cases: 2 run" in done.stdout
    with open(tmp_path / "out" / "results.csv") as f:
        assert len(f.readlines()) == 3
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"scenes": ["pendulum"], "seeds": [1, 2]}))
    done = subprocess.run([sys.executable, "-m", "lieflow.sweep", str(bad), "--out", str(tmp_path / "bad")],
                          capture_output=True, text=True, env=env, timeout=200)
    assert done.returncode == 2 and "'seeds' seed the recording noise" in done.stderr


def test_bad_specs_and_bad_cases():
    with pytest.raises(lieflow.InputError, match="unknown key"):
        sweep_module.cases({"scenes": ["pendulum"], "integrator": ["rkmk4"]})
    with pytest.raises(lieflow.InputError, match="'scenes' is required"):
        sweep_module.cases({"dt": [0.1]})
    with pytest.raises(lieflow.InputError, match="non-empty list"):
        sweep_module.cases({"scenes": []})
    # A bad case is a failed row, not the end of the sweep.
    case = sweep_module.cases({"scenes": ["pendulum"], "integrators": ["no-such"], "t_end": 0.1})[0]
    row = sweep_module.run_case(case)
    assert row["failed"] is True and row["failure"].startswith("bad input: ")


def _parent(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return int(f.read().rsplit(")", 1)[1].split()[1])
    except (OSError, ValueError, IndexError):
        return 0


def _case_processes():
    """The pids of the processes running this test's sweep cases
    (lieflow._sweep_child under this process: not another test's)."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                if b"lieflow._sweep_child" not in f.read():
                    continue
        except OSError:
            continue
        ancestor = int(entry)
        while ancestor > 1 and ancestor != os.getpid():
            ancestor = _parent(ancestor)
        if ancestor == os.getpid():
            pids.append(int(entry))
    return pids


def test_a_crashed_or_hung_case_is_a_failed_row_and_the_others_complete(tmp_path, client):
    # The long case (chain-300 for 20 s, far more than the short one's work
    # whatever the load: with chain-30's 2 s a CI run once finished it before
    # the short case's process had started, and the crash hit the short one)
    # is killed with SIGSEGV, as a fault in native code would end it, once
    # the short one is in; then, in a second sweep, it runs past its time limit.
    spec = {"scenes": ["pendulum", "chain-300"], "integrators": ["rkmk4"], "dt": [0.0005], "t_end": 20.0}
    killed = []

    def crash_the_running_case(done, total):
        # On a loaded machine the long case's process may still be starting
        # when the short one is in: wait for it (up to 30 s).
        deadline = time.monotonic() + 30.0
        while not killed and time.monotonic() < deadline:
            for pid in _case_processes():
                os.kill(pid, signal.SIGSEGV)
                killed.append(pid)
            if not killed:
                time.sleep(0.05)

    summary = lieflow.sweep(spec, client=client, out=tmp_path / "crash", progress=crash_the_running_case)
    assert killed
    rows = {r["scene"]: r for r in summary["rows"]}
    assert rows["pendulum"]["failed"] is False, rows["pendulum"]["failure"]
    assert rows["pendulum"]["steps"] == 40000
    assert rows["chain-300"]["failed"] is True
    assert rows["chain-300"]["failure"].startswith("crashed: the process running the case ended with SIGSEGV")
    with open(tmp_path / "crash" / "results.csv", newline="") as f:
        assert len(list(csv.DictReader(f))) == 2
    # The time limit: the long case (chain-300, about 9 s of work) is a
    # failed row, the sweep ends; the short one, which starts a Python
    # process too (a second on a loaded machine), is well inside it.
    hung = lieflow.sweep(spec, client=client, out=tmp_path / "hung",
                         case_timeout=3)
    rows = {r["scene"]: r for r in hung["rows"]}
    assert rows["chain-300"]["failure"].startswith("timed out: the case ran longer than its limit of 3 s")
    assert rows["pendulum"]["failed"] is False, rows["pendulum"]["failure"]


def test_output_directories_and_case_files_that_are_not_the_sweeps(tmp_path, client):
    spec = {"scenes": ["pendulum"], "dt": [0.01, 0.005], "t_end": 0.05}
    not_a_directory = tmp_path / "file"
    not_a_directory.write_text("x")
    with pytest.raises(lieflow.InputError, match="cannot hold the sweep"):
        lieflow.sweep(spec, client=client, out=not_a_directory)
    first = lieflow.sweep(spec, client=client, out=tmp_path / "out")
    case_files = sorted((tmp_path / "out" / "cases").glob("*.json"))
    assert len(case_files) == 2
    # An empty file and another case's row: neither is this case's result.
    case_files[0].write_text("")
    other = json.loads(case_files[1].read_text())
    other["case_id"] = "somebody-else"
    case_files[1].write_text(json.dumps(other))
    again = lieflow.sweep(spec, client=client, out=tmp_path / "out")
    assert again["ran"] == 2 and again["failed"] == 0
    assert [r["case_id"] for r in again["rows"]] == [r["case_id"] for r in first["rows"]]
    assert oct((tmp_path / "out" / "results.csv").stat().st_mode & 0o777) != oct(0o600)
    # Another spec's sweep in the same directory is refused, not replaced.
    with pytest.raises(lieflow.InputError, match="holds the sweep of another spec"):
        lieflow.sweep({"scenes": ["heavy-top"], "t_end": 0.05}, client=client, out=tmp_path / "out")


def test_cases_are_what_they_run_edited_scenes_again_duplicates_once(tmp_path, client):
    scene = tmp_path / "scene.json"
    text = open(os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "pendulum.json")).read()
    scene.write_text(text)
    spec = {"scenes": [str(scene)], "dt": [0.01, 0.01], "options": [{}, None], "t_end": 0.05}
    first = lieflow.sweep(spec, client=client, out=tmp_path / "out")
    assert first["cases"] == 1 and first["duplicates"] == 3
    scene.write_text(text.replace('"gravity": [0, 0, -9.81]', '"gravity": [0, 0, -3.7]'))
    second = lieflow.sweep(spec, client=client, out=tmp_path / "out")
    assert second["ran"] == 1 and second["reused"] == 0  # the edited file is a new case
    assert second["rows"][0]["energy_drift"] != first["rows"][0]["energy_drift"]


def test_the_readme_example_with_empty_options_runs_every_case(tmp_path):
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps({"scenes": ["pendulum", "double-pendulum"], "integrators": ["rkmk4", "lgvi"],
                                "dt": [0.004, 0.002], "options": [{}], "t_end": 0.1}))
    done = subprocess.run([sys.executable, "-m", "lieflow.sweep", str(spec), "--out", str(tmp_path / "out"),
                           "--workers", "2"], capture_output=True, text=True, timeout=200)
    assert done.returncode == 0, done.stderr
    assert "8 cases: 8 run, 0 already done, 0 failed" in done.stdout
    assert "lieflow sweep: 8 cases: 8 to run" in done.stderr  # said at once, before any case ends
    bad = subprocess.run([sys.executable, "-m", "lieflow.sweep", str(spec), "--out", str(spec)],
                         capture_output=True, text=True, timeout=200)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and "cannot hold the sweep" in bad.stderr


def test_a_directory_in_use_and_limits_of_the_case_time(tmp_path, client):
    import fcntl
    spec = {"scenes": ["pendulum"], "dt": [0.01], "t_end": 0.05}
    out = tmp_path / "out"
    out.mkdir()
    # Another sweep (here: this process, as another one would) holds DIR/.lock.
    with open(out / ".lock", "a") as held:
        fcntl.flock(held.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(lieflow.InputError, match="is in use by another sweep"):
            lieflow.sweep(spec, client=client, out=out)
    # Released, the sweep runs, and leaves the lock free for the next one.
    assert lieflow.sweep(spec, client=client, out=out)["ran"] == 1
    with open(out / ".lock", "a") as again:
        fcntl.flock(again.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    for bad in (1e300, float("inf"), float("nan"), 0, -1, True, "10"):
        with pytest.raises(lieflow.InputError, match="case_timeout"):
            lieflow.sweep(spec, client=client, out=out, case_timeout=bad)
    with pytest.raises(lieflow.InputError, match="case_timeout"):
        lieflow.sweep(dict(spec, case_timeout=1e12), client=client, out=out)
    # A case file that is a directory is named, not a traceback.
    case_file = next((out / "cases").glob("*.json"))
    case_file.unlink()
    case_file.mkdir()
    with pytest.raises(lieflow.InputError, match=case_file.name):
        lieflow.sweep(spec, client=client, out=out)
