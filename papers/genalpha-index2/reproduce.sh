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

source "$root/papers/build_target.sh" study_genalpha_convergence bench/multibody
study=$program
out="$here/out"
rm -rf "$out"
mkdir -p "$out"
"$study" >"$out/convergence.csv"
echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')" >"$out/machine.txt"
/usr/bin/python3 "$here/analyze.py" "$out" "$here"
