#!/usr/bin/env bash
# Regenerates papers/heavy-top/: convergence of every integrator on the heavy
# top of Brüls, Cardona & Arnold (2012), built-in scene `heavy-top`, against a
# converged reference, then analyze.py writes results.md and the PNG figures.
#
#   bash papers/heavy-top/reproduce.sh
#
# The binary is ${LIEFLOW_BUILD_DIR:-build}/app/lieflow relative to the
# repository root; when it is missing it is built with scripts/run.sh.
# Raw output (study CSVs, trajectory CSVs, --stats JSON) goes to out/ here.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"
source "$root/papers/find_lieflow.sh"

load_start=$(cut -d' ' -f1-3 /proc/loadavg)
out="$here/out"
rm -rf "$out"
mkdir -p "$out"

# 1. Fixed-step integrators, h = 8e-3 / 2^k, k = 0..10, t_end = 2 s: error at
#    t = 2 s against the study's reference (a converged rkmk45 run at rtol
#    1e-13, atol 1e-15, whose error the study estimates from a run at rtol
#    1e-11), run time = median of repeated runs.
fixed=rkmk-euler,rkmk-heun,rkmk3,rkmk4,cg3,cf4,lgvi,splitting,genalpha
steps=0.008,0.004,0.002,0.001,0.0005,0.00025,0.000125,6.25e-05,3.125e-05,1.5625e-05,7.8125e-06
echo "reproduce: lieflow study heavy-top (9 integrators x 11 steps)" >&2
"$lieflow" study heavy-top --integrators "$fixed" --dt "$steps" --out "$out/study" --no-plots \
  >"$out/study_table.md" 2>"$out/study.log" || { cat "$out/study.log" >&2; exit 1; }

# Lie-Euler reaches its asymptotic regime only below h ~ 2e-5: two more steps.
"$lieflow" study heavy-top --integrators rkmk-euler --dt 3.90625e-06,1.953125e-06 --out "$out/study-euler" \
  --no-plots >/dev/null 2>>"$out/study.log" || { cat "$out/study.log" >&2; exit 1; }

# 2. rkmk45 is adaptive: its dt is only the output interval, so it is studied
#    over its tolerance instead (atol = rtol/100), one study per tolerance on a
#    copy of scenes/heavy-top.json whose integrator block carries the options.
echo "reproduce: rkmk45 tolerance sweep" >&2
for rtol in 1e-05 1e-06 1e-07 1e-08 1e-09 1e-10 1e-11 1e-12; do
  scene="$out/heavy-top-rkmk45-rtol$rtol.json"
  /usr/bin/python3 - "$root/scenes/heavy-top.json" "$scene" "$rtol" <<'EOF'
import json, sys
scene = json.load(open(sys.argv[1]))
rtol = float(sys.argv[3])
scene["integrator"] = {"name": "rkmk45", "dt": scene["t_end"], "rtol": rtol, "atol": rtol / 100}
json.dump(scene, open(sys.argv[2], "w"), indent=2)
EOF
  "$lieflow" study "$scene" --integrators rkmk45 --dt 2 --out "$out/rkmk45-rtol$rtol" --no-plots \
    >/dev/null 2>>"$out/study.log" || { cat "$out/study.log" >&2; exit 1; }
done

# 3. Trajectories at h = 1e-3 (the scene's step) for the conservation figure:
#    energy, vertical angular momentum L_z, spin about the symmetry axis.
echo "reproduce: trajectories at h = 1e-3" >&2
mkdir -p "$out/h0.001"
for name in ${fixed//,/ } rkmk45; do
  set +e
  "$lieflow" simulate heavy-top --integrator "$name" --dt 0.001 --every 4 \
    --out "$out/h0.001/$name.csv" --stats >"$out/h0.001/$name.json" 2>"$out/h0.001/$name.err"
  rc=$?
  set -e
  echo "$rc" >"$out/h0.001/$name.rc"
  if [[ $rc -ne 0 && $rc -ne 1 ]]; then
    echo "reproduce: lieflow simulate failed with exit status $rc for $name:" >&2
    cat "$out/h0.001/$name.err" >&2
    exit 1
  fi
done

{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "machine: $(nproc) cores, $(uname -srm), load average (1, 5, 15 min) $load_start at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
} >"$out/machine.txt"

/usr/bin/python3 "$here/analyze.py" "$out" "$here"
