"""Shared fixtures of the Python tests (run by ctest: tests/CMakeLists.txt
sets PYTHONPATH to BUILD/python and LIEFLOW_BIN, LIEFLOW_GROUP_REFERENCE)."""
import os
import subprocess

import pytest


@pytest.fixture(scope="session")
def lieflow_bin():
    path = os.environ.get("LIEFLOW_BIN")
    if not path or not os.path.exists(path):
        pytest.fail("LIEFLOW_BIN must name the built lieflow command (ctest sets it)")
    return path


@pytest.fixture(scope="session")
def run_command(lieflow_bin):
    """Runs `lieflow ARGS...` and returns (exit status, stdout, stderr)."""

    def run(*args, cwd=None):
        done = subprocess.run([lieflow_bin, *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=240)
        return done.returncode, done.stdout, done.stderr

    return run
