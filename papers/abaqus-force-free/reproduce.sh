#!/usr/bin/env bash
# Regenerates papers/abaqus-force-free/: runs the built `lieflow` command on the
# built-in scene `abaqus-force-free` (I = 1, I3 = 2, A = 0.25, n = 2 pi, 2 s)
# with every integrator at h = 0.01 (the benchmark) and at larger steps, then
# analyze.py turns the CSVs into results.md and the PNG figures.
#
#   bash papers/abaqus-force-free/reproduce.sh
#
# The binary is ${LIEFLOW_BUILD_DIR:-build}/app/lieflow relative to the
# repository root; when it is missing it is built with scripts/run.sh.
# Raw output (trajectory CSVs, --stats JSON, study.csv) goes to out/ here.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"
source "$root/papers/find_lieflow.sh"

integrators=(rkmk-euler rkmk-heun rkmk3 rkmk4 rkmk45 cg3 cf4 lgvi splitting genalpha exact)
steps=(0.01 0.02 0.05 0.1 0.2 0.25)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
out="$here/out"
rm -rf "$out"
mkdir -p "$out"

for h in "${steps[@]}"; do
  mkdir -p "$out/h$h"
  for name in "${integrators[@]}"; do
    options=()
    if [[ $name == genalpha ]]; then options=(--options rho_inf=1); fi
    # Exit status 1 = the run failed (non-convergence, blow-up): kept, it is a result.
    set +e
    "$lieflow" simulate abaqus-force-free --integrator "$name" --dt "$h" "${options[@]}" \
      --out "$out/h$h/$name.csv" --stats >"$out/h$h/$name.json" 2>"$out/h$h/$name.err"
    rc=$?
    set -e
    echo "$rc" >"$out/h$h/$name.rc"
    if [[ $rc -ne 0 && $rc -ne 1 ]]; then
      echo "reproduce: lieflow simulate failed with exit status $rc for $name at h = $h:" >&2
      cat "$out/h$h/$name.err" >&2
      exit 1
    fi
  done
done

# Run time per step (median of repeated runs) and the error at t = 2 s
# against the exact flow, from the work-precision study at the same steps.
# (The scene's own integrator is genalpha with rho_inf = 1, so the study runs
# genalpha with rho_inf = 1.)
mkdir -p "$out/study"
IFS=,
"$lieflow" study abaqus-force-free --dt "${steps[*]}" --out "$out/study" --no-plots \
  >"$out/study/table.md" 2>"$out/study.log" || { cat "$out/study.log" >&2; exit 1; }
unset IFS

{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "machine: $(nproc) cores, $(uname -srm), load average (1, 5, 15 min) $load_start at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
} >"$out/machine.txt"

/usr/bin/python3 "$here/analyze.py" "$out" "$here"
