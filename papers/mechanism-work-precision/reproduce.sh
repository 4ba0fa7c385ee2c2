#!/usr/bin/env bash
# Regenerates papers/mechanism-work-precision/: error against run time on the
# double pendulum, chain-10 and the free Cardan shaft, every lieflow integrator (joint and maximal
# coordinates) beside MuJoCo's RK4, Euler and implicit integrators on the same
# model (bench/multibody/mechanism_work_precision.cpp), then analyze.py writes
# results.md, work_precision.png and the table between the GENERATED markers
# of README.md.
#
#   bash papers/mechanism-work-precision/reproduce.sh [T]
#
# T: end time in seconds (default 2). Build dir: ${LIEFLOW_BUILD_DIR:-build}
# (configured by scripts/run.sh when it has no CMakeCache.txt); the target
# study_mechanism_work_precision exists only where CMake found MuJoCo
# (apt-get install libmujoco-dev) and Google Benchmark (libbenchmark-dev).
# About 2 minutes on 2 CPUs.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"

source "$root/papers/build_target.sh" study_mechanism_work_precision bench/multibody
out="$here/out"
rm -rf "$out"
mkdir -p "$out"
"$program" "$out/runs.csv" "${1:-2}" | tee "$out/log.txt"
{
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
} >"$out/machine.txt"
/usr/bin/python3 "$here/analyze.py" "$out" "$here"
