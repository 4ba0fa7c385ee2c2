#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/CMakeLists.txt) with clang-14 in
# build-fuzz/ and runs each for SECONDS (default 30) from a seed corpus made
# of scenes/*.json, fuzz/corpus/, the test models and MuJoCo's sample models
# and, when build/app/lieflow exists, a recording it writes. Prints executions, corpus size and crashes per target;
# exits 1 when a target found a crash (its input is saved in build-fuzz/ as
# fuzz_T-crash-...). The targets run side by side, one per core.
# Usage: bash fuzz/run.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-30}
out="$root/build-fuzz"

packages=(clang-14 libclang-rt-14-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=(); [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ ! -f "$out/CMakeCache.txt" ]; then
  cmake -S "$root/fuzz" -B "$out" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
cmake --build "$out" -- -j"$(nproc)"

# The targets this build has (fuzz_mjcf and fuzz_urdf need MuJoCo and
# urdfdom; fuzz/CMakeLists.txt leaves them out without).
targets=(scene recording run cli)
for t in mjcf urdf; do [ -x "$out/fuzz_$t" ] && targets+=("$t"); done

# Seed corpora (copied, so that the committed seeds stay as they are).
for t in "${targets[@]}"; do
  rm -rf "$out/corpus-$t"; mkdir -p "$out/corpus-$t"
  cp "$root"/fuzz/corpus/$t/* "$out/corpus-$t/" 2>/dev/null || true
done
cp "$root"/scenes/*.json "$out/corpus-scene/"
# Real models: the test models, and MuJoCo's sample models where installed
# (libmujoco-samples; those under 64 KiB, the fuzzer's input length).
if [ -d "$out/corpus-mjcf" ]; then
  cp "$root"/tests/data/models/*.xml "$out/corpus-mjcf/"
  find /usr/share/mujoco/model -name '*.xml' -size -64k -exec cp {} "$out/corpus-mjcf/" \; 2>/dev/null || true
fi
[ -d "$out/corpus-urdf" ] && cp "$root"/tests/data/models/*.urdf "$out/corpus-urdf/"
if [ -x "$root/build/app/lieflow" ]; then
  "$root/build/app/lieflow" simulate hinge-pair --every 100 --t-end 0.5 --out "$out/corpus-recording/hinge-pair.csv" >/dev/null
  "$root/build/app/lieflow" simulate spring-hinge --every 100 --t-end 0.5 --out "$out/corpus-recording/spring-hinge.csv" >/dev/null
  "$root/build/app/lieflow" simulate double-pendulum --every 50 --t-end 0.5 --out "$out/corpus-run/double-pendulum.csv" >/dev/null
fi

# One target for SECONDS; its exit status in fuzz_T.rc. The targets run as
# many at a time as the machine has cores (each fuzzer uses one).
run_target() {
  local t=$1 log="$out/fuzz_$1.log" extra=()
  case $t in
    mjcf|urdf) extra=(-dict="$root/fuzz/$t.dict" -max_len=65536) ;;
    *) extra=(-max_len=8192) ;;
  esac
  set +e
  (cd "$out" && ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions="$root/fuzz/lsan.supp" \
      "./fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$out/fuzz_$t-" "${extra[@]}" "corpus-$t" >"$log" 2>&1)
  echo $? >"$out/fuzz_$t.rc"
  set -e
}

jobs_at_once=$(nproc)
running=0
for t in "${targets[@]}"; do
  run_target "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs_at_once" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait

status=0
for t in "${targets[@]}"; do
  log="$out/fuzz_$t.log"
  rc=$(cat "$out/fuzz_$t.rc")
  execs=$(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}' || true)
  corpus=$(find "$out/corpus-$t" -type f | wc -l)
  crashes=$(find "$out" -maxdepth 1 \( -name "fuzz_$t-crash-*" -o -name "fuzz_$t-timeout-*" -o -name "fuzz_$t-leak-*" \
                                     -o -name "fuzz_$t-oom-*" \) | wc -l)
  echo "fuzz_$t: ${execs:-?} executions in ${seconds} s, corpus ${corpus} inputs, exit ${rc}"
  if [ "$rc" -ne 0 ]; then
    status=1
    echo "fuzz_$t FOUND A PROBLEM ($crashes saved inputs); the log's end:"
    tail -30 "$log"
  fi
done
exit $status
