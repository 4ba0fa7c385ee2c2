"""Loads written in Python: a body torque and a joint moment as callables of
(t, state), against a closed form and against the scene's own force
elements, and what is refused."""
import json
import math
import os

import numpy as np
import pytest

import lieflow

SCENES = os.path.join(os.path.dirname(__file__), "..", "..", "scenes")


def scene(name):
    with open(os.path.join(SCENES, name + ".json")) as f:
        return json.load(f)


def test_a_body_torque_against_the_closed_form():
    # A body of isotropic inertia I with the torque -c omega: omega(t) =
    # omega0 exp(-c t / I) keeps its direction, so the body turns about that
    # fixed axis by |omega0| I/c (1 - exp(-c t/I)).
    I, c, w0 = 2.0, 0.7, np.array([1.0, -2.0, 0.5])
    body = {"name": "ball", "mass": 1.0, "inertia": [I, I, I], "rotation_only": True, "angular_velocity": list(w0)}
    spec = {"name": "damped-ball", "gravity": [0, 0, 0], "bodies": [body], "t_end": 3.0}
    calls = []

    def torque(t, state):
        calls.append(t)
        assert state["q"].shape == (4,) and state["p"].shape == (3,) and state["v"].shape == (3,)
        return -c * state["omega"]

    run = lieflow.simulate(spec, integrator="rkmk4", dt=0.01, torques={"ball": torque})
    T = run.columns["t"][-1]
    w = np.array([run.columns[f"ball.w{a}"][-1] for a in "xyz"])
    np.testing.assert_allclose(w, w0 * math.exp(-c * T / I), rtol=1e-9)
    angle = np.linalg.norm(w0) * I / c * (1 - math.exp(-c * T / I))
    expected = lieflow.SO3.exp(w0 / np.linalg.norm(w0) * angle).quaternion()
    q = np.array([run.columns[f"ball.q{a}"][-1] for a in "wxyz"])
    np.testing.assert_allclose(q * np.sign(q[0] * expected[0]), expected, atol=1e-9)
    assert len(calls) >= 4 * 300  # four stages per step, 300 steps
    assert run.stats["momentum_drift"] is None  # a torque on a body: momentum is not conserved


def test_a_joint_moment_equals_the_scenes_own_moment_bit_for_bit():
    spec = scene("pendulum")
    spec["joints"][0]["moment"] = {"type": "constant", "value": 0.3}
    own = lieflow.simulate(spec, dt=0.002, t_end=2.0)
    del spec["joints"][0]["moment"]
    states = []

    def moment(t, state):
        states.append(state)
        return 0.3

    user = lieflow.simulate(spec, dt=0.002, t_end=2.0, moments={"hinge": lambda t, s: moment(t, s)})
    for name, column in own.columns.items():
        np.testing.assert_array_equal(user.columns[name], column, err_msg=name)
    assert states[0]["coordinate"] == 1 and abs(states[0]["phi"] - 1.0) < 1e-12


def test_a_joint_moment_written_as_a_spring_and_dashpot():
    spec = scene("spring-hinge")
    own = lieflow.simulate(spec, dt=0.002, t_end=3.0)
    joint = spec["joints"][0]
    k, rest, c = joint["spring"]["stiffness"], joint["spring"]["rest_angle"], joint["damper"]["damping"]
    del joint["spring"], joint["damper"]
    user = lieflow.simulate(spec, dt=0.002, t_end=3.0,
                            moments={"hinge": lambda t, s: -k * (s["phi"] - rest) - c * s["phidot"]})
    np.testing.assert_allclose(user.columns["hinge.phi"], own.columns["hinge.phi"], atol=1e-12)
    np.testing.assert_allclose(user.columns["hinge.moment"], own.columns["hinge.moment"], atol=1e-10)


def test_loads_in_joint_coordinates_follow_the_maximal_formulation():
    # A moment from Python on the driven arm's elbow and a torque on its fore
    # arm, in both formulations: the same motion (two different algorithms).
    spec = scene("driven-arm")
    loads = dict(moments={"elbow": lambda t, s: 0.2 * math.sin(3 * t) - 0.05 * s["phidot"]},
                 torques={"fore": lambda t, s: [0.0, 0.0, 0.1 * math.cos(2 * t)]})
    runs = {f: lieflow.simulate(spec, integrator="rkmk4", dt=1e-3, t_end=1.0, formulation=f, **loads)
            for f in ("maximal", "joint")}
    assert runs["joint"].stats["formulation"] == "joint"
    for column in ("elbow.phi", "shoulder.phi", "fore.x", "fore.wz", "elbow.moment"):
        np.testing.assert_allclose(runs["joint"].columns[column], runs["maximal"].columns[column], atol=1e-8,
                                   err_msg=column)


def test_refusals():
    with pytest.raises(lieflow.InputError, match="'lgvi' treats forces implicitly"):
        lieflow.simulate("pendulum", integrator="lgvi", moments={"hinge": lambda t, s: 0.0})
    with pytest.raises(lieflow.InputError, match="torques: the scene has no body 'arm'"):
        lieflow.simulate("pendulum", torques={"arm": lambda t, s: [0, 0, 0]})
    with pytest.raises(lieflow.InputError, match=r"torques\['rod'\]: the callable returned"):
        lieflow.simulate("pendulum", t_end=0.1, torques={"rod": lambda t, s: [0.0, 1.0]})
    with pytest.raises(lieflow.InputError, match=r"moments\['hinge'\]: the callable returned nan"):
        lieflow.simulate("pendulum", t_end=0.1, moments={"hinge": lambda t, s: float("nan")})
    with pytest.raises(lieflow.InputError, match="expected a name and a callable"):
        lieflow.simulate("pendulum", moments={"hinge": 3.0})

    def broken(t, state):
        raise ZeroDivisionError("user code failed")

    with pytest.raises(ZeroDivisionError, match="user code failed"):
        lieflow.simulate("pendulum", t_end=0.1, moments={"hinge": broken})
