#!/usr/bin/env bash
# Regenerates papers/genalpha-index2/: the convergence of the Lie-group
# generalized-α step with joints in positions, velocities and multipliers,
# stabilized index 2 (the default) against index 3, at ρ∞ = 1 and 0.8
# (bench/multibody/genalpha_convergence.cpp), then analyze.py writes
# results.md, convergence.png and the table between the GENERATED markers of
# README.md.
#
#   bash papers/genalpha-index2/reproduce.sh
#
# Build dir: ${LIEFLOW_BUILD_DIR:-build} relative to the repository root
# (configured by scripts/run.sh when it has no CMakeCache.txt); the target
# study_genalpha_convergence is (re)built there with ${LIEFLOW_JOBS:-2} jobs.
# It needs bench/ (Google Benchmark installed: apt-get install libbenchmark-dev).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"

build_dir=${LIEFLOW_BUILD_DIR:-build}
study="$build_dir/bench/multibody/study_genalpha_convergence"
if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  echo "reproduce: $build_dir not configured, configuring it (scripts/run.sh)" >&2
  bash scripts/run.sh --help >/dev/null
fi
cmake --build "$build_dir" -j"${LIEFLOW_JOBS:-2}" --target study_genalpha_convergence >&2
if [[ ! -x "$study" ]]; then
  echo "reproduce: $study was not built (bench/ needs Google Benchmark: apt-get install libbenchmark-dev)" >&2
  exit 1
fi
out="$here/out"
rm -rf "$out"
mkdir -p "$out"
"$study" >"$out/convergence.csv"
echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')" >"$out/machine.txt"
/usr/bin/python3 "$here/analyze.py" "$out" "$here"
