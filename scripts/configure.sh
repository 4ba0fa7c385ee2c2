#!/usr/bin/env bash
# Configures a build directory once (Ninja, Release unless the extra cmake
# arguments say otherwise); later calls leave it as it is, so builds stay
# incremental. Usage: configure.sh BUILD_DIR [cmake args...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$1
shift
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
fi
