#!/usr/bin/env bash
# Configures a build directory once (default: build/, Release, Ninja) and
# builds the given targets incrementally. Usage: configure.sh BUILD_DIR [cmake args...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$1
shift
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
fi
