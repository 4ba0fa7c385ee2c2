#!/usr/bin/env bash
# The installed package, as a user outside this tree meets it (issue 13):
#   test_package.sh install BUILD_DIR PREFIX
#       cmake --install BUILD_DIR --prefix PREFIX (a fresh prefix)
#   test_package.sh example PREFIX SOURCE_DIR WORK_DIR
#       configure, build and run examples/cpp against PREFIX with nothing set
#       but CMAKE_PREFIX_PATH; a missing component and a too-new version fail
#   test_package.sh headers PREFIX EIGEN_INCLUDE_DIR
#       every installed header compiles on its own (one translation unit each)
#   test_package.sh python PREFIX WORK_DIR
#       `import lieflow` from PREFIX/lib/python3/dist-packages (nothing else
#       set), a run, and a study whose plots come from PREFIX/share/lieflow
#   test_package.sh command PREFIX WORK_DIR
#       the installed `lieflow` runs a scene and draws its study plots from
#       PREFIX/share/lieflow, away from the source tree
#   test_package.sh pip SOURCE_DIR BUILD_DIR WORK_DIR
#       `pip install --no-build-isolation --no-index SOURCE_DIR` into a fresh
#       virtual environment (offline, Debian's setuptools), reusing BUILD_DIR's
#       CMake build (LIEFLOW_CMAKE_BUILD_DIR): `import lieflow` without
#       PYTHONPATH, the `lieflow` command on the venv's PATH, a replay page and
#       a study's plots from the package's own scripts; then with Debian's pip
#       into the system's layout under a staging --root; exits 77 (skipped)
#       without python3-venv or python3-setuptools
set -euo pipefail
mode=$1
shift
jobs=$(nproc)

case "$mode" in
install)
  build=$1 prefix=$2
  rm -rf "$prefix"
  cmake --install "$build" --prefix "$prefix" >/dev/null
  for f in bin/lieflow lib/cmake/lieflow/lieflowConfig.cmake lib/cmake/lieflow/lieflowConfigVersion.cmake \
           lib/cmake/lieflow/lieflowTargets.cmake include/lieflow/liegroup/so3.hpp share/lieflow/scenes/heavy-top.json \
           share/lieflow/scripts/plot_study.py; do
    [ -e "$prefix/$f" ] || { echo "not installed: $prefix/$f" >&2; exit 1; }
  done
  echo "installed into $prefix"
  ;;
example)
  prefix=$1 source=$2 work=$3
  rm -rf "$work"
  mkdir -p "$work"
  # Only CMAKE_PREFIX_PATH: no lieflow_DIR, no include paths.
  env -u lieflow_DIR -u CMAKE_PREFIX_PATH cmake -S "$source" -B "$work/build" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release >"$work/configure.log"
  cmake --build "$work/build" -j "$jobs" >"$work/build.log"
  "$work/build/gravity_gradient"
  # What find_package must refuse: an unknown component and a version the
  # package is not compatible with (0.x: the minor version must match).
  mkdir -p "$work/refuse"
  for request in "0.1 CONFIG REQUIRED COMPONENTS no_such_component" "0.99 CONFIG REQUIRED COMPONENTS liegroup"; do
    printf 'cmake_minimum_required(VERSION 3.18)\nproject(refuse LANGUAGES CXX)\nfind_package(lieflow %s)\n' \
      "$request" >"$work/refuse/CMakeLists.txt"
    if cmake -S "$work/refuse" -B "$work/refuse/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/refuse.log" 2>&1; then
      echo "find_package(lieflow $request) succeeded; it must fail" >&2
      exit 1
    fi
    rm -rf "$work/refuse/build"
  done
  echo "find_package refuses an unknown component and version 0.99"
  ;;
headers)
  prefix=$1 eigen=$2
  include=$prefix/include/lieflow
  cxx=${CXX:-c++}
  count=$(find "$include" -name '*.hpp' | wc -l)
  [ "$count" -gt 0 ] || { echo "no headers under $include" >&2; exit 1; }
  # -include on an empty translation unit: the header is all the unit sees.
  find "$include" -name '*.hpp' -print0 | sort -z |
    xargs -0 -P "$jobs" -I{} sh -c \
      'echo "" | "$0" -std=c++17 -fsyntax-only -Wall -Wextra -Werror -I"$1" -isystem "$2" -include "{}" -x c++ - ||
       { echo "does not compile on its own: {}" >&2; exit 255; }' "$cxx" "$include" "$eigen"
  echo "$count installed headers compile on their own"
  ;;
command)
  prefix=$1 work=$2
  rm -rf "$work"
  mkdir -p "$work"
  cd "$work"
  env -u LIEFLOW_SCRIPTS_DIR "$prefix/bin/lieflow" scenes >/dev/null
  env -u LIEFLOW_SCRIPTS_DIR "$prefix/bin/lieflow" simulate "$prefix/share/lieflow/scenes/heavy-top.json" \
    --integrator rkmk4 --dt 0.01 --t-end 1 --out run.csv
  [ "$(wc -l <run.csv)" -eq 102 ] || { echo "run.csv has $(wc -l <run.csv) lines, expected 102" >&2; exit 1; }
  if /usr/bin/python3 -c 'import matplotlib' 2>/dev/null; then
    env -u LIEFLOW_SCRIPTS_DIR "$prefix/bin/lieflow" study heavy-top --integrators rkmk4,lgvi --dt 0.02,0.01 --t-end 1 --min-time 0.01 \
      --out study >study.log 2>&1 || { cat study.log >&2; exit 1; }
    ls study/*.png >/dev/null || { echo "the installed command drew no plots" >&2; cat study.log >&2; exit 1; }
    echo "the installed lieflow ran a scene and drew its study plots"
  else
    echo "the installed lieflow ran a scene (no matplotlib: plots not checked)"
  fi
  ;;
python)
  prefix=$1 work=$2
  rm -rf "$work"
  mkdir -p "$work"
  cd "$work"
  env -u LIEFLOW_SCRIPTS_DIR PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 - "$prefix" <<'PY'
import os, sys
import lieflow
prefix = os.path.realpath(sys.argv[1])
assert os.path.realpath(lieflow.__file__).startswith(prefix), lieflow.__file__
run = lieflow.simulate("pendulum", dt=0.01, t_end=0.5)
assert len(run.columns["t"]) == 51 and not run.failed
assert os.path.realpath(os.environ["LIEFLOW_SCRIPTS_DIR"]) == os.path.join(prefix, "share", "lieflow", "scripts")
try:
    import matplotlib  # noqa: F401
except ImportError:
    print("lieflow imported from", os.path.dirname(lieflow.__file__), "(no matplotlib: plots not checked)")
    sys.exit(0)
study = lieflow.study("heavy-top", integrators=["rkmk4"], dt=[0.002, 0.001], t_end=0.5, min_time=0.001,
                      out="study", plots=True)
assert "plot_problem" not in study, study.get("plot_problem")
assert os.path.exists("study/work_precision.png")
print("lieflow imported from", os.path.dirname(lieflow.__file__), "ran a scene and drew a study's plots")
PY
  ;;
pip)
  source_dir=$1 build=$2 work=$3
  if ! /usr/bin/python3 -c "import venv, ensurepip, setuptools, wheel" 2>/dev/null; then
    echo "skipped: pip install needs python3-venv, python3-setuptools and python3-wheel" >&2
    exit 77
  fi
  rm -rf "$work"
  mkdir -p "$work"
  cd "$work"
  # --system-site-packages: NumPy (and matplotlib) from Debian, offline.
  /usr/bin/python3 -m venv --system-site-packages venv
  LIEFLOW_CMAKE_BUILD_DIR="$build" venv/bin/pip install --no-build-isolation --no-index -q "$source_dir"
  [ -x venv/bin/lieflow ] || { echo "pip installed no lieflow command" >&2; exit 1; }
  env -u PYTHONPATH -u LIEFLOW_SCRIPTS_DIR -u LIEFLOW_BIN PATH="$work/venv/bin:$PATH" \
    venv/bin/python - "$work/venv" <<'PY'
import os, shutil, subprocess, sys
import lieflow
venv = os.path.realpath(sys.argv[1])
assert os.path.realpath(lieflow.__file__).startswith(venv), lieflow.__file__
assert os.path.realpath(shutil.which("lieflow")) == os.path.join(venv, "bin", "lieflow"), shutil.which("lieflow")
stats = subprocess.run(["lieflow", "simulate", "pendulum", "--t-end", "0.5", "--stats"], capture_output=True,
                       text=True, check=True).stdout
assert '"integrator"' in stats, stats
run = lieflow.simulate("pendulum", dt=0.01, t_end=0.5)
assert len(run.columns["t"]) == 51 and not run.failed
if os.path.exists("/usr/share/javascript/three/build/three.min.js"):
    assert os.path.getsize(lieflow.view(run, out="replay.html")) > 100000
study = subprocess.run(["lieflow", "study", "heavy-top", "--integrators", "rkmk4", "--dt", "0.002,0.001",
                        "--t-end", "0.5", "--min-time", "0.001", "--out", "study"], capture_output=True, text=True)
assert study.returncode == 0, study.stderr
try:
    import matplotlib  # noqa: F401
    assert os.path.exists("study/work_precision.png"), study.stderr
except ImportError:
    pass
print("pip installed lieflow into", venv, ": import, the command, a replay and a study's plots")
PY
  # Into the system's layout (Debian's /usr/local/lib/python3.X/dist-packages
  # and /usr/local/bin, under a staging root so that the test leaves the
  # machine as it was), with Debian's own pip.
  if /usr/bin/python3 -m pip --version >/dev/null 2>&1; then
    LIEFLOW_CMAKE_BUILD_DIR="$build" /usr/bin/python3 -m pip install --no-build-isolation --no-index -q \
      --break-system-packages --root "$work/root" "$source_dir"
    site=$(find "$work/root" -type d -name dist-packages -path "*python3*" | head -n 1)
    [ -n "$site" ] && [ -x "$work/root/usr/local/bin/lieflow" ] || { echo "no system-layout install under $work/root" >&2; exit 1; }
    env -u LIEFLOW_SCRIPTS_DIR PYTHONPATH="$site" /usr/bin/python3 -c \
      "import lieflow, sys; assert lieflow.__file__.startswith('$site'), lieflow.__file__; print('and into the system layout:', lieflow.__file__)"
    env -u LIEFLOW_SCRIPTS_DIR PYTHONPATH="$site" "$work/root/usr/local/bin/lieflow" scenes >/dev/null
  else
    echo "system install not checked: no pip for /usr/bin/python3 (python3-pip)"
  fi
  ;;
*)
  echo "unknown mode $mode" >&2
  exit 2
  ;;
esac
