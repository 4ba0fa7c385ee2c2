#!/usr/bin/env bash
# Regenerates papers/robots-work-precision/: error against run time on public
# robot descriptions (bench/models/robots: UR5, Panda fixed; Solo12, ANYmal,
# Talos, Talos full floating and turning; MuJoCo's humanoid turning), every
# integrator family with lieflow's defaults (the default formulation) beside
# MuJoCo's RK4, Euler and implicit integrators on the same file, each model
# one `lieflow study MODEL --ignore all --with-mujoco` run; then analyze.py
# writes results.md, work_precision.png and the table between the GENERATED
# markers of README.md.
#
#   bash papers/robots-work-precision/reproduce.sh [T]
#
# T: end time in seconds (default 1). Needs a build with MuJoCo
# (libmujoco-dev; libmujoco-samples for the MJCF models) and URDF reading
# (liburdfdom-dev). About fifteen minutes on 2 CPUs. A URDF with links whose
# inertias break the triangle inequality (ANYmal, Talos) is read by both
# engines from a copy in out/models/ with those links balanced by MuJoCo's
# rule (out/models/NAME.log lists them). The floating robots start
# turning (--spin 0.5,1,2 rad/s, MuJoCo from the same start): falling limp
# from rest, a floating tree does not move relative to itself (uniform
# gravity), so every integrator's error would be round-off (README).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"
source "$root/papers/find_lieflow.sh"
t_end=${1:-1}
out="$here/out"
rm -rf "$out"
mkdir -p "$out"
robots="$root/bench/models/robots"
samples=/usr/share/mujoco/model
# name|file|flags|joint rates of a keyframe "swing" added in a copy (MJCF)|
# steps beside $steps (the Panda's chaotic fall: lieflow's error at 6.25e-5
# is 1e-9, and MuJoCo's RK4 reaches 1e-9 only in a longer run; slider_crank:
# MuJoCo's Euler reaches 1e-3 in 86 us, and radau5's runs that short need
# steps longer than 32 ms)
spin="--spin 0.5,1,2"
models=(
  "ur5|$robots/ur5.urdf||"
  "panda|$robots/panda.urdf|||3.125e-5,1.5625e-5"
  "solo12|$robots/solo12.urdf|--floating-base $spin|"
  "anymal|$robots/anymal.urdf|--floating-base $spin|"
  "talos|$robots/talos.urdf|--floating-base $spin|"
  "talos_full|$robots/talos_full.urdf|--floating-base $spin|"
  "humanoid|$samples/humanoid/humanoid.xml|$spin|"
  "slider_crank|$samples/slider_crank/slider_crank.xml|--keyframe swing|3,-5,4|6.25e-2,4e-2"
  "arm26|$samples/tendon_arm/arm26.xml|--keyframe swing|3,-5"
)
integrators=rkmk4,rkmk6,cf4,lgvi,genalpha,radau5
# From steps where MuJoCo's errors lie near 1e-3 to where they reach 1e-9.
steps=3.2e-2,1.6e-2,8e-3,4e-3,2e-3,1e-3,5e-4,2.5e-4,1.25e-4,6.25e-5
for entry in "${models[@]}"; do
  IFS='|' read -r name file flags rates more <<<"$entry"
  if [[ ! -f "$file" ]]; then
    echo "reproduce: $file absent, $name left out" >&2
    continue
  fi
  dir="$out/${name%% *}"
  if [[ -n "$rates" ]]; then
    # With their actuators left out, slider_crank's and arm26's hinges
    # (axes along gravity) do not move: both engines start them swinging
    # from a keyframe added in a copy (bench/models/robots/with_keyframe.py).
    mkdir -p "$out/models"
    /usr/bin/python3 "$robots/with_keyframe.py" "$file" "$out/models/$name.xml" swing "$rates"
    file="$out/models/$name.xml"
  fi
  if [[ "$file" == *.urdf ]]; then
    # Links whose inertias break A + B >= C are balanced by MuJoCo's own rule
    # in a copy both engines read (else MuJoCo would balance them and lieflow
    # not: different bodies; bench/models/robots/balance_inertia.py).
    mkdir -p "$out/models"
    /usr/bin/python3 "$robots/balance_inertia.py" "$file" "$out/models/$name.urdf" 2>"$out/models/$name.log"
    if grep -q "^balance_inertia: 0 link" "$out/models/$name.log"; then
      rm -f "$out/models/$name.urdf" "$out/models/$name.log"
    else
      file="$out/models/$name.urdf"
    fi
  fi
  # shellcheck disable=SC2086
  "$lieflow" study "$file" --ignore all $flags --with-mujoco --integrators "$integrators" \
    --dt "$steps${more:+,$more}" --t-end "$t_end" --min-time 0.1 --no-plots --out "$dir" >"$dir.log" 2>&1 ||
    { echo "reproduce: the study of $name failed (see $dir.log)" >&2; continue; }
  rm -f "$dir/drift.csv"  # the drift series: not what this paper reads
  # The formulation each lieflow integrator ran in (the default's choice).
  for i in ${integrators//,/ }; do
    # shellcheck disable=SC2086
    f=$("$lieflow" simulate "$file" --ignore all $flags --integrator "$i" --dt 1e-3 --t-end 1e-3 --stats --quiet 2>/dev/null |
      sed -n 's/.*"formulation":"\([a-z]*\)".*/\1/p')
    echo "$name,$i,$f" >>"$out/formulations.csv"
  done
  echo "$name|$dir" >>"$out/models.txt"
done
{
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
} >"$out/machine.txt"
/usr/bin/python3 "$here/analyze.py" "$out" "$here"
