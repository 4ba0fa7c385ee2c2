"""The lieflow commands as functions: the command's flags as keyword
arguments, its outputs as NumPy arrays and dicts with the command's names.

The arguments are handed to the command's own C++ code, so input is checked
and refused exactly as on the command line (InputError, the message naming
the flag or field); a run or fit that fails raises ComputationError unless
``partial=True`` asks for what was computed.
"""
import csv
import inspect
import json
import math
import numbers
import os
import shutil
import tempfile
import warnings

import numpy as np

from . import _lieflow
from ._lieflow import ComputationError, InputError


class SimulationResult:
    """What ``simulate`` returns.

    columns: dict of 1-D NumPy arrays, the CSV's columns by their CSV names
             (t, B.qw, ..., J.phi, ...), one entry per output row;
    stats:   dict with the keys of ``lieflow simulate --stats``;
    failed, failure: whether the run failed and why (only seen with
             ``partial=True``; otherwise a failure raises ComputationError);
    source, model_options: the scene as given to ``simulate`` and how a
             model file was read (ignore, keyframe, floating_base, spin), for
             ``view``.
    """

    def __init__(self, scene, columns, stats, failed, failure):
        self.scene = scene
        self.columns = columns
        self.stats = stats
        self.failed = failed
        self.failure = failure

    def __repr__(self):
        rows = len(next(iter(self.columns.values()))) if self.columns else 0
        state = f"failed: {self.failure}" if self.failed else "ok"
        return f"lieflow.SimulationResult({self.scene!r}, {rows} rows, {len(self.columns)} columns, {state})"


def _shown(value):
    """repr(value) for a message: an integer of many digits by its size, other
    values cut to 60 characters."""
    if isinstance(value, numbers.Integral) and not isinstance(value, bool) and abs(int(value)) >= 10**20:
        return f"an integer of {len(str(abs(int(value))))} digits"
    text = repr(value)
    return text if len(text) <= 60 else text[:60] + "…"


def _scalar(value):
    """A NumPy scalar as the Python number it holds; anything else as is."""
    return value.item() if isinstance(value, np.generic) else value


def _number(flag, value):
    value = _scalar(value)
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{flag}: expected a number, got {_shown(value)}")
    try:
        value = float(value)
    except OverflowError:
        raise InputError(f"{flag}: {_shown(value)} overflows a double") from None
    if not math.isfinite(value):
        raise InputError(f"{flag}: {value} is not a finite number")
    return repr(value)


# The integers the command's flags take fit a signed 64-bit integer.
_MAX_INTEGER = 2**63 - 1


def _integer(flag, value):
    value = _scalar(value)
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(f"{flag}: expected an integer, got {_shown(value)}")
    if abs(int(value)) > _MAX_INTEGER:
        raise InputError(f"{flag}: {_shown(value)} is beyond the 64-bit integer range")
    return str(int(value))


def _text(flag, value):
    if not isinstance(value, (str, os.PathLike)):
        raise InputError(f"{flag}: expected a string, got {_shown(value)}")
    text = os.fspath(value)
    if not isinstance(text, str) or "\0" in text:
        raise InputError(f"{flag}: expected a string without NUL characters, got {value!r}")
    return text


def _numbers(flag, values):
    values = _scalar(values)
    if isinstance(values, numbers.Real) and not isinstance(values, bool):
        values = [values]
    if isinstance(values, (str, bytes, dict)):
        raise InputError(f"{flag}: expected a number or a list of numbers, got {_shown(values)}")
    try:
        items = list(values)
    except TypeError:
        raise InputError(f"{flag}: expected a number or a list of numbers, got {_shown(values)}") from None
    if not items:
        raise InputError(f"{flag}: expected at least one number")
    return ",".join(_number(flag, v) for v in items)


def _low_pass(flag, value):
    """--low-pass: "none", "auto" or a cutoff [Hz]."""
    if isinstance(value, str) and value in ("none", "auto"):
        return value
    return _number(flag, value)


def _keyframe(flag, value):
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return str(value)
    return _text(flag, value)


def _spin_values(flag, value):
    """Three finite numbers (a list, tuple or NumPy array) as floats."""
    values = _plain(value, flag)
    if not isinstance(values, list) or len(values) != 3 or not all(
            isinstance(v, numbers.Real) and not isinstance(v, bool) for v in values):
        raise InputError(f"{flag}: expected three numbers (rad/s, world axes), got {_shown(value)}")
    return [float(v) for v in values]


def _spin(flag, value):
    """--spin's WX,WY,WZ."""
    return ",".join(repr(v) for v in _spin_values(flag, value))


def _names(flag, values):
    if isinstance(values, (str, os.PathLike)):
        values = [values]
    if not isinstance(values, (list, tuple)):
        raise InputError(f"{flag}: expected a name or a list of names, got {_shown(values)}")
    if not values:
        raise InputError(f"{flag}: expected at least one name")
    return ",".join(_text(flag, v) for v in values)


def _options(flag, options):
    """The --options list, or None for an empty dict (no options: the scene's own)."""
    if not isinstance(options, dict):
        raise InputError(f"{flag}: expected a dict of integrator options, got {_shown(options)}")
    if not options:
        return None
    return ",".join(f"{_text(flag, k)}={_number(flag + '.' + str(k), v)}" for k, v in options.items())


def _switch(name, value):
    """A yes/no argument: True or False (NumPy's too), else InputError."""
    value = _scalar(value)
    if not isinstance(value, bool):
        raise InputError(f"{name}: expected True or False, got {_shown(value)}")
    return value


def _flags(spec, values):
    """Command-line tokens for the keyword arguments that are not None:
    spec maps a keyword to (flag, formatter); a formatter of None marks a
    switch (given when the value is true)."""
    tokens = []
    for key, value in values.items():
        if value is None or key not in spec:
            continue
        flag, fmt = spec[key]
        if fmt is None:
            if _switch(key, value):
                tokens.append(flag)
            continue
        text = fmt(flag, value)
        if text is not None:
            tokens += [flag, text]
    return tokens


_LIMITS = {"max_steps": ("--max-steps", _integer), "max_input_mb": ("--max-input-mb", _integer),
           "max_bodies": ("--max-bodies", _integer), "ignore": ("--ignore", _names),
           "keyframe": ("--keyframe", _keyframe), "floating_base": ("--floating-base", None),
           "spin": ("--spin", _spin)}


def _plain(value, where):
    """`value` as plain JSON data: NumPy scalars and arrays as numbers and
    lists, tuples as lists; every number finite (InputError naming its place,
    "bodies[0].mass", as the scene reader names fields)."""
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                raise InputError(f"{where or '(top level)'}: keys must be strings, got {key!r}")
            out[key] = _plain(item, f"{where}.{key}" if where else key)
        return out
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(item, f"{where}[{i}]") for i, item in enumerate(value)]
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (str, bool)):
        return value
    if isinstance(value, numbers.Real):
        try:
            number = float(value)
        except OverflowError:
            number = math.inf if value > 0 else -math.inf  # an int beyond double range: beyond the bound below
        if math.isnan(number) or (math.isinf(number) and not isinstance(value, numbers.Integral)):
            raise InputError(f"{where}: is not a finite number ({_shown(value)})")
        if abs(number) > _lieflow.max_input_magnitude:
            raise InputError(f"{where}: {_shown(value)} is beyond ±{_lieflow.max_input_magnitude:g}, the largest "
                             "magnitude lieflow reads")
        return int(value) if isinstance(value, numbers.Integral) else number
    raise InputError(f"{where or '(top level)'}: expected a number, string, bool, list or dict, "
                     f"got {type(value).__name__}")


def _scene(scene, what="scene"):
    """(positional tokens, JSON text): a file or built-in name is passed as the
    command's SCENE; a dict in the scene schema as JSON text (checked and made
    plain by _plain; the reader's messages then say "scene dict: FIELD")."""
    if isinstance(scene, dict):
        try:
            return [], json.dumps(_plain(scene, ""), allow_nan=False)
        except InputError as e:
            raise InputError(f"scene dict: {e}") from None
        except RecursionError:
            raise InputError("scene dict: nested too deeply (or it contains itself)") from None
    if isinstance(scene, (str, os.PathLike)):
        return [os.fspath(scene)], None
    raise InputError(f"{what}: expected a scene file, a built-in scene name or a dict, got {type(scene).__name__}")


def import_model(model, ignore=None, keyframe=None, floating_base=False, spin=None):
    """A MuJoCo MJCF (.xml) or URDF (.urdf) model as the scene it becomes, as
    ``lieflow import MODEL``: a dict in the scene schema (welded links merged;
    pass it to simulate, study or stability, or edit it first). ignore: what
    the model may leave out (e.g. ["contacts", "limits"], or ["all"]); what was
    left out is reported with warnings.warn. keyframe: an MJCF keyframe's name
    or index whose qpos and qvel are the start (default: qpos0, at rest).
    floating_base: a URDF's root link on a free joint to the world (default:
    fixed to it, as URDF's tools take it; the notes say so). spin: (wx, wy, wz)
    rad/s, world axes: every free tree turning rigidly about its centre of
    mass, added to its start (--spin).
    Raises InputError naming the file, element and line for what lieflow
    cannot represent."""
    if not isinstance(model, (str, os.PathLike)):
        raise InputError(f"model: expected a path to a .xml or .urdf file, got {type(model).__name__}")
    text, notes = _lieflow.import_model(os.fspath(model), _names("ignore", ignore) if ignore is not None else "",
                                        _keyframe("keyframe", keyframe) if keyframe is not None else "",
                                        _switch("floating_base", floating_base),
                                        _spin_values("spin", spin) if spin is not None else [])
    if notes:
        warnings.warn(f"lieflow: {os.fspath(model)}: " + "; ".join(notes), stacklevel=2)
    return json.loads(text)


def scenes():
    """The built-in scenes: a dict of name -> one-line description."""
    return dict(_lieflow.scenes())


def _callables(name, loads):
    if loads is None:
        return {}
    if not isinstance(loads, dict):
        raise InputError(f"{name}: expected a dict of name -> callable, got {type(loads).__name__}")
    for key, value in loads.items():
        if not isinstance(key, str) or not callable(value):
            raise InputError(f"{name}[{key!r}]: expected a name and a callable f(t, state)")
        # Called as f(t, state): a callable that cannot take two arguments is
        # refused here, not with a TypeError from inside the run.
        try:
            signature = inspect.signature(value)
        except (TypeError, ValueError):
            continue  # a builtin without a signature: called as it is
        try:
            signature.bind(0.0, {})
        except TypeError:
            raise InputError(f"{name}[{key!r}]: the callable must take (t, state), its signature is "
                             f"{signature}") from None
    return loads


def simulate(scene, integrator=None, dt=None, t_end=None, every=1, options=None, noise=None, torques=None,
             moments=None, partial=False, max_steps=None, max_input_mb=None, max_bodies=None, formulation=None,
             imu=False, ignore=None, keyframe=None, floating_base=False, check_every=None, spin=None):
    """Runs a scene, as ``lieflow simulate SCENE --stats``.

    scene:      a scene file, a model file (MJCF .xml, URDF .urdf), a built-in
                name (``lieflow.scenes()``) or a dict in the scene schema;
    ignore:     what a model file may leave out (--ignore), e.g.
                ["contacts", "limits"]; what was left out is printed to stderr;
    keyframe:   an MJCF model's keyframe (name or index) as the start (--keyframe);
    spin:       (wx, wy, wz) rad/s, world axes: every free tree of a model
                turning rigidly about its centre of mass, added to its start
                (--spin);
    integrator, dt, t_end, every: as --integrator, --dt, --t-end, --every
                (None: the scene's own; a scene that names no integrator or step
                runs rkmk4 at a default step, as stats["integrator"] and
                stats["dt"] say);
    check_every: steps between the checks of the drifts, invariants and
                constraint error (--check-every; None: at the rows, every
                `every`-th step, as stats["checked_every"] says);
    options:    dict of integrator options (--options), e.g. {"rho_inf": 0.8};
    formulation: "maximal" or "joint" (--formulation; None: the default, joint
                coordinates wherever they represent the scene, as stats["formulation"] says);
    noise:      dict with any of gyro, angle, quat, acc, bias_gyro (standard
                deviations, as --noise-gyro/--noise-angle/--noise-quat/
                --noise-acc/--bias-gyro) and seed;
    imu:        also the accelerometer columns B.ax, B.ay, B.az (--imu);
    torques:    {body name: f(t, state)}: a torque on the body [N m], body
                frame, about its centre of mass; state is a dict with q
                (w, x, y, z), omega (body frame), p and v (world);
    moments:    {joint name: f(t, state)}: a moment [N m] on each coordinate
                of a revolute or universal joint, beside its spring, dashpot
                and moment; state has phi, phidot and coordinate (1 or 2).
                With torques or moments the scene runs as a multibody system
                with an explicit integrator (rkmk-*, cg3, cf4); each stage of
                each step calls every function once (see the README for
                the cost per call);
    partial:    return a failed run's rows and stats instead of raising.
    Returns a SimulationResult (columns, stats, failed, failure). The run
    releases the GIL; Ctrl-C stops it (KeyboardInterrupt) at its next
    progress report (about every 0.25 s of run time).
    """
    positional, scene_json = _scene(scene)
    partial = _switch("partial", partial)
    if noise is not None and not isinstance(noise, dict):
        raise InputError(f"noise: expected a dict like {{'gyro': 0.01, 'seed': 1}}, got {noise!r}")
    noise = dict(noise or {})
    unknown = set(noise) - {"gyro", "angle", "quat", "acc", "bias_gyro", "seed"}
    if unknown:
        raise InputError(f"noise: unknown key(s) {sorted(unknown)} (gyro, angle, quat, acc, bias_gyro, seed)")
    spec = {"integrator": ("--integrator", _text), "dt": ("--dt", _number), "t_end": ("--t-end", _number),
            "every": ("--every", _integer), "check_every": ("--check-every", _integer),
            "options": ("--options", _options), "gyro": ("--noise-gyro", _number), "angle": ("--noise-angle", _number),
            "quat": ("--noise-quat", _number), "seed": ("--seed", _integer),
            "acc": ("--noise-acc", _number), "bias_gyro": ("--bias-gyro", _number),
            "formulation": ("--formulation", _text), "imu": ("--imu", None), **_LIMITS}
    tokens = positional + _flags(spec, dict(integrator=integrator, dt=dt, t_end=t_end, every=every, check_every=check_every,
                                            options=options, formulation=formulation, imu=imu, ignore=ignore, keyframe=keyframe,
                                            floating_base=floating_base, spin=spin, max_steps=max_steps, max_input_mb=max_input_mb, max_bodies=max_bodies,
                                            **noise)) + ["--quiet"]
    raw = _lieflow.simulate(tokens, scene_json, _callables("torques", torques), _callables("moments", moments))
    data = raw["data"]
    columns = {name: data[:, i].copy() for i, name in enumerate(raw["columns"])}
    result = SimulationResult(raw["scene"], columns, json.loads(raw["stats"]), raw["failed"], raw["failure"])
    # What view() needs to read the scene again as this run read it.
    result.source = scene
    result.model_options = {"ignore": ignore, "keyframe": keyframe, "floating_base": floating_base, "spin": spin}
    if result.failed and not partial:
        error = ComputationError(f"simulation of {raw['scene']} with {result.stats.get('integrator')} failed: "
                                 f"{result.failure}")
        error.result = result
        raise error
    return result


# Columns of the command's CSV files that hold text (quoted by the writer).
_TEXT_COLUMNS = {"scene", "integrator", "failure", "reference", "options", "first_failure"}


def _read_csv(path):
    """A CSV file the command wrote, as a dict of columns: text columns as
    lists of strings, true/false as bool arrays, numbers as float arrays (a
    column with empty cells, meaning "does not apply", as a masked array)."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    out = {}
    for i, name in enumerate(header):
        cells = [r[i] if i < len(r) else "" for r in rows]
        if name in _TEXT_COLUMNS:
            out[name] = cells
        elif cells and all(c in ("true", "false") for c in cells):
            out[name] = np.array([c == "true" for c in cells])
        elif all(c != "" for c in cells):
            out[name] = np.array([float(c) for c in cells])
        else:
            out[name] = np.ma.masked_array([float(c) if c else 0.0 for c in cells], mask=[c == "" for c in cells])
    return out


class _OutputDirectory:
    """The command's output directory: the caller's, or a temporary one that
    is removed once its files were read."""

    def __init__(self, out):
        self.given = out is not None
        self.path = _text("out", out) if self.given else tempfile.mkdtemp(prefix="lieflow-")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if not self.given:
            shutil.rmtree(self.path, ignore_errors=True)


def view(run, scene=None, out="replay.html", frames=None, ignore=None, keyframe=None, floating_base=False,
         spin=None):
    """Writes a replay of a run, as ``lieflow view RUN.csv --scene SCENE --out OUT``:
    one self-contained HTML file that opens offline in any browser.

    run:    a SimulationResult (what ``simulate`` returns) or a trajectory
            CSV file (``lieflow simulate --out``);
    scene:  the scene the run is of, as ``simulate`` takes it (None: the
            SimulationResult's own);
    out:    the HTML file to write;
    frames: most frames the page holds (--frames; default 2000);
    ignore, keyframe, floating_base, spin: how a model file is read (None:
            as the SimulationResult's run read it).
    Returns the path written. Raises InputError when the run's columns do
    not fit the scene, ComputationError when three.js (Debian's libjs-three)
    is missing."""
    given = {"ignore": ignore, "keyframe": keyframe, "floating_base": floating_base or None, "spin": spin}
    if isinstance(run, SimulationResult):
        for key, value in getattr(run, "model_options", {}).items():
            if given[key] is None and (scene is None or scene is run.source):
                given[key] = value
    if scene is None:
        if not isinstance(run, SimulationResult):
            raise InputError("scene: needed when run is a CSV file (the scene or model file the run is of)")
        scene = getattr(run, "source", run.scene)
    if not isinstance(out, (str, os.PathLike)):
        raise InputError(f"out: expected a path, got {type(out).__name__}")
    positional, scene_json = _scene(scene)
    with tempfile.TemporaryDirectory(prefix="lieflow-view-") as tmp:
        if scene_json is not None:
            scene_path = os.path.join(tmp, "scene.json")
            with open(scene_path, "w") as f:
                f.write(scene_json)
        else:
            scene_path = positional[0]
        if isinstance(run, SimulationResult):
            run_path = os.path.join(tmp, "run.csv")
            names = list(run.columns)
            table = np.column_stack([np.asarray(run.columns[n], dtype=float) for n in names])
            with open(run_path, "w") as f:
                f.write(",".join(names) + "\n")
                np.savetxt(f, table, delimiter=",", fmt="%.17g")
        elif isinstance(run, (str, os.PathLike)):
            run_path = os.fspath(run)
        else:
            raise InputError(f"run: expected a SimulationResult or a CSV path, got {type(run).__name__}")
        spec = {"frames": ("--frames", _integer), **_LIMITS}
        tokens = [run_path, "--scene", scene_path, "--out", os.fspath(out), "--quiet"]
        tokens += _flags(spec, {"frames": frames, **given})
        _lieflow.view(tokens)
    return os.fspath(out)


def study(scene, integrators=None, dt=None, t_end=None, out=None, min_time=None, options=None, plots=False,
          max_steps=None, max_input_mb=None, max_bodies=None, formulation=None, ignore=None, keyframe=None,
          with_mujoco=False, floating_base=False, spin=None):
    """Work-precision study, as ``lieflow study SCENE``.

    Returns a dict: "rows" (the columns of study.csv: integrator, dt, steps,
    wall_seconds, ns_per_step, orientation_error, ..., a masked entry where the
    CSV cell is empty), "drift" (the columns of drift.csv), "reference",
    "reference_error", and "out" (the directory with the CSV files and, with
    plots=True, the plots; None when out was not given: the files were
    written to a temporary directory and removed). with_mujoco: MuJoCo's
    Euler, RK4 and implicit integrators beside lieflow's on a model file,
    MJCF or URDF (--with-mujoco; rows "mujoco-euler", "mujoco-rk4", "mujoco-implicit"),
    each measured against MuJoCo's own converged run (its RK4 at the smallest
    step over 32), which the rows' "reference" column names with how far it
    lies from lieflow's reference.
    """
    positional, scene_json = _scene(scene)
    plots = _switch("plots", plots)
    spec = {"integrators": ("--integrators", _names), "dt": ("--dt", _numbers), "t_end": ("--t-end", _number),
            "min_time": ("--min-time", _number), "options": ("--options", _options),
            "formulation": ("--formulation", _text), "with_mujoco": ("--with-mujoco", None), **_LIMITS}
    with _OutputDirectory(out) as directory:
        tokens = positional + _flags(spec, dict(integrators=integrators, dt=dt, t_end=t_end, min_time=min_time,
                                                options=options, max_steps=max_steps, max_input_mb=max_input_mb,
                                                max_bodies=max_bodies, formulation=formulation, ignore=ignore,
                                                keyframe=keyframe, with_mujoco=with_mujoco,
                                                floating_base=floating_base, spin=spin))
        tokens += ["--out", directory.path]
        if not plots:
            tokens.append("--no-plots")
        raw = _lieflow.study(tokens, scene_json)
        result = {"rows": _read_csv(os.path.join(directory.path, "study.csv")),
                  "drift": _read_csv(os.path.join(directory.path, "drift.csv")),
                  "reference": raw["reference"], "reference_error": raw["reference_error"],
                  "out": directory.path if directory.given else None}
        if plots and raw["plot_problem"]:
            result["plot_problem"] = raw["plot_problem"]
    return result


def stability(scenes=None, integrators=None, options=None, out=None, plots=False, max_steps=None,
              max_input_mb=None, max_bodies=None, formulation=None, ignore=None, keyframe=None,
              floating_base=False, spin=None):
    """Stability scan, as ``lieflow stability [SCENE...]``: for each integrator
    and scene the largest bounded h*omega_c. scenes: a list of files, built-in
    names or dicts (default stiff-spring and fast-top). Returns a dict:
    "rows" (the columns of stability.csv) and "out" (as in study)."""
    if scenes is None:
        scenes = []
    elif isinstance(scenes, (str, os.PathLike, dict)):
        scenes = [scenes]
    elif not isinstance(scenes, (list, tuple)):
        raise InputError(f"scenes: expected a scene or a list of scenes, got {_shown(scenes)}")
    positional, jsons = [], []
    for s in scenes:
        p, j = _scene(s, "scenes")
        positional += p
        if j is not None:
            jsons.append(j)
    if positional and jsons:
        raise InputError("scenes: give either names and files or dicts, not both")
    plots = _switch("plots", plots)
    spec = {"integrators": ("--integrators", _names), "options": ("--options", _options),
            "formulation": ("--formulation", _text), **_LIMITS}
    with _OutputDirectory(out) as directory:
        tokens = positional + _flags(spec, dict(integrators=integrators, options=options, max_steps=max_steps,
                                                max_input_mb=max_input_mb, max_bodies=max_bodies,
                                                formulation=formulation, ignore=ignore, keyframe=keyframe,
                                                floating_base=floating_base, spin=spin))
        tokens += ["--out", directory.path] + ([] if plots else ["--no-plots"])
        raw = _lieflow.stability(tokens, jsons)
        result = {"rows": _read_csv(os.path.join(directory.path, "stability.csv")),
                  "out": directory.path if directory.given else None}
        if plots and raw["plot_problem"]:
            result["plot_problem"] = raw["plot_problem"]
    return result


def _write_recording(recording, path):
    """A recording given as a dict of equal-length 1-D arrays (t first or
    not), written as the CSV the command reads (17 significant digits)."""
    if not isinstance(recording, dict) or not recording:
        raise InputError("recording: expected a CSV file or a non-empty dict of columns")
    names = list(recording)
    if "t" in names:
        names.remove("t")
        names.insert(0, "t")
    columns = []
    for name in names:
        if not isinstance(name, str):
            raise InputError(f"recording: column names must be strings, got {_shown(name)}")
        if not name or any(c in name for c in ',"') or any(ord(c) < 0x20 or ord(c) == 0x7f for c in name):
            raise InputError(f"recording[{name!r}]: a column name must be non-empty, without commas, quotes or "
                             "control characters")
        try:
            column = np.asarray(recording[name], dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InputError(f"recording[{name!r}]: expected numbers ({e})") from None
        if column.ndim != 1:
            raise InputError(f"recording[{name!r}]: expected a 1-D array, got shape {column.shape}")
        columns.append(column)
    n = len(columns[0])
    for name, column in zip(names, columns):
        if len(column) != n:
            raise InputError(f"recording[{name!r}]: {len(column)} values, column {names[0]!r} has {n}")
    with open(path, "w", newline="") as f:
        f.write(",".join(names) + "\n")
        for i in range(n):
            f.write(",".join(repr(float(c[i])) for c in columns) + "\n")


def _calibrate(kind, recording, spec, values, partial):
    partial = _switch("partial", partial)
    if not _lieflow.have_calibration:
        raise InputError(f"calibrate_{kind}: this lieflow was built without Ceres (apt-get install libceres-dev, "
                         "then rebuild with -DLIEFLOW_BUILD_CALIBRATION=ON)")
    several = isinstance(recording, (list, tuple))
    if several and kind != "hinge":
        raise InputError(f"calibrate_{kind}: recording: one recording (a list of several is for calibrate_hinge)")
    if several and not recording:
        raise InputError("calibrate_hinge: recording: an empty list")
    recordings = list(recording) if several else [recording]
    temporary = None
    written = {}  # path -> how the message names the dict it was written from
    try:
        paths = []
        for i, r in enumerate(recordings):
            if isinstance(r, (str, os.PathLike)):
                paths.append(os.fspath(r))
                continue
            if temporary is None:
                temporary = tempfile.mkdtemp(prefix="lieflow-recording-")
            path = os.path.join(temporary, f"recording{i}.csv")
            _write_recording(r, path)
            written[path] = f"recording[{i}] dict" if several else "recording dict"
            paths.append(path)
        tokens = [kind] + paths + _flags(spec, values)

        def named(text):
            # The messages name the file a dict was written to: name the dict.
            for path, name in written.items():
                text = text.replace(path, name)
            return text

        try:
            text, status, error = _lieflow.calibrate(tokens)
        except InputError as e:
            if not written:
                raise
            raise InputError(named(str(e))) from None
        error = named(error)
    finally:
        if temporary:
            shutil.rmtree(temporary, ignore_errors=True)
    result = json.loads(text) if text else None
    if result and written:
        # (A spring fit's "segments" is a count, not the check's list.)
        for key, field in (("recordings", "file"), ("segments", "recording")):
            entries = result.get(key)
            for entry in entries if isinstance(entries, list) else []:
                if isinstance(entry, dict) and field in entry:
                    entry[field] = written.get(entry[field], entry[field])
    if status != 0:
        if not partial:
            failure = ComputationError(error)
            failure.result = result
            raise failure
        result = dict(result or {})
        result["failed"] = True
        result["failure"] = error
    return result


_AXIS_FIT = {"main": ("--main", _text), "secondary": ("--secondary", _text), "use": ("--use", _text),
             "loss": ("--loss", _text), "loss_scale": ("--loss-scale", _number),
             "start_main": ("--start-main", _numbers), "start_secondary": ("--start-secondary", _numbers),
             "max_iterations": ("--max-iterations", _integer), "max_sigma_deg": ("--max-sigma-deg", _number),
             "min_samples": ("--min-samples", _integer), "max_input_mb": ("--max-input-mb", _integer),
             "max_rows": ("--max-rows", _integer), "verbose": ("--verbose", None)}
_UNIVERSAL_FIT = dict(_AXIS_FIT, fit_gyro_bias=("--fit-gyro-bias", None), fit_time_offset=("--fit-time-offset", None),
                      low_pass=("--low-pass", _low_pass))
_HINGE_FIT = dict(_AXIS_FIT, fit_gyro_bias=("--fit-gyro-bias", None), fit_time_offset=("--fit-time-offset", None),
                  estimator=("--estimator", _text), low_pass=("--low-pass", _low_pass))


def calibrate_hinge(recording, main=None, secondary=None, use=None, loss=None, loss_scale=None, start_main=None,
                    start_secondary=None, max_iterations=None, max_sigma_deg=None, min_samples=None,
                    max_input_mb=None, max_rows=None, verbose=False, fit_gyro_bias=False, fit_time_offset=False,
                    estimator=None, low_pass=None, partial=False):
    """The hinge axis in both bodies' frames, as ``lieflow calibrate hinge``.
    recording: a CSV file or a dict of columns (t, B.wx, ..., B.qw, ...), or
    a list of them: several recordings of the same joint, one axis pair (as
    ``lieflow calibrate hinge A.csv B.csv``; the result's "recordings" and
    "segments" name them).
    Returns the command's JSON object as a dict (axis_main, axis_secondary,
    axis_sigma_deg, rms_residual, converged, message, ...). A fit the data do
    not identify, or one that does not converge, raises ComputationError (its
    .result holds the JSON when there is one); partial=True returns it with
    "failed" and "failure" added instead. fit_gyro_bias / fit_time_offset
    estimate the gyroscopes' biases and the secondary sensor's clock offset
    (gyro_bias_main, gyro_bias_secondary, time_offset and their _sigma; with
    several recordings each one's biases and clock offset are its own, in its
    entry of "recordings");
    estimator: None or "auto" (the default: maximum likelihood over the joint
    angle on gyroscopes alone, else the constraint fit; the result's
    "estimator" and "estimator_reason" say which and why), "likelihood" or
    "constraint";
    low_pass=None (auto: the hinge fit filters by itself when a gyroscope
    wobbles, saying so in "low_pass_hz" and "low_pass_reason"), "none", or
    HZ low-passes the gyroscopes and accelerometers first (sensors
    wobbling on soft tissue; gyro_misfit says how well a hinge explains them)."""
    values = dict(main=main, secondary=secondary, use=use, loss=loss, loss_scale=loss_scale, start_main=start_main,
                  start_secondary=start_secondary, max_iterations=max_iterations, max_sigma_deg=max_sigma_deg,
                  min_samples=min_samples, max_input_mb=max_input_mb, max_rows=max_rows, verbose=verbose,
                  fit_gyro_bias=fit_gyro_bias, fit_time_offset=fit_time_offset, estimator=estimator,
                  low_pass=low_pass)
    return _calibrate("hinge", recording, _HINGE_FIT, values, partial)


def calibrate_universal(recording, main=None, secondary=None, use=None, loss=None, loss_scale=None,
                        start_main=None, start_secondary=None, max_iterations=None, max_sigma_deg=None,
                        min_samples=None, max_input_mb=None, max_rows=None, verbose=False, fit_gyro_bias=False,
                        fit_time_offset=False, low_pass=None, partial=False):
    """Both axes of a universal joint, as ``lieflow calibrate universal``
    (needs orientations); arguments and errors as calibrate_hinge
    (fit_gyro_bias: the gyroscopes' biases perpendicular to each body's axis;
    fit_time_offset: the secondary sensor's clock offset, time_offset).
    Never filtered: with low_pass=None (auto) gyroscopes that wobble on soft
    tissue are left out and the orientations answer ("low_pass_reason" says
    so); low_pass="none" keeps them. From 1000 samples the fit checks its
    quarters, and its parts between rests of 1 s ("model_check",
    "model_spread_deg", "segments", each with "by": "time" or "activity")."""
    values = dict(main=main, secondary=secondary, use=use, loss=loss, loss_scale=loss_scale, start_main=start_main,
                  start_secondary=start_secondary, max_iterations=max_iterations, max_sigma_deg=max_sigma_deg,
                  min_samples=min_samples, max_input_mb=max_input_mb, max_rows=max_rows, verbose=verbose,
                  fit_gyro_bias=fit_gyro_bias, fit_time_offset=fit_time_offset, low_pass=low_pass)
    return _calibrate("universal", recording, _UNIVERSAL_FIT, values, partial)


_CENTRE_FIT = {"main": ("--main", _text), "secondary": ("--secondary", _text),
               "max_iterations": ("--max-iterations", _integer), "min_samples": ("--min-samples", _integer),
               "max_input_mb": ("--max-input-mb", _integer), "max_rows": ("--max-rows", _integer),
               "verbose": ("--verbose", None), "low_pass": ("--low-pass", _low_pass)}


def calibrate_spherical(recording, main=None, secondary=None, max_input_mb=None, max_rows=None, verbose=False,
                        low_pass=None, partial=False):
    """The centre of a ball joint from both bodies' gyroscopes and
    accelerometers (B.wx.., B.ax..), as ``lieflow calibrate spherical``:
    anchor_main, anchor_secondary [m] from each sensor point in its body's
    axes, their _sigma, rms_residual, converged, message; errors as
    calibrate_hinge. low_pass=None (auto) low-passes both at 4 Hz when a
    gyroscope wobbles, "none" never, HZ at that cutoff (as calibrate_hinge);
    "low_pass_hz" and "low_pass_reason" say which. From 4000 samples the fit
    checks its quarters' anchors, and those of its parts between rests of 1 s
    of at least 1000 samples ("model_check", "model_spread_m", "segments", each
    with "by": "time" or "activity")."""
    values = dict(main=main, secondary=secondary, max_input_mb=max_input_mb, max_rows=max_rows, verbose=verbose,
                  low_pass=low_pass)
    return _calibrate("spherical", recording, _CENTRE_FIT, values, partial)


_SPRING_FIT = {"scene": ("--scene", _text), "joint": ("--joint", _text), "main": ("--main", _text),
               "secondary": ("--secondary", _text), "coordinate": ("--coordinate", _integer),
               "fit_rest_angle": ("--fit-rest-angle", None), "hold_damping": ("--hold-damping", None),
               "stiffness_start": ("--stiffness-start", _number), "damping_start": ("--damping-start", _number),
               "rest_angle_start": ("--rest-angle-start", _number), "shooting": ("--shooting", _text),
               "segments": ("--segments", _integer), "integrator": ("--integrator", _text),
               "substeps": ("--substeps", _integer), "max_iterations": ("--max-iterations", _integer),
               "min_samples": ("--min-samples", _integer), "max_substeps": ("--max-substeps", _integer),
               "max_input_mb": ("--max-input-mb", _integer), "max_bodies": ("--max-bodies", _integer),
               "max_rows": ("--max-rows", _integer), "verbose": ("--verbose", None), "data": ("--data", _text),
               "fit_axis": ("--fit-axis", None), "start": ("--start", _text)}


def calibrate_spring(recording, scene, joint=None, main=None, secondary=None, coordinate=None,
                     fit_rest_angle=False, hold_damping=False, stiffness_start=None, damping_start=None,
                     rest_angle_start=None, shooting=None, segments=None, integrator=None, substeps=None,
                     max_iterations=None, min_samples=None, max_substeps=None, max_input_mb=None, max_bodies=None,
                     max_rows=None, verbose=False, data=None, fit_axis=False, start=None, partial=False):
    """Stiffness, damping and rest angle of a joint coordinate, as ``lieflow
    calibrate spring RECORDING --scene SCENE`` (scene: a file or built-in
    name). On a scene of several bodies every sprung or damped coordinate is
    fitted ("coordinates" in the result; data="angles" or "gyroscopes";
    fit_axis=True fits the sprung revolute joints' axes too, on any scene;
    start="inverse-dynamics" or "scene", default from the angles when recorded,
    else from the angles integrated from the gyroscopes).
    Returns the command's JSON object as a dict; errors as calibrate_hinge."""
    if isinstance(scene, dict):
        raise InputError("scene: calibrate_spring takes a scene file or a built-in name")
    values = dict(scene=scene, joint=joint, main=main, secondary=secondary, coordinate=coordinate,
                  fit_rest_angle=fit_rest_angle, hold_damping=hold_damping, stiffness_start=stiffness_start,
                  damping_start=damping_start, rest_angle_start=rest_angle_start, shooting=shooting,
                  segments=segments, integrator=integrator, substeps=substeps, max_iterations=max_iterations,
                  min_samples=min_samples, max_substeps=max_substeps, max_input_mb=max_input_mb,
                  max_bodies=max_bodies, max_rows=max_rows, verbose=verbose, data=data, fit_axis=fit_axis,
                  start=start)
    return _calibrate("spring", recording, _SPRING_FIT, values, partial)
