"""lieflow: geometric integration of constrained rigid bodies on Lie groups.

The Python face of the C++ library and of the ``lieflow`` command:

- ``SO3``, ``SE3``: the groups, vectorized over NumPy arrays (lieflow.groups);
- ``simulate``, ``study``, ``stability``: the commands, with their flags as
  keyword arguments and their outputs as NumPy arrays and dicts
  (lieflow.commands);
- ``calibrate_hinge``, ``calibrate_universal``, ``calibrate_spherical``,
  ``calibrate_spring``: the fits (in builds with Ceres);
- ``view``: a run as a self-contained HTML replay (lieflow view);
- ``sweep``: many runs at once on a Dask cluster (lieflow.sweep).

Bad input raises ``InputError`` (a ValueError) with the command's message; a
failed computation raises ``ComputationError`` (a RuntimeError).
"""
import os as _os

from ._lieflow import ComputationError, InputError, __version__

InputError.__module__ = ComputationError.__module__ = __name__

# The installed command and module find the plot scripts next to them; a
# module installed under PREFIX/lib/python3/dist-packages/lieflow points the
# C++ side at PREFIX/share/lieflow/scripts.
_installed_scripts = _os.path.normpath(
    _os.path.join(_os.path.dirname(__file__), "..", "..", "..", "..", "share", "lieflow", "scripts"))
# A pip-installed package holds them itself (setup.py).
_package_scripts = _os.path.join(_os.path.dirname(__file__), "scripts")
if "LIEFLOW_SCRIPTS_DIR" not in _os.environ and _os.path.isdir(_package_scripts):
    _os.environ["LIEFLOW_SCRIPTS_DIR"] = _package_scripts
elif "LIEFLOW_SCRIPTS_DIR" not in _os.environ and _os.path.isdir(_installed_scripts):
    _os.environ["LIEFLOW_SCRIPTS_DIR"] = _installed_scripts

from .groups import SE3, SO3  # noqa: E402
from .commands import (  # noqa: E402
    SimulationResult,
    calibrate_hinge,
    calibrate_spherical,
    calibrate_spring,
    calibrate_universal,
    import_model,
    scenes,
    simulate,
    stability,
    study,
    view,
)


def __getattr__(name):
    # lieflow.sweep is the module lieflow/sweep.py (so that `python3 -m
    # lieflow.sweep` runs it), imported on first use (it needs Dask) and
    # callable: lieflow.sweep(spec, ...) is lieflow.sweep.sweep(spec, ...).
    if name == "sweep":
        import importlib
        return importlib.import_module(".sweep", __name__)
    raise AttributeError(f"module 'lieflow' has no attribute {name!r}")

__all__ = [
    "ComputationError", "InputError", "SE3", "SO3", "SimulationResult", "__version__", "calibrate_hinge",
    "calibrate_spring", "calibrate_universal", "import_model", "scenes", "simulate", "stability", "study", "sweep",
    "view",
]
