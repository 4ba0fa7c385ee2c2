"""lieflow.simulate / study / stability / calibrate_*: the same numbers as the
command on the same input (CSV cells are written with 17 significant digits,
so they read back exactly), the same refusals with the same messages, and
long runs that release the GIL and stop on Ctrl-C."""
import csv
import json
import pathlib
import os
import signal
import threading
import time

import numpy as np
import pytest

import lieflow

SCENES = os.path.join(os.path.dirname(__file__), "..", "..", "scenes")
TIMING = {"wall_seconds", "ns_per_step", "seconds"}


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


@pytest.mark.parametrize("scene,args", [
    ("double-pendulum", dict(integrator="rkmk4", dt=0.01, t_end=2.0, every=3)),
    ("heavy-top", dict(integrator="genalpha", dt=0.002, t_end=1.0, options={"rho_inf": 0.8})),
    ("hinge-pair", dict(dt=0.01, t_end=1.0, noise={"gyro": 0.05, "angle": 0.01, "quat": 0.01, "seed": 5})),
])
def test_simulate_equals_the_command(tmp_path, run_command, scene, args):
    flags = [f"--integrator={args['integrator']}"] if "integrator" in args else []
    flags += ["--dt", args["dt"], "--t-end", args["t_end"]]
    if "every" in args:
        flags += ["--every", args["every"]]
    if "options" in args:
        flags += ["--options", ",".join(f"{k}={v}" for k, v in args["options"].items())]
    noise = args.get("noise", {})
    for key, flag in (("gyro", "--noise-gyro"), ("angle", "--noise-angle"), ("quat", "--noise-quat"),
                      ("seed", "--seed")):
        if key in noise:
            flags += [flag, noise[key]]
    status, out, err = run_command("simulate", scene, *flags, "--out", tmp_path / "run.csv", "--stats", "--quiet")
    assert status == 0, err
    header, rows = read_csv(tmp_path / "run.csv")
    command_stats = json.loads(out)

    result = lieflow.simulate(scene, **args)
    assert list(result.columns) == header
    for j, name in enumerate(header):
        np.testing.assert_array_equal(result.columns[name], [float(r[j]) for r in rows], err_msg=name)
    assert set(result.stats) == set(command_stats)
    for key in set(command_stats) - TIMING:
        assert result.stats[key] == command_stats[key], key
    assert not result.failed and result.failure == ""


def test_a_scene_dict_runs_like_its_file():
    with open(os.path.join(SCENES, "pendulum.json")) as f:
        scene = json.load(f)
    from_dict = lieflow.simulate(scene, dt=0.01, t_end=1.0)
    from_name = lieflow.simulate("pendulum", dt=0.01, t_end=1.0)
    for name, column in from_name.columns.items():
        np.testing.assert_array_equal(from_dict.columns[name], column)
    scene["bodies"][0]["mass"] = -1.0
    with pytest.raises(lieflow.InputError, match=r"scene dict: bodies\[0\]\.mass"):
        lieflow.simulate(scene)


@pytest.mark.parametrize("kwargs,flags", [
    (dict(integrator="no-such-integrator"), ["--integrator", "no-such-integrator"]),
    (dict(options={"rho_inf": 2.0}, integrator="genalpha"), ["--options", "rho_inf=2.0", "--integrator", "genalpha"]),
    (dict(options={"no_such_option": 1.0}), ["--options", "no_such_option=1.0"]),
    (dict(noise={"angle": 0.1}), ["--noise-angle", "0.1"]),
])
def test_bad_input_raises_input_error_with_the_commands_message(run_command, kwargs, flags):
    status, _, err = run_command("simulate", "heavy-top", *flags, "--stats", "--quiet")
    assert status == 2
    with pytest.raises(lieflow.InputError) as raised:
        lieflow.simulate("heavy-top", **kwargs)
    assert isinstance(raised.value, ValueError)
    assert err.strip() == "lieflow: " + str(raised.value)


def test_python_side_refusals():
    with pytest.raises(lieflow.InputError, match="--dt: expected a number"):
        lieflow.simulate("pendulum", dt="fast")
    with pytest.raises(lieflow.InputError, match="not a finite number"):
        lieflow.simulate("pendulum", t_end=float("inf"))
    with pytest.raises(lieflow.InputError, match="noise: unknown key"):
        lieflow.simulate("pendulum", noise={"gyroscope": 0.1})
    with pytest.raises(lieflow.InputError, match="expected a scene file"):
        lieflow.simulate(42)


def test_a_failed_run_raises_or_returns_its_partial_result(run_command):
    status, out, err = run_command("simulate", "stiff-spring", "--integrator", "rkmk4", "--dt", "1", "--t-end", "50",
                                   "--stats", "--quiet")
    assert status == 1
    with pytest.raises(lieflow.ComputationError) as raised:
        lieflow.simulate("stiff-spring", integrator="rkmk4", dt=1.0, t_end=50.0)
    assert isinstance(raised.value, RuntimeError)
    assert json.loads(out)["failure"] in str(raised.value)
    partial = lieflow.simulate("stiff-spring", integrator="rkmk4", dt=1.0, t_end=50.0, partial=True)
    assert partial.failed and partial.failure == json.loads(out)["failure"]
    assert partial.stats["failed"] is True
    assert all(np.all(np.isfinite(c)) for c in partial.columns.values())


def test_study_equals_the_command(tmp_path, run_command):
    args = ["--integrators", "rkmk4,lgvi,cg3", "--dt", "0.004,0.002", "--t-end", "0.5", "--min-time", "0.001"]
    status, _, err = run_command("study", "dzhanibekov", *args, "--out", tmp_path / "cmd", "--no-plots")
    assert status == 0, err
    header, rows = read_csv(tmp_path / "cmd" / "study.csv")
    result = lieflow.study("dzhanibekov", integrators=["rkmk4", "lgvi", "cg3"], dt=[0.004, 0.002], t_end=0.5,
                           min_time=0.001, out=tmp_path / "py")
    assert list(result["rows"]) == header
    for j, name in enumerate(header):
        if name in TIMING or name == "repeats":
            continue
        column = result["rows"][name]
        expected = [r[j] for r in rows]
        if isinstance(column, list):
            assert column == expected, name
        elif column.dtype == bool:
            assert list(column) == [c == "true" for c in expected], name
        else:
            filled = np.ma.getmaskarray(column) == np.array([c == "" for c in expected])
            assert filled.all(), name
            np.testing.assert_array_equal(np.ma.filled(column, 0.0), [float(c) if c else 0.0 for c in expected])
    assert result["reference"] == rows[0][header.index("reference")]
    assert os.path.exists(tmp_path / "py" / "drift.csv") and result["out"] == str(tmp_path / "py")
    drift_header, _ = read_csv(tmp_path / "cmd" / "drift.csv")
    assert list(result["drift"]) == drift_header


def test_stability_equals_the_command(tmp_path, run_command):
    status, _, err = run_command("stability", "stiff-spring", "--integrators", "rkmk4,lgvi,genalpha",
                                 "--out", tmp_path, "--no-plots")
    assert status == 0, err
    header, rows = read_csv(tmp_path / "stability.csv")
    result = lieflow.stability("stiff-spring", integrators=["rkmk4", "lgvi", "genalpha"])
    assert result["out"] is None and list(result["rows"]) == header
    h = result["rows"]["h_omega_max"]
    np.testing.assert_array_equal(h, [float(r[header.index("h_omega_max")]) for r in rows])
    assert result["rows"]["integrator"] == ["rkmk4", "lgvi", "genalpha"]


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_equals_the_command(tmp_path, run_command):
    status, _, err = run_command("simulate", "hinge-pair", "--every", "10", "--noise-gyro", "0.02", "--out",
                                 tmp_path / "rec.csv", "--quiet")
    assert status == 0, err
    status, out, err = run_command("calibrate", "hinge", tmp_path / "rec.csv")
    assert status == 0, err
    command = json.loads(out)
    recording = lieflow.simulate("hinge-pair", every=10, noise={"gyro": 0.02}).columns
    for source in (str(tmp_path / "rec.csv"), recording):
        fit = lieflow.calibrate_hinge(source)
        assert list(fit) == list(command)
        for key in set(command) - TIMING:
            assert fit[key] == command[key], key


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_hinge_gyro_bias_and_clock_offset(tmp_path, run_command):
    noise = {"gyro": 0.02, "bias_gyro": 0.05, "seed": 3}
    status, _, err = run_command("simulate", "hinge-pair", "--every", "10", "--noise-gyro", "0.02", "--bias-gyro",
                                 "0.05", "--seed", "3", "--out", tmp_path / "rec.csv", "--quiet")
    assert status == 0, err
    status, out, err = run_command("calibrate", "hinge", tmp_path / "rec.csv", "--fit-gyro-bias", "--fit-time-offset")
    assert status == 0, err
    command = json.loads(out)
    for key in ("gyro_bias_main", "gyro_bias_secondary", "gyro_bias_main_sigma", "gyro_bias_secondary_sigma",
                "time_offset", "time_offset_sigma"):
        assert key in command, key
    assert abs(command["time_offset"]) < 5 * command["time_offset_sigma"] + 1e-3  # no offset simulated
    recording = lieflow.simulate("hinge-pair", every=10, noise=noise).columns
    fit = lieflow.calibrate_hinge(recording, fit_gyro_bias=True, fit_time_offset=True)
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_hinge_from_several_recordings(tmp_path, run_command):
    paths = []
    for seed in (1, 2):
        path = tmp_path / f"rec{seed}.csv"
        status, _, err = run_command("simulate", "hinge-pair", "--every", "10", "--noise-gyro", "0.05", "--seed",
                                     str(seed), "--out", path, "--quiet")
        assert status == 0, err
        paths.append(path)
    status, out, err = run_command("calibrate", "hinge", *paths)
    assert status == 0, err
    command = json.loads(out)
    assert [r["file"] for r in command["recordings"]] == [str(p) for p in paths]
    assert [s["recording"] for s in command["segments"]] == [str(p) for p in paths]
    fit = lieflow.calibrate_hinge([str(p) for p in paths])
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key
    # Dicts of columns, named in the result and in errors by their place in the list.
    columns = [lieflow.simulate("hinge-pair", every=10, noise={"gyro": 0.05, "seed": seed}).columns for seed in (1, 2)]
    fit = lieflow.calibrate_hinge(columns)
    assert [r["file"] for r in fit["recordings"]] == ["recording[0] dict", "recording[1] dict"]
    assert fit["axis_main"] == command["axis_main"]
    # Each recording's biases and clock offset are its own, in its entry of "recordings".
    fit = lieflow.calibrate_hinge(columns, fit_gyro_bias=True, fit_time_offset=True)
    assert "gyro_bias_main" not in fit and "time_offset" not in fit
    for entry in fit["recordings"]:
        assert len(entry["gyro_bias_main"]) == 3 and entry["gyro_bias_secondary_sigma"] > 0, entry
        assert entry["time_offset_sigma"] > 0, entry
    with pytest.raises(lieflow.InputError, match="for calibrate_hinge"):
        lieflow.calibrate_universal(columns)


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_universal_gyro_bias(tmp_path, run_command):
    status, _, err = run_command("simulate", "universal-pair", "--every", "10", "--noise-gyro", "0.01", "--noise-quat",
                                 "0.003", "--bias-gyro", "0.05", "--seed", "4", "--out", tmp_path / "rec.csv", "--quiet")
    assert status == 0, err
    status, out, err = run_command("calibrate", "universal", tmp_path / "rec.csv", "--fit-gyro-bias",
                                   "--fit-time-offset")
    assert status == 0, err
    command = json.loads(out)
    for key in ("gyro_bias_main", "gyro_bias_secondary", "gyro_bias_main_sigma", "gyro_bias_secondary_sigma",
                "time_offset", "time_offset_sigma"):
        assert key in command, key
    assert max(abs(b) for b in command["gyro_bias_main"]) > 3 * command["gyro_bias_main_sigma"]  # a bias is found
    assert abs(command["time_offset"]) < 5 * command["time_offset_sigma"] + 1e-3  # no offset simulated
    fit = lieflow.calibrate_universal(str(tmp_path / "rec.csv"), fit_gyro_bias=True, fit_time_offset=True)
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key
    # Never filtered; low_pass="none" as --low-pass none.
    assert fit["low_pass_hz"] is None
    plain = lieflow.calibrate_universal(str(tmp_path / "rec.csv"), low_pass="none", partial=True)
    assert plain["low_pass_reason"] == "no filter: asked for (--low-pass none)"


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_hinge_low_pass_on_a_real_knee(run_command):
    knee = pathlib.Path(__file__).resolve().parents[1] / "data" / "qmt" / "right_knee_walking_90s_25s.csv"
    status, out, err = run_command("calibrate", "hinge", knee, "--low-pass", "4")
    assert status == 0, err
    command = json.loads(out)
    assert command["low_pass_hz"] == 4 and 0 < command["low_pass_noise_gain"] < 0.1
    assert command["converged"] and 0 < command["gyro_misfit"] and 0 < command["accelerometer_misfit"]
    fit = lieflow.calibrate_hinge(str(knee), low_pass=4)
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key
    status, _, err = run_command("calibrate", "hinge", knee, "--low-pass", "45")  # above 0.8 of Nyquist
    assert status == 2 and "--low-pass" in err, err
    status, _, err = run_command("calibrate", "universal", knee, "--low-pass", "4")
    assert status == 2, err


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_spherical_low_pass(tmp_path, run_command):
    status, _, err = run_command("simulate", "hinge-pair", "--imu", "--every", "10", "--noise-gyro", "0.01",
                                 "--noise-acc", "0.05", "--seed", "2", "--out", tmp_path / "rec.csv", "--quiet")
    assert status == 0, err
    status, out, err = run_command("calibrate", "spherical", tmp_path / "rec.csv", "--low-pass", "5")
    assert status == 0, err
    command = json.loads(out)
    assert command["low_pass_hz"] == 5 and command["anchor_main_sigma"] < 0.01
    fit = lieflow.calibrate_spherical(str(tmp_path / "rec.csv"), low_pass=5)
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_spring_of_a_mechanism_equals_the_command(tmp_path, run_command):
    scene = {"name": "two", "gravity": [0, 0, -9.81], "t_end": 2,
             "integrator": {"name": "rkmk4", "dt": 0.001},
             "bodies": [{"name": "upper", "mass": 1.0, "inertia": [0.0833, 0.0833, 0.001], "position": [0, 0, -0.5]},
                        {"name": "lower", "mass": 0.7, "inertia": [0.05, 0.04, 0.02], "position": [0, 0, -1.5]}],
             "joints": [{"name": "shoulder", "type": "revolute", "main": "ground", "secondary": "upper",
                         "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0],
                         "initial_angle": 0.4, "spring": {"stiffness": 8.0}, "damper": {"damping": 0.05}},
                        {"name": "elbow", "type": "revolute", "main": "upper", "secondary": "lower",
                         "anchor_main": [0, 0, -0.5], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0],
                         "initial_angle": -0.3, "spring": {"stiffness": 3.0}}]}
    path = tmp_path / "two.json"
    path.write_text(json.dumps(scene))
    status, _, err = run_command("simulate", path, "--formulation", "joint", "--every", "10", "--noise-gyro", "0.01",
                                 "--out", tmp_path / "rec.csv", "--quiet")
    assert status == 0, err
    status, out, err = run_command("calibrate", "spring", tmp_path / "rec.csv", "--scene", path, "--data",
                                   "gyroscopes")
    assert status == 0, err
    command = json.loads(out)
    fit = lieflow.calibrate_spring(str(tmp_path / "rec.csv"), scene=str(path), data="gyroscopes")
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key
    assert [c["joint"] for c in fit["coordinates"]] == ["shoulder", "elbow"]
    assert abs(fit["coordinates"][0]["stiffness"] - 8.0) < 5 * fit["coordinates"][0]["stiffness_sigma"] + 0.01
    # The recording has the angles too: the start is their inverse dynamics
    # unless --start scene asks for the scene's values.
    assert "inverse dynamics" in fit["start"]
    status, out, err = run_command("calibrate", "spring", tmp_path / "rec.csv", "--scene", path, "--data",
                                   "gyroscopes", "--start", "scene")
    assert status == 0, err
    command = json.loads(out)
    assert command["start"] == "the scene's springs and dashpots"
    fit = lieflow.calibrate_spring(str(tmp_path / "rec.csv"), scene=str(path), data="gyroscopes", start="scene")
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key
    status, _, err = run_command("calibrate", "spring", tmp_path / "rec.csv", "--scene", path, "--start", "guess")
    assert status == 2 and "--start" in err and "inverse-dynamics" in err, err


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_spherical_equals_the_command(tmp_path, run_command):
    scene = {"name": "ball", "gravity": [0, 0, -9.81], "t_end": 5, "integrator": {"name": "rkmk4", "dt": 0.001},
             "bodies": [{"name": "upper", "mass": 1.0, "inertia": [0.02, 0.05, 0.065], "rotation_only": True,
                         "angular_velocity": [2.0, -1.0, 1.5], "sensor": [0.05, -0.03, 0.08]},
                        {"name": "lower", "mass": 1.0, "inertia": [0.012, 0.03, 0.035], "rotation_only": True,
                         "angular_velocity": [-1.0, 2.5, 0.5], "sensor": [-0.04, 0.06, 0.02]}],
             "joints": [{"name": "ball", "type": "spherical", "main": "upper", "secondary": "lower",
                         "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0]}]}
    recording = lieflow.simulate(scene, every=10, imu=True, noise={"gyro": 0.01, "acc": 0.05, "seed": 2}).columns
    path = tmp_path / "ball.csv"
    with open(path, "w") as f:
        names = list(recording)
        f.write(",".join(names) + "\n")
        for row in zip(*(recording[n] for n in names)):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    status, out, err = run_command("calibrate", "spherical", path)
    assert status == 0, err
    command = json.loads(out)
    for source in (str(path), recording):
        fit = lieflow.calibrate_spherical(source)
        assert list(fit) == list(command)
        for key in set(command) - TIMING:
            assert fit[key] == command[key], key
    truth = np.array([-0.05, 0.03, -0.08])
    assert np.linalg.norm(np.array(command["anchor_main"]) - truth) < 4 * command["anchor_main_sigma"]


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_spring_equals_the_command(tmp_path, run_command):
    status, _, err = run_command("simulate", "spring-hinge", "--every", "10", "--noise-angle", "0.01", "--out",
                                 tmp_path / "decay.csv", "--quiet")
    assert status == 0, err
    status, out, err = run_command("calibrate", "spring", tmp_path / "decay.csv", "--scene", "spring-hinge",
                                   "--fit-rest-angle")
    assert status == 0, err
    command = json.loads(out)
    fit = lieflow.calibrate_spring(str(tmp_path / "decay.csv"), scene="spring-hinge", fit_rest_angle=True)
    assert list(fit) == list(command)
    for key in set(command) - TIMING:
        assert fit[key] == command[key], key


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_calibrate_refusals_and_failures(tmp_path):
    with pytest.raises(lieflow.InputError, match="^recording dict: the recording has 0 bodies"):
        lieflow.calibrate_hinge({"t": [0.0, 0.1]})
    with pytest.raises(lieflow.InputError, match="--loss"):
        lieflow.calibrate_hinge({"t": [0.0, 0.1], "a.wx": [0, 0], "a.wy": [0, 0], "a.wz": [0, 0],
                                 "b.wx": [0, 0], "b.wy": [0, 0], "b.wz": [0, 0]}, loss="quadratic")
    # A joint that never moves cannot be identified: exit 1 on the command line.
    still = lieflow.simulate("hinge-pair", dt=0.01, t_end=1.0).columns
    for key in still:
        if key.endswith((".wx", ".wy", ".wz")):
            still[key] = np.zeros_like(still[key])
    with pytest.raises(lieflow.ComputationError):
        lieflow.calibrate_hinge({k: v for k, v in still.items() if "." not in k or k.split(".")[1][0] == "w"})
    answer = lieflow.calibrate_hinge({k: v for k, v in still.items() if "." not in k or k.split(".")[1][0] == "w"},
                                     partial=True)
    assert answer["failed"] is True and answer["failure"]


def test_long_runs_release_the_gil_and_stop_on_ctrl_c():
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.01)

    threading.Thread(target=count, daemon=True).start()
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        # 1e8 steps of the heavy top: minutes, unless interrupted.
        lieflow.simulate("heavy-top", integrator="rkmk4", dt=1e-4, t_end=1e4, every=1_000_000)
    elapsed = time.perf_counter() - start
    stop.set()
    assert elapsed < 3.0, f"the run stopped {elapsed:.2f} s after it started (SIGINT at 0.5 s)"
    # The other thread ran while the simulation held no GIL.
    assert sum(1 for t in ticks if start + 0.1 < t < start + 0.5) >= 10


def interrupt_after(seconds, call):
    """Sends SIGINT to this process after `seconds`; returns how long after
    the signal `call` stopped with KeyboardInterrupt."""
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
    finally:
        timer.cancel()
    return time.perf_counter() - start - seconds


def test_imu_columns_equal_the_command(run_command, tmp_path):
    args = ["--integrator", "rkmk4", "--dt", "0.001", "--t-end", "0.2", "--imu", "--noise-acc", "0.05",
            "--bias-gyro", "0.01", "--seed", "4"]
    status, _, err = run_command("simulate", "double-pendulum", *args, "--out", tmp_path / "imu.csv")
    assert status == 0, err
    header, rows = read_csv(tmp_path / "imu.csv")
    result = lieflow.simulate("double-pendulum", integrator="rkmk4", dt=0.001, t_end=0.2, imu=True,
                              noise={"acc": 0.05, "bias_gyro": 0.01, "seed": 4})
    assert list(result.columns) == header
    assert header.index("upper.ax") == header.index("upper.vz") + 1
    for j, name in enumerate(header):
        np.testing.assert_array_equal(result.columns[name], [float(r[j]) for r in rows], err_msg=name)
    with pytest.raises(lieflow.InputError, match="--imu"):
        lieflow.simulate("double-pendulum", integrator="rkmk4", dt=0.001, t_end=0.01, noise={"acc": 0.1})


def test_study_in_joint_coordinates(tmp_path):
    # The same study in both formulations: the same reference (maximal
    # coordinates), errors of the same size at the same step (both fourth
    # order), and genalpha offered in joint coordinates.
    runs = {f: lieflow.study("double-pendulum", integrators=["rkmk4", "genalpha"], dt=[0.004, 0.002], t_end=0.5,
                             min_time=0.001, formulation=f) for f in ("maximal", "joint")}
    assert runs["joint"]["reference"] == runs["maximal"]["reference"]
    for f, result in runs.items():
        rows = result["rows"]
        assert list(rows["integrator"]) == ["rkmk4", "rkmk4", "genalpha", "genalpha"], f
        assert not any(rows["failed"]), f
    joint, maximal = runs["joint"]["rows"], runs["maximal"]["rows"]
    ratio = np.asarray(joint["orientation_error"][:2]) / np.asarray(maximal["orientation_error"][:2])
    assert np.all((ratio > 0.2) & (ratio < 5.0)), ratio
    # lgvi runs in joint coordinates on trees of hinges and on a
    # rotation-only root turning on SO(3), and is refused naming why where
    # a joint's angle is prescribed.
    for scene in ("double-pendulum", "hinge-pair"):
        lgvi = lieflow.study(scene, integrators=["lgvi"], dt=[0.004], t_end=0.1, min_time=0.001,
                             formulation="joint")
        assert not any(lgvi["rows"]["failed"]), scene
    with pytest.raises(lieflow.InputError, match="prescribed joint angle"):
        lieflow.study("driven-arm", integrators=["lgvi"], dt=[0.004], t_end=0.1, formulation="joint")


def test_loops_in_joint_coordinates():
    # The Cardan shaft's cross closes a loop: in joint coordinates it is held
    # by multipliers on the tree of the two bearings, with the same columns
    # and the same motion as in maximal coordinates.
    runs = {f: lieflow.simulate("cardan-shaft", integrator="rkmk4", dt=1e-3, t_end=0.5, formulation=f)
            for f in ("maximal", "joint")}
    assert runs["joint"].stats["formulation"] == "joint"
    for column in ("output-bearing.phi", "output-bearing.phidot", "input-bearing.moment", "cross.phi2"):
        np.testing.assert_allclose(runs["joint"].columns[column], runs["maximal"].columns[column], atol=1e-10,
                                   err_msg=column)
    assert np.max(runs["joint"].columns["constraint_error"]) <= 1e-12
    with pytest.raises(lieflow.InputError, match="prescribed"):
        lieflow.simulate("cardan-shaft", integrator="genalpha", dt=1e-3, t_end=0.01, formulation="joint")


def test_a_long_study_stops_on_ctrl_c(tmp_path):
    # The reference alone (projected rkmk4 at h = 3.1e-6 over 300 s, 1e8 steps) would take minutes.
    late = interrupt_after(0.5, lambda: lieflow.study("double-pendulum", integrators=["rkmk4"], dt=[1e-4],
                                                      t_end=300.0, out=tmp_path))
    assert late < 2.0, f"the study stopped {late:.2f} s after SIGINT"


@pytest.mark.skipif(not lieflow._lieflow.have_calibration, reason="built without Ceres")
def test_a_long_fit_stops_on_ctrl_c(tmp_path, run_command):
    status, _, err = run_command("simulate", "spring-hinge", "--t-end", "300", "--noise-angle", "0.01", "--out",
                                 tmp_path / "long.csv", "--quiet")
    assert status == 0, err
    late = interrupt_after(1.0, lambda: lieflow.calibrate_spring(str(tmp_path / "long.csv"), scene="spring-hinge",
                                                                 fit_rest_angle=True, substeps=4))
    # The fit looks for SIGINT between solver iterations; one iteration over
    # these 30000 samples took 2.3 s on a 2-core machine running the test
    # suite two at a time, so the bound is a few iterations, not a speed.
    assert late < 5.0, f"the fit stopped {late:.2f} s after SIGINT"
