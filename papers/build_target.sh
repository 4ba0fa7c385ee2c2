# Sourced by the papers' reproduce.sh scripts that run a bench/ program, with
# $root set to the repository root and $1 the CMake target: configures
# ${LIEFLOW_BUILD_DIR:-build} with scripts/run.sh when it has no
# CMakeCache.txt, (re)builds the target there with ${LIEFLOW_JOBS:-2} jobs (a
# no-op when it is up to date), and sets $build_dir and $program to the
# built program's path; exits 1 saying why when it was not built (bench/ needs
# Google Benchmark: apt-get install libbenchmark-dev).
#   source "$root/papers/build_target.sh" bench_multibody bench/multibody
target=$1
target_dir=$2
build_dir=${LIEFLOW_BUILD_DIR:-build}
program="$build_dir/$target_dir/$target"
if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  echo "reproduce: $build_dir not configured, configuring it (scripts/run.sh)" >&2
  bash scripts/run.sh --help >/dev/null
fi
echo "reproduce: cmake --build $build_dir --target $target" >&2
cmake --build "$build_dir" -j"${LIEFLOW_JOBS:-2}" --target "$target" >&2
if [[ ! -x "$program" ]]; then
  echo "reproduce: $program was not built (bench/ needs Google Benchmark: apt-get install libbenchmark-dev)" >&2
  exit 1
fi
