#!/usr/bin/env bash
# Command 1 of the README: set up, build and run the main job (`lieflow` with
# no arguments). Extra arguments are passed to `lieflow`.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIEFLOW_BUILD_DIR:-$root/build}
bash "$root/scripts/setup.sh"
bash "$root/scripts/configure.sh" "$build_dir"
cmake --build "$build_dir" --target lieflow -- -j"$(nproc)" >/dev/null
cd "$root"
exec "$build_dir/app/lieflow" "$@"
