#!/usr/bin/env bash
# Regenerates papers/hinge-axis-identification/: Monte Carlo sweeps of
# `lieflow calibrate hinge|universal` on recordings written by
# `lieflow simulate hinge-pair|universal-pair --noise-...` (Seel, Schauer &
# Raisch 2012; Olsson et al. 2020), and of `lieflow calibrate spring` on
# `lieflow simulate spring-hinge --noise-angle ...`; analyze.py then writes
# the tables into README.md and the figures axis_vs_noise.png,
# axis_vs_samples.png, spring_vs_noise.png, spring_vs_length.png; then
# bench/calibration/study_hinge_estimators (the likelihood estimator against
# the Cramér–Rao bound, accelerometers, biases) and analyze_estimators.py
# (its table and estimators.png).
#
#   bash papers/hinge-axis-identification/reproduce.sh
#
# The binary is ${LIEFLOW_BUILD_DIR:-build}/app/lieflow relative to the
# repository root; when it is missing it is built with scripts/run.sh.
# LIEFLOW_SEEDS (default 50) trials per point, LIEFLOW_JOBS (default 2)
# parallel jobs. Raw output goes to out/ here (not committed):
#   out/scenes/            the scene files simulated (their axes are the truth)
#   out/cases.tsv          one line per sweep point (what analyze.py tabulates)
#   out/runs/CASE/sK.json  the calibrate JSON of trial K (sK.rc its exit status,
#                          sK.err its stderr); the recording of trial 1 is kept
#   out/clean/             noise-free recordings (motion statistics, the decay)
#   out/lieflow            the copy of the binary that ran
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"
source "$root/papers/find_lieflow.sh"

seeds=${LIEFLOW_SEEDS:-50}
jobs=${LIEFLOW_JOBS:-2}
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
start_seconds=$(date +%s)
out="$here/out"
rm -rf "$out"
mkdir -p "$out/scenes" "$out/runs" "$out/clean"
# The ~6000 invocations use a copy of the binary: a rebuild of the build
# directory during the run can neither fail a trial nor mix two binaries.
binary_note="$lieflow, modified $(date -u -r "$lieflow" '+%Y-%m-%d %H:%M UTC')"
cp "$lieflow" "$out/lieflow"
lieflow="$out/lieflow"
cp scenes/hinge-pair.json scenes/universal-pair.json scenes/spring-hinge.json "$out/scenes/"
hinge="$out/scenes/hinge-pair.json"
universal="$out/scenes/universal-pair.json"
spring="$out/scenes/spring-hinge.json"

# The scenes' step is h = 1e-3 (rkmk4). With every E-th step written and
# t_end = (N - 1) E h the rows t = 0, E h, ..., t_end are N samples at
# 1/(E h) Hz; E = 10 gives 100 Hz.
t_end() { awk -v n="$1" -v e="${2:-10}" 'BEGIN { printf "%.3f", (n - 1) * e / 1000 }'; }

# One trial: simulate with noise, calibrate, keep the JSON and the exit status.
# Arguments: CASE SEED SCENE EVERY T_END KIND USE START NOISE-OPTIONS...
# USE is the --use value ("-": none); for KIND spring it is instead the
# comma-separated calibrate options after `--scene SCENE` ("-": none), e.g.
# --fit-rest-angle,--stiffness-start,4. START "-" or "X,Y,Z/X,Y,Z": the fit is
# repeated with that extra start (the true axes) into sK.truth.json, which
# tells a local minimum (the start reaches a lower cost) from the data's own.
run_one() {
  local case=$1 seed=$2 scene=$3 every=$4 tend=$5 kind=$6 use=$7 start=$8
  shift 8
  local dir="$out/runs/$case" rc opts=() more=()
  if [[ $kind == spring ]]; then
    opts+=(--scene "$scene")
    [[ $use == - ]] || { IFS=, read -ra more <<<"$use"; opts+=("${more[@]}"); }
  else
    [[ $use == - ]] || opts+=(--use "$use")
  fi
  local rec="$dir/s$seed.csv"
  if ! "$lieflow" simulate "$scene" --dt 0.001 --every "$every" --t-end "$tend" --seed "$seed" "$@" \
      --out "$rec" 2>"$dir/s$seed.sim.err"; then
    echo "reproduce: lieflow simulate failed for $case seed $seed:" >&2
    cat "$dir/s$seed.sim.err" >&2
    return 255  # stops xargs
  fi
  rc=0
  "$lieflow" calibrate "$kind" "$rec" "${opts[@]}" >"$dir/s$seed.json" 2>"$dir/s$seed.err" || rc=$?
  echo "$rc" >"$dir/s$seed.rc"
  if [[ $rc -ne 0 && $rc -ne 1 ]]; then  # 1: refused or not converged (tabulated)
    echo "reproduce: lieflow calibrate exited $rc for $case seed $seed:" >&2
    cat "$dir/s$seed.err" >&2
    return 255
  fi
  if [[ $start != - ]]; then
    rc=0
    "$lieflow" calibrate "$kind" "$rec" "${opts[@]}" --start-main "${start%/*}" --start-secondary "${start#*/}" \
      >"$dir/s$seed.truth.json" 2>"$dir/s$seed.truth.err" || rc=$?
    echo "$rc" >"$dir/s$seed.truth.rc"
  fi
  (( seed % 1000 == 1 )) || rm -f "$rec"
}
export -f run_one
export lieflow out

# add_case CASE STUDY KIND USE N GYRO_SIGMA QUAT_SIGMA SCENE [EVERY [START [ANGLE_SIGMA]]]:
# one sweep point (N samples, every EVERY-th step written, default 10; START
# as in run_one; ANGLE_SIGMA the joint-angle noise in rad, default 0) with
# $seeds trials; its seeds are CASE_INDEX*1000 + 1 ... CASE_INDEX*1000 + $seeds,
# so the noise of different points is independent. With seeds_of=I set in
# the call (seeds_of=I add_case ...), the case reuses the seeds (the same
# recordings) of case number I instead, for paired comparisons.
case_index=0
: >"$out/cases.tsv"
: >"$out/jobs.txt"
add_case() {
  local case=$1 study=$2 kind=$3 use=$4 n=$5 gyro=$6 quat=$7 scene=$8 every=${9:-10} start=${10:--}
  local angle=${11:-0} noise=() k
  case_index=$((case_index + 1))
  local base=${seeds_of:-$case_index}
  mkdir -p "$out/runs/$case"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$case" "$study" "$kind" "$use" "$n" "$gyro" "$quat" \
    "$(basename "$scene")" "$every" "$angle" >>"$out/cases.tsv"
  [[ $gyro == 0 ]] || noise+=(--noise-gyro "$gyro")
  [[ $quat == 0 ]] || noise+=(--noise-quat "$quat")
  [[ $angle == 0 ]] || noise+=(--noise-angle "$angle")
  for ((k = 1; k <= seeds; k++)); do
    echo "$case $((base * 1000 + k)) $scene $every $(t_end "$n" "$every") $kind $use $start" \
      "${noise[*]}" >>"$out/jobs.txt"
  done
}

deg() { awk -v d="$1" 'BEGIN { printf "%.9f", d * atan2(0, -1) / 180 }'; }

# ---- Hinge and universal axes --------------------------------------------
# The true hinge axes (main/secondary frames, as analyze.py reads them from
# the scene): the extra start of the gyroscope fits' second run.
truth=$(PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); from analyze import true_axes
t = true_axes(sys.argv[2]); print("/".join(",".join(repr(float(x)) for x in t[k]) for k in ("a1", "a2")))' \
  "$here" "$hinge")
# 1. gyroscopes only, 1000 samples, sigma = 0.001 ... 0.3 rad/s
for sigma in 0.001 0.003 0.01 0.03 0.1 0.3; do
  add_case "gyro_sigma$sigma" gyro_sigma hinge gyroscopes 1000 "$sigma" 0 "$hinge" 10 "$truth"
done
# 2. gyroscopes only, sigma = 0.01 rad/s, N = 50 ... 5000 samples at 100 Hz
#    (0.49 ... 49.99 s), and N = 50 ... 5000 samples of the same 10 s
#    (every 200th ... 2nd step: 5 ... 500 Hz)
for n in 50 100 200 500 1000 2000 5000; do
  add_case "gyro_n$n" gyro_n hinge gyroscopes "$n" 0.01 0 "$hinge" 10 "$truth"
done
for n in 50 100 200 500 1000 2000 5000; do
  add_case "gyro_rate_n$n" gyro_rate hinge gyroscopes "$n" 0.01 0 "$hinge" $((10000 / n)) "$truth"
done
# 3. orientations only (quaternion noise 0.1 ... 3 deg), 1000 samples; and
#    both kinds together at 0.01 rad/s + 0.5 deg
for d in 0.1 0.3 0.5 1 3; do
  add_case "quat_sigma${d}deg" quat_sigma hinge orientations 1000 0 "$(deg "$d")" "$hinge"
done
add_case "both_0.01_0.5deg" both hinge both 1000 0.01 "$(deg 0.5)" "$hinge"
# 4. universal joint, 1000 samples: orientations 0.5 deg, and gyroscopes
#    0.01 rad/s + orientations 0.5 deg
add_case "universal_quat0.5deg" universal universal orientations 1000 0 "$(deg 0.5)" "$universal"
add_case "universal_both" universal universal both 1000 0.01 "$(deg 0.5)" "$universal"

# Noise-free 50 s recordings of both scenes (rates, joint angles).
"$lieflow" simulate "$hinge" --dt 0.001 --every 10 --t-end "$(t_end 5000)" --out "$out/clean/hinge-pair.csv"
"$lieflow" simulate "$universal" --dt 0.001 --every 10 --t-end "$(t_end 1000)" --out "$out/clean/universal-pair.csv"

# ---- Spring and dashpot (calibrate spring) -----------------------------------
# spring-hinge: free decay, k = 12 N m/rad, c = 0.1 N m s/rad, rest angle
# 0.1 rad (the truth, as analyze.py reads it from the scene); the recorded
# column hinge.phi gets N(0, sigma^2) rad. 100 Hz, T = (N - 1)/100 s.
# 1. angle noise 0.001 ... 0.1 rad, T = 10 s (1001 samples); and 0.1 rad over
#    the first 5 s (501 samples)
for sigma in 0.001 0.003 0.01 0.03 0.1; do
  add_case "spring_sigma$sigma" spring_sigma spring - 1001 0 0 "$spring" 10 - "$sigma"
  [[ $sigma != 0.01 ]] || spring_ref=$case_index
done
add_case "spring_sigma0.1_t5" spring_sigma spring - 501 0 0 "$spring" 10 - 0.1
# 2. sigma = 0.01 rad, T = 2 ... 40 s
for t in 2 5 10 20 40; do
  add_case "spring_t$t" spring_t spring - $((t * 100 + 1)) 0 0 "$spring" 10 - 0.01
done
# 3. the rest angle fitted too, and 4. starts a factor 3 from the truth
#    (k0 in {4, 36}, c0 in {0.0333, 0.3}, rest angle -0.5 rad, i.e. 0.6 rad
#    off), multiple and single shooting: on the recordings of the
#    sigma = 0.01 rad, T = 10 s point of 1 (the same seeds), so that every
#    fit of one recording can be compared with its default-start fits.
seeds_of=$spring_ref add_case spring_rest spring_rest spring --fit-rest-angle 1001 0 0 "$spring" 10 - 0.01
for shooting in multiple single; do
  for k0 in 4 36; do
    for c0 in 0.0333 0.3; do
      seeds_of=$spring_ref add_case "spring_start_${shooting}_k${k0}_c${c0}" spring_start spring \
        "--fit-rest-angle,--rest-angle-start,-0.5,--stiffness-start,$k0,--damping-start,$c0,--shooting,$shooting" \
        1001 0 0 "$spring" 10 - 0.01
    done
  done
done
# Noise-free 40 s recording of the decay (amplitude, the figure).
"$lieflow" simulate "$spring" --dt 0.001 --every 10 --t-end 40 --out "$out/clean/spring-hinge.csv"

# ---- (further blocks add their cases here) ----

echo "reproduce: $(wc -l <"$out/jobs.txt") trials ($case_index cases x $seeds seeds), $jobs in parallel" >&2
# Each job line: CASE SEED SCENE EVERY T_END KIND USE START NOISE...; trial 1
# of every case (SEED = CASE_INDEX*1000 + 1) keeps its recording.
xargs -P "$jobs" -L 1 bash -c 'run_one "$@"' _ <"$out/jobs.txt"

end_seconds=$(date +%s)
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "machine: $(nproc) cores, $(uname -srm), load average (1, 5, 15 min) $load_start at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "binary: $binary_note"
  echo "trials: $(wc -l <"$out/jobs.txt") in $((end_seconds - start_seconds)) s with $jobs parallel jobs"
} >"$out/machine.txt"

/usr/bin/python3 "$here/analyze.py" "$out" "$here"

# Estimators, the Cramér–Rao bound, accelerometers and biases: a study program
# over the library (bench/calibration/study_hinge_estimators.cpp; LIEFLOW_SEEDS
# trials per point, about 40 s for 50).
source "$root/papers/build_target.sh" study_hinge_estimators bench/calibration
estimators_start=$(date +%s)
"$program" "$out/estimators.tsv" "$seeds"
echo "estimators: $(($(date +%s) - estimators_start)) s for $seeds trials per point ($program)" >>"$out/machine.txt"
/usr/bin/python3 "$here/analyze_estimators.py" "$out/estimators.tsv" "$out/machine.txt" "$here"
