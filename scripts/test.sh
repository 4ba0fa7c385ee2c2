#!/usr/bin/env bash
# Command 2 of the README: set up, build everything and run the whole test
# suite through ctest. Extra arguments are passed to ctest.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIEFLOW_BUILD_DIR:-$root/build}
bash "$root/scripts/setup.sh"
bash "$root/scripts/configure.sh" "$build_dir"
cmake --build "$build_dir" -- -j"$(nproc)"
ctest --test-dir "$build_dir" --output-on-failure -j"$(nproc)" "$@"
