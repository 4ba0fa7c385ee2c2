#!/usr/bin/env bash
# Regenerates papers/chain-scaling/: time per step of a chain of N rods on
# revolute joints against N (10, 30, 100, 300, 1000), lieflow's projected
# RKMK4 step and its constrained acceleration solve alone, beside MuJoCo's RK4
# and Euler steps of the same chain when bench_multibody was built with MuJoCo
# (bench/multibody/), then analyze.py writes results.md, chain_scaling.png and
# the tables between the GENERATED markers of README.md.
#
#   bash papers/chain-scaling/reproduce.sh
#
# Build dir: ${LIEFLOW_BUILD_DIR:-build} relative to the repository root
# (configured by scripts/run.sh when it has no CMakeCache.txt); the target
# bench_multibody is (re)built there with ${LIEFLOW_JOBS:-2} jobs, a no-op when
# it is up to date. Google Benchmark: every family/N
# ${LIEFLOW_BENCH_REPETITIONS:-3} times (the tables take the median). Raw
# output (benchmark JSON, console with the SUMMARY lines, load samples) goes to
# out/ here.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"

source "$root/papers/build_target.sh" bench_multibody bench/multibody
bench=$program

out="$here/out"
rm -rf "$out"
mkdir -p "$out"
load_start=$(cut -d' ' -f1-3 /proc/loadavg)

# The 1-minute load average every 5 s during the run (the machine is shared).
(
  while true; do
    echo "$(date +%s) $(cut -d' ' -f1-3 /proc/loadavg)"
    sleep 5
  done
) >"$out/loadavg.txt" &
sampler=$!
trap 'kill "$sampler" 2>/dev/null || true' EXIT

echo "reproduce: $bench (repetitions ${LIEFLOW_BENCH_REPETITIONS:-3}; about 2 min)" >&2
"$bench" --benchmark_filter='BM_ChainCachedSolve|BM_ChainStep_' \
  --benchmark_repetitions="${LIEFLOW_BENCH_REPETITIONS:-3}" \
  --benchmark_out="$out/bench.json" --benchmark_out_format=json \
  --benchmark_color=false >"$out/bench_console.txt" 2>"$out/bench.err" ||
  { cat "$out/bench.err" >&2; exit 1; }
kill "$sampler" 2>/dev/null || true
wait "$sampler" 2>/dev/null || true
trap - EXIT
grep '^SUMMARY' "$out/bench_console.txt" >&2 || true

cache="$build_dir/CMakeCache.txt"
build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$cache")
flags=$(sed -n "s/^CMAKE_CXX_FLAGS_${build_type^^}:[A-Z]*=//p" "$cache")
compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$cache")
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "machine: $(nproc) cores ($(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)), $(uname -srm), load average (1, 5, 15 min) $load_start at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  echo "build: $build_dir, ${build_type:-no build type} ${flags}, $("${compiler:-c++}" --version 2>/dev/null | head -1)"
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
} >"$out/machine.txt"

/usr/bin/python3 "$here/analyze.py" "$out" "$here"
