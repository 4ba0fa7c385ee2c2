"""`pip install .`: the package lieflow (python/lieflow) with its extension
module and the `lieflow` command, built by CMake.

The CMake build goes to $LIEFLOW_CMAKE_BUILD_DIR, else build-pip/ in the
repository (configured once, Release, without tests and benchmarks; later
installs rebuild incrementally). An existing build tree (such as build/ of
scripts/test.sh) is used as it is configured. What CMake finds missing
switches off as it does for any build (a lieflow without Ceres has no
calibrate_* functions).
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def version():
    m = re.search(r"project\(lieflow\s+VERSION\s+([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    return m.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = Path(os.environ.get("LIEFLOW_CMAKE_BUILD_DIR", ROOT / "build-pip")).resolve()
        if not (build / "CMakeCache.txt").exists():
            generator = ["-G", "Ninja"] if shutil.which("ninja") else []
            subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build), *generator,
                                   "-DCMAKE_BUILD_TYPE=Release", "-DLIEFLOW_BUILD_TESTS=OFF",
                                   "-DLIEFLOW_BUILD_BENCH=OFF", "-DPython3_EXECUTABLE=" + sys.executable])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "_lieflow", "lieflow",
                               "--parallel", str(os.cpu_count() or 2)])
        module = next((build / "python" / "lieflow").glob("_lieflow*.so"), None)
        if module is None:
            raise RuntimeError("lieflow: the CMake build in %s made no Python module (is pybind11-dev installed? "
                               "see its CMake output)" % build)
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(module, target)
        # The command and the plot scripts, inside the package
        # (lieflow/_command.py runs the one, lieflow/__init__.py finds the others).
        package = target.parent
        (package / "bin").mkdir(exist_ok=True)
        shutil.copy2(build / "app" / "lieflow", package / "bin" / "lieflow")
        (package / "scripts").mkdir(exist_ok=True)
        for script in ("plot_study.py", "plot_stability.py"):
            shutil.copy2(ROOT / "scripts" / script, package / "scripts" / script)


setup(
    version=version(),
    package_dir={"": "python"},
    packages=["lieflow"],
    ext_modules=[Extension("lieflow._lieflow", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    # setuptools' own build folder apart from CMake's build/.
    options={"build": {"build_base": "build-pip/setuptools"}, "egg_info": {"egg_base": "build-pip"}},
)
