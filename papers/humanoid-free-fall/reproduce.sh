#!/usr/bin/env bash
# Regenerates papers/humanoid-free-fall/: MuJoCo's humanoid (Debian
# libmujoco-samples) thrown turning in free fall, contacts, limits, armature
# and actuators left out in both engines (--ignore all), started from the
# keyframe "spin" of humanoid_spin.xml.in.
#  1. lieflow study out/humanoid_spin.xml --with-mujoco over 1 s: error of the
#     torso's orientation against run time, lieflow's integrators and
#     MuJoCo's Euler, RK4 and implicit on the same model (out/study/).
#  2. study_model_drift (bench/multibody/model_drift.cpp) over 100 s: the
#     drift of the angular momentum about the centre of mass and of energy +
#     dissipated work, each engine measuring its own run (out/drift/), and
#     the same thrown turning without gravity (out/drift-zero-g/).
# Then analyze.py writes work_precision.png, drift.png, drift_cost.png,
# results.md and the table between the GENERATED markers of README.md.
#
#   bash papers/humanoid-free-fall/reproduce.sh [T_DRIFT]
#
# T_DRIFT: the long runs' end time in seconds (default 100). Build dir:
# ${LIEFLOW_BUILD_DIR:-build}; needs libmujoco-dev, libmujoco-samples and
# libbenchmark-dev (bench/). About 4 minutes on 2 CPUs.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"

humanoid=/usr/share/mujoco/model/humanoid/humanoid.xml
if [[ ! -f "$humanoid" ]]; then
  echo "reproduce: $humanoid missing (apt-get install libmujoco-samples)" >&2
  exit 1
fi
source "$root/papers/find_lieflow.sh"
source "$root/papers/build_target.sh" study_model_drift bench/multibody
out="$here/out"
rm -rf "$out"
mkdir -p "$out/study" "$out/drift"
# MuJoCo resolves <include> relative to the including file.
relative=$(/usr/bin/python3 -c "import os, sys; print(os.path.relpath(sys.argv[1], sys.argv[2]))" "$humanoid" "$out")
sed "s|@HUMANOID@|$relative|" "$here/humanoid_spin.xml.in" >"$out/humanoid_spin.xml"
model="$out/humanoid_spin.xml"
# The same without gravity (MuJoCo merges a second <option>): no fall, so no
# positions tens of kilometres from the origin.
sed 's|<keyframe>|<option gravity="0 0 0"/>\n  <keyframe>|' "$model" >"$out/humanoid_spin_zero_g.xml"

"$lieflow" study "$model" --ignore all --keyframe spin --with-mujoco --integrators rkmk4,cf4,cg3,lgvi,genalpha \
  --dt 0.004,0.002,0.001,0.0005 --t-end 1 --out "$out/study" --no-plots 2>"$out/study_log.txt" >"$out/study_table.md"

t_drift=${1:-100}
"$program" "$model" "$out/drift" "$t_drift" 400 all spin \
  lgvi:0.004 lgvi:0.002 lgvi:0.001 rkmk4:0.004 rkmk4:0.002 genalpha:0.004 genalpha:0.002 \
  mujoco-euler:0.001 mujoco-euler:0.0005 mujoco-euler:0.00025 mujoco-rk4:0.002 mujoco-rk4:0.001 mujoco-rk4:0.0005 \
  mujoco-implicit:0.002 mujoco-implicit:0.001 mujoco-implicit:0.0005 2>"$out/drift_log.txt"
mkdir -p "$out/drift-zero-g"
"$program" "$out/humanoid_spin_zero_g.xml" "$out/drift-zero-g" "$t_drift" 400 all spin \
  lgvi:0.002 lgvi:0.001 rkmk4:0.004 rkmk4:0.002 mujoco-euler:0.00025 mujoco-rk4:0.001 mujoco-rk4:0.0005 \
  mujoco-implicit:0.0005 2>>"$out/drift_log.txt"
{
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) CPUs"
  echo "long runs: $t_drift s"
} >"$out/machine.txt"
/usr/bin/python3 "$here/analyze.py" "$out" "$here"
