"""Property test of the Python API, like the command line's
(tests/app/cli_property_test.py): every public function called with random
arguments of every type, shape and value ends in a result or in
lieflow.InputError / lieflow.ComputationError, never in a crash (which would
end this process) or another exception; results hold no NaN or inf.

Each case starts from a call that works and replaces one or two of its
arguments with random values, so that the call reaches the checks behind
the first. Deterministic for the seed."""
import math
import random

import numpy as np
import pytest

import lieflow

CASES = 1500
SEED = 28


def _values():
    """Arguments a hostile user passes: every type, odd shapes and values."""
    return [None, True, False, 0, 1, -1, 3, 10**400, -10**400, 2**63, 0.5, 1e-3, 1e30, 1e308, -1e308, 5e-324,
            float("nan"), float("inf"), -float("inf"), "", "abc", "rkmk4", "pendulum", "joint", "maximal", b"x",
            "x" * 300, "a\0b", [], [1], [1.0, 2.0, 3.0], [[1.0]], [float("nan")], (1, 2), {}, {"rho_inf": 0.5},
            {"rho_inf": float("nan")}, {"gyro": 0.01, "seed": 1}, {"bogus": 1}, np.float32(0.01), np.int64(3),
            np.bool_(True), np.array([1.0, 2.0, 3.0]), np.zeros((2, 3)), np.zeros((0, 3)), np.array([np.nan, 0, 0]),
            np.array([1e300, 0, 0]), np.array(["a", "b", "c"]), np.array([1 + 2j, 0, 0]), object(), 1j,
            lambda t, s: 1.0, lambda: 1.0, lambda t, s: float("nan"), lambda t, s: [1e308, 0, 0],
            lambda t, s: "text", print]


def _recordings():
    """Small recordings as dicts: a hinge's gyroscopes, accelerometers and
    orientations, and a sprung joint's angle."""
    run = lieflow.simulate("hinge-pair", t_end=1.0, every=10, noise={"gyro": 0.01, "seed": 3}, imu=True)
    hinge = {k: v for k, v in run.columns.items() if k == "t" or k.startswith(("upper.", "lower."))}
    spring = lieflow.simulate("spring-hinge", t_end=2.0, every=10).columns
    return hinge, {k: spring[k] for k in ("t", "hinge.phi")}


def _calls(recording, angles):
    """(function, keyword arguments of a call that works) for every public function."""
    q = lieflow.SO3.exp([0.1, 0.2, 0.3])
    g = lieflow.SE3.exp([0.1, 0.0, 0.2, 0.3, 0.1, 0.0])
    calls = [
        (lieflow.simulate, dict(scene="pendulum", integrator="rkmk4", dt=0.01, t_end=0.05, every=1, options=None,
                                noise=None, formulation=None, partial=False, max_steps=None)),
        (lieflow.simulate, dict(scene="spring-hinge", t_end=0.02, moments={"hinge": lambda t, s: 0.1}, partial=True)),
        (lieflow.simulate, dict(scene="hinge-pair", t_end=0.02, noise={"gyro": 0.01, "seed": 1}, imu=False)),
        (lieflow.study, dict(scene="pendulum", integrators=["rkmk4"], dt=[0.01, 0.005], t_end=0.02, min_time=1e-4,
                             options=None, formulation=None)),
        (lieflow.stability, dict(scenes=["stiff-spring"], integrators=["rkmk4"], options=None)),
        (lieflow.import_model, dict(model="/nonexistent/model.urdf", ignore=None, keyframe=None)),
        (lieflow.scenes, dict()),
        (lieflow.SO3.exp, dict(tangent=[0.1, 0.2, 0.3])),
        (lieflow.SO3.Jr, dict(tangent=[0.1, 0.2, 0.3])),
        (lieflow.SO3.JlInv, dict(tangent=[0.1, 0.2, 0.3])),
        (lieflow.SO3.from_quaternion, dict(quaternion=[1.0, 0.0, 0.0, 0.0])),
        (lieflow.SO3.from_matrix, dict(matrix=np.eye(3))),
        (lieflow.SO3.identity, dict(n=2)),
        (q.act, dict(points=[1.0, 0.0, 0.0])),
        (q.compose, dict(other=q)),
        (q.__mul__, dict(other=q)),
        (q.__getitem__, dict(index=0)),
        (lieflow.SE3.exp, dict(tangent=[0.1, 0.0, 0.2, 0.3, 0.1, 0.0])),
        (lieflow.SE3.Jr, dict(tangent=[0.1, 0.0, 0.2, 0.3, 0.1, 0.0])),
        (lieflow.SE3, dict(quaternion=[1.0, 0.0, 0.0, 0.0], translation=[1.0, 2.0, 3.0])),
        (lieflow.SE3.from_matrix, dict(matrix=np.eye(4))),
        (g.act, dict(points=[[1.0, 0.0, 0.0]])),
    ]
    if hasattr(lieflow, "calibrate_hinge"):
        calls += [
            (lieflow.calibrate_hinge, dict(recording=recording, main="upper", secondary="lower", use=None,
                                           loss=None, loss_scale=None, low_pass=None, partial=True)),
            (lieflow.calibrate_universal, dict(recording=recording, main="upper", secondary="lower", partial=True)),
            (lieflow.calibrate_spherical, dict(recording=recording, partial=True)),
            (lieflow.calibrate_spring, dict(recording=angles, scene="spring-hinge", partial=True,
                                            max_iterations=5)),
        ]
    return calls


def _finite(result):
    """Whether every number in a result is finite (arrays, dicts, lists, objects with columns)."""
    if isinstance(result, (lieflow.SO3, lieflow.SE3)):
        return _finite(result.quaternion())
    if isinstance(result, lieflow.SimulationResult):
        return _finite(result.columns)
    if isinstance(result, dict):
        return all(_finite(v) for v in result.values())
    if isinstance(result, (list, tuple)):
        return all(_finite(v) for v in result)
    if isinstance(result, np.ma.MaskedArray):
        return _finite(result.compressed())
    if isinstance(result, np.ndarray):
        return result.dtype.kind not in "fc" or bool(np.all(np.isfinite(result)))
    if isinstance(result, float):
        return math.isfinite(result)
    return True


def test_random_arguments_end_in_a_result_or_lieflow_errors():
    rng = random.Random(SEED)
    values = _values()
    calls = _calls(*_recordings())
    outcomes = {"result": 0, "InputError": 0, "ComputationError": 0}
    problems = []
    for case in range(CASES):
        function, base = calls[case % len(calls)]
        kwargs = dict(base)
        if kwargs:
            for key in rng.sample(sorted(kwargs), k=min(len(kwargs), rng.choice([1, 1, 2]))):
                kwargs[key] = rng.choice(values)
        try:
            result = function(**kwargs)
        except lieflow.InputError:
            outcomes["InputError"] += 1
            continue
        except lieflow.ComputationError:
            outcomes["ComputationError"] += 1
            continue
        except Exception as e:  # noqa: BLE001 - the property under test
            problems.append(f"{getattr(function, '__qualname__', function)}({kwargs!r:.300}): "
                            f"{type(e).__name__}: {e}"[:500])
            continue
        outcomes["result"] += 1
        if not _finite(result):
            problems.append(f"{getattr(function, '__qualname__', function)}({kwargs!r:.300}): a non-finite number in "
                            "the result")
    assert not problems, f"{len(problems)} of {CASES} cases:\n" + "\n".join(problems[:20])
    # The cases reached results as well as refusals, not only the first check.
    assert outcomes["result"] >= CASES // 20 and outcomes["InputError"] >= CASES // 4, outcomes


@pytest.mark.parametrize("call", [
    lambda: lieflow.SO3.from_quaternion(None),
    lambda: lieflow.SE3(None),
    lambda: lieflow.SO3.Jr(np.array([1e300, 0.0, 0.0])),
    lambda: lieflow.SE3.exp(np.array([0.0, 0.0, 0.0, 1e300, 0.0, 0.0])),
    lambda: lieflow.simulate("pendulum", t_end=10**400),
    lambda: lieflow.simulate("pendulum", every=10**400),
    lambda: lieflow.simulate("pendulum", noise=0.01),
    lambda: lieflow.simulate("spring-hinge", t_end=0.01, moments={"hinge": lambda: 1.0}),
    lambda: lieflow.simulate("spring-hinge", t_end=0.01, moments={"hinge": lambda t, s: 1e308}),
    lambda: lieflow.study("pendulum", dt="0.001"),
    lambda: lieflow.import_model("x.urdf", ignore=b"x"),
    lambda: lieflow.stability(scenes=5),
    lambda: lieflow.SO3.identity(10**12),
    lambda: lieflow.SO3.identity() * lieflow.SE3.identity(),
])
def test_the_issue_examples_are_input_errors(call):
    with pytest.raises(lieflow.InputError):
        call()


def test_scene_dicts_take_numpy_values_and_name_bad_numbers_by_field():
    import json
    import os
    with open(os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "pendulum.json")) as f:
        scene = json.load(f)
    scene["bodies"][0]["mass"] = np.float32(2.0)
    scene["bodies"][0]["inertia"] = np.array(scene["bodies"][0]["inertia"])
    scene["joints"][0]["initial_angle"] = np.float64(0.5)
    assert lieflow.simulate(scene, t_end=0.01).stats["steps"] == 10
    scene["bodies"][0]["mass"] = float("nan")
    with pytest.raises(lieflow.InputError, match=r"scene dict: bodies\[0\]\.mass: is not a finite number"):
        lieflow.simulate(scene, t_end=0.01)
    scene["bodies"][0]["mass"] = 10**400
    with pytest.raises(lieflow.InputError, match=r"scene dict: bodies\[0\]\.mass: .* is beyond"):
        lieflow.simulate(scene, t_end=0.01)
    loop = {}
    loop["self"] = loop
    with pytest.raises(lieflow.InputError, match="nested too deeply"):
        lieflow.simulate(loop)


def test_empty_options_are_no_options():
    # The README's sweep example gives "options": [{}]; a dict of none is the
    # scene's own integrator settings.
    assert lieflow.simulate("pendulum", t_end=0.01, options={}).stats["steps"] == 10
    assert lieflow.study("pendulum", integrators=["rkmk4"], dt=[0.01], t_end=0.02, options={},
                         min_time=1e-4)["rows"]["steps"][0] == 2
