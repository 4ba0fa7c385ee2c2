"""Model files from Python: lieflow.import_model is `lieflow import`, and
simulate takes a model file (with ignore=) as the command does."""
import json
import os
import warnings

import numpy as np
import pytest

import lieflow
from lieflow import _lieflow

MODELS = os.path.join(os.path.dirname(__file__), "..", "data", "models")
needs_urdf = pytest.mark.skipif(not _lieflow.reads_urdf, reason="this build has no URDF reader (liburdfdom-dev)")



@needs_urdf
def test_import_model_equals_the_command(run_command, tmp_path):
    model = os.path.join(MODELS, "arm6.urdf")
    status, out, err = run_command("import", model)
    assert status == 0, err
    assert lieflow.import_model(model) == json.loads(out)
    status, _, err = run_command("import", model, "--out", tmp_path / "arm6.json")
    assert status == 0, err
    with open(tmp_path / "arm6.json") as f:
        assert json.load(f) == json.loads(out)


@needs_urdf
def test_a_model_file_simulates_like_its_imported_scene(tmp_path):
    model = os.path.join(MODELS, "arm6.urdf")
    direct = lieflow.simulate(model, integrator="rkmk4", dt=0.01, t_end=0.2)
    scene = lieflow.import_model(model)
    via_dict = lieflow.simulate(scene, integrator="rkmk4", dt=0.01, t_end=0.2)
    assert list(direct.columns) == list(via_dict.columns)
    for name in direct.columns:
        np.testing.assert_array_equal(direct.columns[name], via_dict.columns[name], err_msg=name)


@needs_urdf
def test_limits_and_contacts_are_refused_then_ignored_with_a_warning():
    path = os.path.join(MODELS, "limited.urdf")  # a joint limit and a collision shape
    with pytest.raises(lieflow.InputError, match=r"limit of joint 'hinge' \(line 6\).*--ignore contacts,limits"):
        lieflow.import_model(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = lieflow.import_model(path, ignore=["contacts", "limits"])
    assert any("limits: limit of joint 'hinge'" in str(w.message) for w in caught)
    assert scene["joints"][0]["type"] == "revolute"
    result = lieflow.simulate(path, ignore=["contacts", "limits"], integrator="rkmk4", dt=0.01, t_end=0.1)
    assert "hinge.phi" in result.columns
    with pytest.raises(lieflow.InputError, match="unknown feature 'gravity'"):
        lieflow.import_model(path, ignore=["gravity"])


@needs_urdf
def test_spin_sets_a_floating_model_turning_as_the_command_does(run_command):
    model = os.path.join(MODELS, "arm6.urdf")
    status, out, err = run_command("import", model, "--floating-base", "--spin", "0.5,-1,2")
    assert status == 0, err
    scene = lieflow.import_model(model, floating_base=True, spin=np.array([0.5, -1.0, 2.0]))
    assert scene == json.loads(out)
    result = lieflow.simulate(model, floating_base=True, spin=(0.5, -1, 2), integrator="rkmk4", dt=0.01, t_end=0.02)
    assert abs(result.columns["j1.phidot"][0]) < 1e-12  # a rigid turn: the joints do not move
    assert result.columns["base.wz"][0] != 0.0
    for bad in [(1, 2), "fast", (1, 2, float("nan"))]:
        with pytest.raises(lieflow.InputError, match="spin"):
            lieflow.import_model(model, floating_base=True, spin=bad)
    with pytest.raises(lieflow.InputError, match="--spin.*--floating-base"):
        lieflow.import_model(model, spin=(0, 0, 1))


needs_mjcf = pytest.mark.skipif(not _lieflow.reads_mjcf, reason="this build has no MJCF reader (libmujoco-dev)")


@needs_mjcf
def test_a_keyframe_starts_the_model_and_mujoco_runs_beside_lieflow(tmp_path):
    path = os.path.join(MODELS, "spinning.xml")
    spin = lieflow.import_model(path, keyframe="spin")
    assert lieflow.import_model(path, keyframe=1) == spin
    assert all(np.linalg.norm(b["angular_velocity"]) > 1.0 for b in spin["bodies"])
    with pytest.raises(lieflow.InputError, match=r"no keyframe 'jump' \(it has rest, spin\)"):
        lieflow.import_model(path, keyframe="jump")
    result = lieflow.study(path, keyframe="spin", with_mujoco=True, integrators=["lgvi"], dt=[0.004],
                           t_end=0.1, min_time=0.001)
    rows = result["rows"]
    assert list(rows["integrator"]) == ["lgvi", "mujoco-euler", "mujoco-rk4", "mujoco-implicit"]
    assert not rows["failed"].any()
    assert (rows["orientation_error"] > 0).all()
    assert "MuJoCo RK4 at h = " in result["reference"]
    assert "L_com_drift" in rows and "energy_balance_drift" in rows
