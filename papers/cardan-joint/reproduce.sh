#!/usr/bin/env bash
# Regenerates papers/cardan-joint/: the speed ratio of a Cardan (Hooke)
# joint, ω₂ = ω₁ cos β / (1 − sin²β cos²θ₁), against lieflow simulations of
# the built-in scene `cardan-shaft` with the output shaft bent by
# β = 15°, 30°, 45°, 60°, 75°; analyze.py then writes the table into README.md
# and the figure speed_ratio.png.
#
#   bash papers/cardan-joint/reproduce.sh
#
# The binary is ${LIEFLOW_BUILD_DIR:-build}/app/lieflow relative to the
# repository root; when it is missing it is built with scripts/run.sh.
# The scenes (copies of scenes/cardan-shaft.json with β changed) and the raw
# output (trajectory CSVs, --stats JSON) go to out/ here (not committed).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"
source "$root/papers/find_lieflow.sh"

betas=(15 30 45 60 75)
steps=(0.001 0.0005)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
out="$here/out"
rm -rf "$out"
mkdir -p "$out/scenes"

# 1. One scene per β: scenes/cardan-shaft.json with the output shaft (and its
#    bearing axis) turned by β about z, its initial speed ω₁/cos β (the
#    formula at θ₁ = 0; the initial projection would correct it anyway) and
#    t_end = 0.7 s, so that the input (10 rad/s) turns 7 rad > 2π.
/usr/bin/python3 - "$root/scenes/cardan-shaft.json" "$out/scenes" "${betas[@]}" <<'PY'
import json, math, sys
base = json.load(open(sys.argv[1]))
for deg in sys.argv[3:]:
    beta = math.radians(float(deg))
    scene = json.loads(json.dumps(base))
    scene["name"] = f"cardan-shaft-beta{deg}"
    scene["description"] = f"{base['description']} (output shaft bent by {deg} degrees)"
    omega1 = next(j for j in scene["joints"] if j["name"] == "input-bearing")["prescribed"]["rate"]
    out = next(b for b in scene["bodies"] if b["name"] == "output")
    out["orientation"] = [math.cos(beta / 2), 0, 0, math.sin(beta / 2)]
    out["angular_velocity"] = [omega1 / math.cos(beta), 0, 0]
    bearing = next(j for j in scene["joints"] if j["name"] == "output-bearing")
    bearing["axis_main"] = [math.cos(beta), math.sin(beta), 0]
    scene["t_end"] = 0.7
    json.dump(scene, open(f"{sys.argv[2]}/beta{deg}.json", "w"), indent=2)
PY

# 2. lieflow simulate, rkmk4 (projected) at h = 1e-3 (the scene's step) and
#    5e-4, every step written.
for beta in "${betas[@]}"; do
  for h in "${steps[@]}"; do
    name="beta${beta}_h${h}"
    echo "reproduce: lieflow simulate beta = $beta deg, h = $h" >&2
    "$lieflow" simulate "$out/scenes/beta$beta.json" --integrator rkmk4 --dt "$h" \
      --out "$out/$name.csv" --stats >"$out/$name.json" 2>"$out/$name.err" ||
      { echo "reproduce: lieflow simulate failed for $name:" >&2; cat "$out/$name.err" >&2; exit 1; }
  done
done

{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "machine: $(nproc) cores, $(uname -srm), load average (1, 5, 15 min) $load_start at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  echo "git: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
} >"$out/machine.txt"

/usr/bin/python3 "$here/analyze.py" "$out" "$here"
