"""lieflow.view: a SimulationResult or a CSV file as a replay page, the same
page the command writes; bad input raises InputError."""
import json
import os
import re

import pytest

import lieflow

THREE = os.environ.get("LIEFLOW_THREE_DIR", "/usr/share/javascript/three")
needs_three = pytest.mark.skipif(not os.path.exists(os.path.join(THREE, "build", "three.min.js")),
                                 reason="three.js (libjs-three) is not installed")


def run_data(path):
    text = open(path).read()
    m = re.search(r'<script id="lieflow-run" type="application/json">(.*?)</script>', text, re.S)
    assert m, "no data block"
    return json.loads(m.group(1).replace("<\\/", "</"))


@needs_three
def test_a_result_and_its_csv_give_the_same_frames(tmp_path):
    result = lieflow.simulate("double-pendulum", t_end=0.5)
    page = lieflow.view(result, out=tmp_path / "a.html")
    assert page == os.fspath(tmp_path / "a.html")
    a = run_data(page)
    assert a["frames"] == a["rows"] == len(result.columns["t"])
    assert [b["name"] for b in a["bodies"]] == ["upper", "lower"]
    # The same run through the command's CSV.
    csv = tmp_path / "run.csv"
    with open(csv, "w") as f:
        names = list(result.columns)
        f.write(",".join(names) + "\n")
        for i in range(len(result.columns["t"])):
            f.write(",".join(repr(float(result.columns[n][i])) for n in names) + "\n")
    b = run_data(lieflow.view(os.fspath(csv), "double-pendulum", out=tmp_path / "b.html", frames=100))
    assert b["frames"] <= 100 and b["values"] != a["values"]
    assert b["columns"] == a["columns"]


@needs_three
def test_a_dict_scene_and_a_model_file(tmp_path):
    scene = json.load(open(os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "pendulum.json")))
    result = lieflow.simulate(scene, t_end=0.2)
    data = run_data(lieflow.view(result, out=tmp_path / "p.html"))
    assert data["bodies"][0]["shapes"][0]["kind"] == "box"  # the inertia box: a scene file gives no shapes
    model = os.path.join(os.path.dirname(__file__), "..", "data", "models", "arm6_shapes.urdf")
    result = lieflow.simulate(model, t_end=0.1)
    data = run_data(lieflow.view(result, out=tmp_path / "arm.html"))
    kinds = sorted(s["kind"] for b in data["bodies"] for s in b["shapes"])
    assert kinds.count("mesh") == 2 and "sphere" in kinds


def test_bad_input_raises_input_error(tmp_path):
    result = lieflow.simulate("double-pendulum", t_end=0.1)
    with pytest.raises(lieflow.InputError, match="top.qw"):
        lieflow.view(result, "heavy-top", out=tmp_path / "x.html")
    with pytest.raises(lieflow.InputError, match="scene"):
        lieflow.view(os.fspath(tmp_path / "missing.csv"), out=tmp_path / "x.html")
    with pytest.raises(lieflow.InputError):
        lieflow.view(42, "double-pendulum", out=tmp_path / "x.html")
    with pytest.raises(lieflow.InputError, match="--frames"):
        lieflow.view(result, frames=1, out=tmp_path / "x.html")
