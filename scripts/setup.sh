#!/usr/bin/env bash
# Installs the Debian 12 packages lieflow builds with, if any is missing.
# Re-running it is fast: it asks dpkg first and calls apt-get only when needed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache      # toolchain
  libeigen3-dev                                 # liegroup/ and everything (required)
  libboost-dev                                  # Boost.Math: Jacobi elliptic functions (exact flows)
  nlohmann-json3-dev                            # scene files (app/)
  libceres-dev                                  # calibration/ and ceres::Jet tests
  libsuitesparse-dev                            # KLU: generalized-alpha's sparse LU (else Eigen's SparseLU)
  libbenchmark-dev                              # bench/
  libgtest-dev libgmock-dev                     # tests/
  python3-matplotlib                            # plots of studies and papers/
  pybind11-dev python3-dev python3-numpy        # the Python module (python/)
  python3-pytest python3-distributed            # its tests; sweeps on Dask (lieflow.sweep)
  python3-venv python3-setuptools python3-wheel # pip install . (pyproject.toml, setup.py) and its test
  python3-pip                                   # the same into the system's layout
  libmujoco-dev libmujoco-samples               # MJCF models (model/import/) and the MuJoCo peer of bench/
  liburdfdom-dev libtinyxml2-dev                # URDF models; element lines for both importers
  libjs-three                                   # three.js, inlined in replay pages (lieflow view)
  chromium                                      # the replay's browser test (headless)
  universal-ctags                               # the function-length check (scripts/layers.py functions)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "lieflow setup: installing ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
