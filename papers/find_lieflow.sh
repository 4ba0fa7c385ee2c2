# Sourced by the papers' reproduce.sh scripts, with $root set to the
# repository root: sets $lieflow to ${LIEFLOW_BUILD_DIR:-build}/app/lieflow,
# building it with scripts/run.sh when it is missing.
build_dir=${LIEFLOW_BUILD_DIR:-build}
lieflow="$build_dir/app/lieflow"
if [[ ! -x "$lieflow" ]]; then
  echo "reproduce: $lieflow missing, building it (scripts/run.sh)" >&2
  bash scripts/run.sh --help >/dev/null
fi
